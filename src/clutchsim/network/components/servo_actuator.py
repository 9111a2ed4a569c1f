"""An electromechanical clutch actuator: a position servo with a bandwidth and a rate limit.

The position command ``x_c`` [m] (a pedal map or a controller's command: a signal) drives
the actuator position ``x`` (the release-bearing travel, counted in the engaging direction
from the open clutch) through the closed servo loop ``dx/dt = clip(ω_b·(x_c − x), −v, v)``
with ``ω_b = 2π·bandwidth``: a first-order loop whose gain is ``1/√2`` (−3 dB) at the
bandwidth while the rate limit ``v`` is not reached.  Signal ``<name>.position`` [m] (from
its state: it breaks loops of signals).  It does no work on a mechanical flange.
"""

from __future__ import annotations

import math

from ..spec import Param
from ._laws import Actuator, emit_rate_limited_lag


class ServoActuator(Actuator):
    """Position servo (see the module docstring)."""

    kind = "electromechanical_actuator"
    title = "electromechanical actuator: position servo with bandwidth and rate limit"
    params = (
        Param("bandwidth", "Hz", "closed-loop bandwidth of the position servo (−3 dB)",
              low=0.0, strict=True),
        Param("rate_limit", "m/s", "largest actuator speed (0: none)", default=0.0, low=0.0),
        Param("x0", "m", "position at the start", default=0.0),
    )

    def __init__(self, name, command: str, **values):
        super().__init__(name, command, "the position command [m]", **values)

    def options(self):
        return (self.command, self.rate_limit > 0.0)

    def input_units(self):
        return {self.command: "m"}

    def signals(self):
        return {"position": "m"}

    def pack(self):
        d = dict(self.values)
        d["omega_b"] = 2.0 * math.pi * self.bandwidth
        return d

    def state_layout(self):
        return [("x", f"{self.name}.position_state", "m")]

    def initial_state(self, ctx):
        return [self.x0]

    def emit_signals(self, e):
        e.signal("position", e.x("x"))
        e.dsignal("position", e.kx("x"), "1.0")

    def emit(self, e):
        P = e.par
        x = e.x("x")
        rate = e.let("rate", f"{P('omega_b')} * ({e.u(self.command)} - {x})")
        emit_rate_limited_lag(e, "x", rate, P("rate_limit") if self.rate_limit > 0.0 else None,
                              P("omega_b"), e.du(self.command))
