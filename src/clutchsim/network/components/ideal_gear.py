"""An ideal rigid gear, optionally with a support flange (a housing that may move)."""

from __future__ import annotations

from ..component import Component
from ..spec import Param


class IdealGear(Component):
    """``ω_a − ω_s = ratio·(ω_b − ω_s)`` (Modelica ``IdealGear`` with ``useSupport``).

    The support flange is grounded when left unconnected.  Output ``T_<name>`` [N·m]: the
    torque the gear passes on at flange b (the part at b receives ``−T``: the coupling
    convention of the spring-damper and the clutch).
    """

    kind = "ideal_gear"
    title = "ideal gear with optional support"
    flanges = ("a", "b", "support")
    grounded = ("support",)
    params = (Param("ratio", "-", "speed ratio ω_a/ω_b relative to the support",
                    low=-1e3, high=1e3, nonzero=True),)

    def constraints(self):
        r = self.ratio
        return [{"a": 1.0, "b": -r, "support": r - 1.0}]

    def emit(self, e):
        e.output(f"T_{self.name}", "N·m", f"-{e.constraint_torque(0, 'b')}")
