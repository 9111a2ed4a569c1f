"""A torque from an input signal, acting between a flange and its support."""

from __future__ import annotations

from ..component import Component
from ._laws import signal_arg


class TorqueSource(Component):
    """Torque ``τ = u(t)`` [N·m] on ``flange``, reaction ``−τ`` on ``support`` (grounded
    when unconnected; Modelica ``Torque``)."""

    kind = "torque"
    title = "torque from an input signal"
    flanges = ("flange", "support")
    grounded = ("support",)

    def __init__(self, name, input: str, **values):
        super().__init__(name, **values)
        self.input = signal_arg(self.label, "input", input)

    def options(self):
        return (self.input,)

    def inputs(self):
        return (self.input,)

    def input_units(self):
        return {self.input: "N·m"}

    def emit(self, e):
        u = e.u(self.input)
        e.torque("flange", u)
        e.torque("support", f"-{u}")
        e.power("in", f"{u} * ({e.w('flange')} - {e.w('support')})")
        e.dpower("in", e.kw("flange"), u)
        e.dpower("in", e.kw("support"), f"-{u}")
        for key, d in e.du(self.input):      # a torque another component produces
            e.dtorque("flange", key, d)
            e.dtorque("support", key, f"-{d}")
            e.dpower("in", key, f"({d}) * ({e.w('flange')} - {e.w('support')})")
        e.output(f"{e.domain.effort}_{self.name}", e.domain.effort_unit, u)
