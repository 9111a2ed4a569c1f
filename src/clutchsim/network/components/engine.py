"""A combustion engine: full-load curve, drag, PI idle governor, stall."""

from __future__ import annotations

import numpy as np

from ..component import Component
from ..spec import Param, check_table, table_entry

#: highest idle (and stall) speed accepted [rad/s]: 2,000 rpm, above any engine's idle
#: (passenger cars 600-900 rpm, trucks 500-700 rpm); 800 typed as rad/s (7,640 rpm) is
#: an rpm value in the wrong unit
IDLE_SPEED_MAX = 2000.0 * np.pi / 30.0
#: band above the full-load table's last speed over which the rev limiter takes the
#: full-load torque to 0, as a share of that speed [-]
REV_LIMIT_BAND = 0.05


class Engine(Component):
    """Torque source on ``flange`` (reaction on ``support``, grounded when unconnected).

    ``T = x·T_max(ω) − (drag0·tanh(ω/1 rad/s) + drag1·ω)`` with ``x = clip(throttle +
    gov, 0, 1)``; the PI idle governor ``gov = clip(kp·e + ki·I, 0, 1 − throttle)``, ``e =
    idle_speed − ω``, ``dI/dt = e + (gov − raw)/(ki·0.1 s)`` (back-calculation anti-windup:
    the right-hand side stays continuous).  Below ``stall_speed`` the run fails (event
    ``engine stalled``).  ``T_max`` is the full-load table (speeds [rad/s], torques [N·m]),
    held constant below its first speed, clipped at 0; above its last speed the rev
    limiter cuts the fuel: ``T_max`` falls linearly to 0 over :data:`REV_LIMIT_BAND` (5 %)
    of that speed and stays 0 (an engine control unit cuts injection at its rated speed
    limit; a ramp, not a step, keeps the right-hand side continuous for the integrator).
    The run gets a warning when the engine overspeeds
    (:func:`clutchsim.analysis.launch_metrics.launch_warnings`).  It produces the signal ``<name>.torque`` [N·m]
    (``T``: a launch controller's feed-forward); the throttle may be another component's
    signal (a driver model).  Outputs: ``T_engine`` [N·m] and ``T_full_load`` [N·m], the
    torque it would give at its present speed at full throttle (``T_max(ω)`` minus the
    drag: its full-load curve along the run; ``T_engine <= T_full_load``, equal at full
    load).
    """

    kind = "engine"
    title = "combustion engine with idle governor"
    flanges = ("flange", "support")
    grounded = ("support",)
    params = (
        Param("drag0", "N·m", "friction torque", default=0.0, low=0.0, high=1e6),
        Param("drag1", "N·m·s/rad", "pumping loss coefficient", default=0.0, low=0.0,
              high=1e4),
        Param("idle_speed", "rad/s", "idle target (0: no governor; 800 rpm = 83.8 rad/s)",
              default=0.0, low=0.0, high=IDLE_SPEED_MAX),
        Param("kp", "1/(rad/s)", "governor proportional gain", default=0.0, low=0.0,
              high=1e6),
        Param("ki", "1/rad", "governor integral gain", default=0.0, low=0.0, high=1e6),
        Param("stall_speed", "rad/s", "stall threshold", default=0.0, low=0.0,
              high=IDLE_SPEED_MAX),
    )

    def __init__(self, name, speeds, torques, throttle="throttle", **values):
        super().__init__(name, **values)
        x, v = check_table(self.label, "full-load curve (speeds, torques)", speeds, torques,
                           min_points=1)
        if self.idle_speed and self.stall_speed >= self.idle_speed:
            raise ValueError(f"{self.label}: stall_speed = {self.stall_speed:g} rad/s must be "
                             f"below idle_speed = {self.idle_speed:g} rad/s")
        self.speeds, self.torques, self.throttle = x, v, str(throttle)

    def described_values(self):
        return {"full_load": table_entry("full-load torque curve at throttle 1 (engine "
                                         "speed → torque)", self.speeds, "rad/s",
                                         self.torques, "N·m")}

    @property
    def governed(self) -> bool:
        return self.idle_speed > 0.0

    def inputs(self):
        return (self.throttle,)

    def input_ranges(self):
        # the throttle is clipped to [0, 1] in the equations: a value outside is a mistake
        return {self.throttle: (0.0, 1.0, "-", "its throttle (0 closed, 1 full load)")}

    def signals(self):
        return {"torque": "N·m"}

    def options(self):
        return (self.governed, len(self.speeds) + 1, self.throttle)

    def pack(self):
        d = dict(self.values)
        # the rev limiter: one more point, torque 0 at REV_LIMIT_BAND above the last speed
        top = self.speeds[-1] + REV_LIMIT_BAND * max(abs(self.speeds[-1]), 1.0)
        d["full_load"] = np.concatenate([self.speeds, [top], self.torques, [0.0]])
        d["t_aw"] = max(self.ki, 1e-12) * 0.1
        return d

    def state_layout(self):
        return [("gi", "engine.governor_integral", "rad")] if self.governed else []

    def initial_state(self, ctx):
        return [0.0] if self.governed else []

    def emit(self, e):
        P = e.par
        w = e.let("wr", f"{e.w('flange')} - {e.w('support')}")
        thr = e.u(self.throttle)
        gov, dgw, dgi = e.tmp("gov"), e.tmp("dgw"), e.tmp("dgi")
        dgt = e.tmp("dgt")
        if self.governed:
            gi = e.x("gi")
            err = e.let("err", f"{P('idle_speed')} - {w}")
            raw = e.let("raw", f"{P('kp')} * {err} + {P('ki')} * {gi}")
            room = e.let("room", f"max(1.0 - {thr}, 0.0)")
            e.line(f"{gov} = 0.0 if {raw} <= 0.0 else ({room} if {raw} >= {room} else {raw})")
            e.line(f"{dgw} = -{P('kp')} if 0.0 < {raw} < {room} else 0.0")
            e.line(f"{dgi} = {P('ki')} if 0.0 < {raw} < {room} else 0.0")
            # d(gov)/d(throttle): -1 while the governor is held at the room left
            e.line(f"{dgt} = -1.0 if ({raw} > 0.0 and {raw} >= {room} and {thr} < 1.0) "
                   "else 0.0")
            e.deriv("gi", f"{err} + ({gov} - {raw}) / {P('t_aw')}")
            for key, d in e.chain(self.throttle, f"{dgt} / {P('t_aw')}"):
                e.dderiv("gi", key, d)
            # d(dI)/dω = -1 + (dgov/dω + kp)/t_aw ; d(dI)/dI = (dgov/dI - ki)/t_aw
            e.dderiv("gi", e.kw("flange"), f"-1.0 + ({dgw} + {P('kp')}) / {P('t_aw')}")
            e.dderiv("gi", e.kw("support"), f"1.0 - ({dgw} + {P('kp')}) / {P('t_aw')}")
            e.dderiv("gi", e.kx("gi"), f"({dgi} - {P('ki')}) / {P('t_aw')}")
        else:
            e.line(f"{gov} = 0.0")
            e.line(f"{dgw} = 0.0")
            e.line(f"{dgi} = 0.0")
            e.line(f"{dgt} = 0.0")
        xr = e.let("xr", f"{thr} + {gov}")
        x = e.let("x", f"min(max({xr}, 0.0), 1.0)")
        dx = e.let("dx", f"1.0 if 0.0 < {xr} < 1.0 else 0.0")
        tf, dtf = e.lookup("full_load", w, "tf")
        e.line(f"if {tf} < 0.0:\n    {tf} = 0.0\n    {dtf} = 0.0")
        th = e.let("th", f"math.tanh({w})")
        fuel = e.let("fuel", f"{x} * {tf}")
        drag = e.let("drag", f"{P('drag0')} * {th} + {P('drag1')} * {w}")
        tq = e.let("tq", f"{fuel} - {drag}")
        e.torque("flange", tq)
        e.torque("support", f"-{tq}")
        dtw = e.let("dtw", f"{dx} * {dgw} * {tf} + {x} * {dtf} - ({P('drag0')} * (1.0 - {th} * "
                           f"{th}) + {P('drag1')})")
        for fl, s in (("flange", ""), ("support", "-")):
            e.dtorque(fl, e.kw("flange"), f"{s}{dtw}")
            e.dtorque(fl, e.kw("support"), f"{'-' if not s else ''}{dtw}")
            if self.governed:
                e.dtorque(fl, e.kx("gi"), f"{s}{dx} * {dgi} * {tf}")
        e.power("in", f"{fuel} * {w}")
        e.power("damp", f"{drag} * {w}")
        dfuel = e.let("dfuel", f"{dx} * {dgw} * {tf} + {x} * {dtf}")
        ddrag = e.let("ddrag", f"{P('drag0')} * (1.0 - {th} * {th}) + {P('drag1')}")
        for fl, s in (("flange", ""), ("support", "-")):
            e.dpower("in", e.kw(fl), f"{s}({dfuel} * {w} + {fuel})")
            e.dpower("damp", e.kw(fl), f"{s}({ddrag} * {w} + {drag})")
        if self.governed:
            e.dpower("in", e.kx("gi"), f"{dx} * {dgi} * {tf} * {w}")
        # partials through a throttle another component produces (a driver model)
        thr_parts = e.chain(self.throttle, f"{dx} * (1.0 + {dgt}) * {tf}")
        for key, d in thr_parts:
            e.dtorque("flange", key, d)
            e.dtorque("support", key, f"-{d}")
            e.dpower("in", key, f"{d} * {w}")
        e.output("T_engine", "N·m", tq)
        # what it could give at this speed at full throttle (the full-load curve, rev
        # limiter and drag included): T_engine <= T_full_load, equal at full load
        e.output("T_full_load", "N·m", f"{tf} - {drag}")
        e.signal("torque", tq)
        for fl, s in (("flange", ""), ("support", "-")):
            e.dsignal("torque", e.kw(fl), f"{s}{dtw}")
        if self.governed:
            e.dsignal("torque", e.kx("gi"), f"{dx} * {dgi} * {tf}")
        for key, d in thr_parts:
            e.dsignal("torque", key, d)
        e.event("engine stalled (speed fell below {stall_speed:g} rad/s = {stall_rpm:.0f} rpm)",
                -1, f"{w} - {P('stall_speed')}", "fail")

    def format_values(self) -> dict:
        return {**self.values, "stall_rpm": self.stall_speed * 30.0 / np.pi}
