"""A rotating inertia with viscous bearing loss."""

from __future__ import annotations

from ..component import Component
from ..spec import Param


class Inertia(Component):
    """Rigid body of inertia ``J``: both flanges turn with it.

    Equation: ``J·dω/dt = Σ torques − d·ω`` (bearing loss ``d·ω`` to the housing).
    """

    kind = "inertia"
    title = "rotating inertia"
    flanges = ("a", "b")
    optional_flanges = ("a", "b")
    joined = (("a", "b"),)
    params = (
        Param("J", "kg·m²", "inertia", low=0.0, strict=True),
        Param("omega0", "rad/s", "initial speed", default=0.0),
        Param("bearing_damping", "N·m·s/rad", "viscous bearing loss to the housing",
              default=0.0, low=0.0),
    )

    def inertias(self):
        return {"a": self.J}

    def initial_speeds(self):
        return {"a": self.omega0}

    def options(self):
        return (self.bearing_damping == 0.0,)

    def emit(self, e):
        if self.bearing_damping == 0.0:
            return
        d, w = e.par("bearing_damping"), e.w("a")
        e.torque("a", f"-{d} * {w}")
        e.dtorque("a", e.kw("a"), f"-{d}")
        e.power("damp", f"{d} * {w} * {w}")
        e.dpower("damp", e.kw("a"), f"2.0 * {d} * {w}")
