"""A rotating inertia with viscous bearing loss, and its translational twin, a mass."""

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
        Param("omega0", "rad/s", "initial speed", default=0.0, low=-1e4, high=1e4),
        Param("bearing_damping", "N·m·s/rad", "viscous bearing loss to the housing",
              default=0.0, low=0.0, high=1e6),
        Param("phi0", "rad", "initial angle (its state phi_<name> with [outputs] angles)",
              default=0.0),
    )
    #: names of (inertia, initial speed, loss coefficient, initial position) in params
    body_keys = ("J", "omega0", "bearing_damping", "phi0")

    def inertias(self):
        return {"a": self.values[self.body_keys[0]]}

    def initial_speeds(self):
        return {"a": self.values[self.body_keys[1]]}

    def initial_position(self) -> float:
        """Initial angle [rad] (position [m]) of its angle state (``[outputs] angles``)."""
        return self.values[self.body_keys[3]]

    def options(self):
        return (self.values[self.body_keys[2]] == 0.0,)

    def emit(self, e):
        if self.values[self.body_keys[2]] == 0.0:
            return
        d, w = e.par(self.body_keys[2]), e.w("a")
        e.torque("a", f"-{d} * {w}")
        e.dtorque("a", e.kw("a"), f"-{d}")
        e.power("damp", f"{d} * {w} * {w}")
        e.dpower("damp", e.kw("a"), f"2.0 * {d} * {w}")


class Mass(Inertia):
    """Rigid sliding mass ``m``: both flanges move with it (Modelica translational
    ``Mass``).  Equation: ``m·dv/dt = Σ forces − d·v`` (viscous loss ``d·v`` to the
    housing)."""

    kind = "mass"
    title = "sliding mass"
    domain = "translational"
    params = (
        Param("m", "kg", "mass", low=0.0, strict=True),
        Param("v0", "m/s", "initial velocity", default=0.0),
        Param("damping", "N·s/m", "viscous loss to the housing", default=0.0, low=0.0),
        Param("s0", "m", "initial position (its state s_<name> with [outputs] angles)",
              default=0.0),
    )
    body_keys = ("m", "v0", "damping", "s0")
