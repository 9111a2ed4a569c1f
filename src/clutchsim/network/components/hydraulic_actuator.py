"""A hydraulic clutch actuator: dead time, rate-limited first-order pressure lag, piston.

The pressure command ``p_c`` [Pa] (a signal: an input or a controller's command) passes a
dead time ``T_d``, approximated by a cascade of ``stages`` equal first-order lags
``(1 + s·T_d/n)⁻ⁿ`` (states ``<name>.delay<k>``; no undershoot and no negative pressure, unlike
a Padé approximant, whose step response starts the wrong way).  Its phase at ``ω`` is
``−n·atan(ω·T_d/n)`` against the exact ``−ω·T_d`` (at ``ω·T_d = 1`` and ``n = 4``: −0.98 rad
instead of −1 rad) and its gain ``(1 + (ω·T_d/n)²)^(−n/2)`` (0.88 there).  The delayed
command ``p_d`` drives the line pressure ``p`` through a first-order lag with a rate limit,
``dp/dt = clip((p_d − p)/τ, −r, r)``.  The piston turns it into the clamp force
``F = A·max(p − p_th, 0)`` (``p_th``: the pressure that balances the return spring; as
Simscape's Disc Friction Clutch, engagement begins above the threshold pressure).

Signals: ``<name>.pressure`` [Pa] and ``<name>.force`` [N] (from its states: they break
loops of signals).  The actuator does no work on a mechanical flange, so it is not part of
the mechanical energy balance.
"""

from __future__ import annotations

from ..spec import Param
from ._laws import Actuator, emit_rate_limited_lag


class HydraulicActuator(Actuator):
    """Dead time + rate-limited lag + piston (see the module docstring)."""

    kind = "hydraulic_actuator"
    title = "hydraulic actuator: dead time, rate-limited pressure lag, piston force"
    params = (
        Param("time_constant", "s", "first-order lag of the line pressure", low=0.0,
              strict=True),
        Param("dead_time", "s", "dead time of the pressure command (a cascade of lags)",
              default=0.0, low=0.0),
        Param("stages", "-", "first-order lags that approximate the dead time (an integer)",
              default=4.0, low=1.0, high=32.0),
        Param("rate_limit", "Pa/s", "largest rate of change of the pressure (0: none)",
              default=0.0, low=0.0),
        Param("area", "m²", "piston area", low=0.0, strict=True),
        Param("threshold_pressure", "Pa", "pressure that balances the return spring: no "
              "force below it", default=0.0, low=0.0),
        Param("p0", "Pa", "pressure (and delayed command) at the start", default=0.0,
              low=0.0),
    )

    def __init__(self, name, command: str, **values):
        super().__init__(name, command, "the pressure command [Pa]", **values)
        if self.stages != int(self.stages):
            raise ValueError(f"{self.label}: stages = {self.stages:g} must be an integer")

    @property
    def n_stages(self) -> int:
        return int(self.stages) if self.dead_time > 0.0 else 0

    def options(self):
        return (self.command, self.n_stages, self.rate_limit > 0.0)

    def input_units(self):
        return {self.command: "Pa"}

    def signals(self):
        return {"pressure": "Pa", "force": "N"}

    def pack(self):
        d = dict(self.values)
        d["t_stage"] = self.dead_time / self.n_stages if self.n_stages else 0.0
        return d

    def state_layout(self):
        out = [(f"d{k}", f"{self.name}.delay{k + 1}", "Pa") for k in range(self.n_stages)]
        return [*out, ("p", f"{self.name}.pressure_state", "Pa")]

    def initial_state(self, ctx):
        return [self.p0] * (self.n_stages + 1)

    def emit_signals(self, e):
        P = e.par
        p = e.x("p")
        e.signal("pressure", p)
        e.dsignal("pressure", e.kx("p"), "1.0")
        e.signal("force", f"{P('area')} * max({p} - {P('threshold_pressure')}, 0.0)")
        e.dsignal("force", e.kx("p"),
                  f"{P('area')} if {p} > {P('threshold_pressure')} else 0.0")

    def emit(self, e):
        P = e.par
        pc = e.u(self.command)
        prev, prev_parts = pc, e.du(self.command)
        for k in range(self.n_stages):
            d = e.x(f"d{k}")
            e.deriv(f"d{k}", f"({prev} - {d}) / {P('t_stage')}")
            e.dderiv(f"d{k}", e.kx(f"d{k}"), f"-1.0 / {P('t_stage')}")
            for key, dd in prev_parts:
                e.dderiv(f"d{k}", key, f"({dd}) / {P('t_stage')}")
            prev, prev_parts = d, [(e.kx(f"d{k}"), "1.0")]
        p = e.x("p")
        rate = e.let("rate", f"({prev} - {p}) / {P('time_constant')}")
        emit_rate_limited_lag(e, "p", rate, P("rate_limit") if self.rate_limit > 0.0 else None,
                              f"(1.0 / {P('time_constant')})", prev_parts)
