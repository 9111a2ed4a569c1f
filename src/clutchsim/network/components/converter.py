"""A hydrodynamic torque converter: pump, turbine and a stator on a one-way clutch."""

from __future__ import annotations

import numpy as np

from ..component import Component
from ..spec import check_table, table_entry

#: speed [rad/s] below which the faster of pump and turbine counts as standing (no torque)
W_EPS = 1e-9


class TorqueConverter(Component):
    """Pump (flange ``pump``), turbine (``turbine``) and the stator's reaction on
    ``support`` (the housing, grounded when unconnected); speeds relative to the support.

    Drive (``ω_p >= ω_t``), speed ratio ``ν = ω_t/ω_p``: the pump absorbs
    ``T_p = f(ν)·(ω_p/K(ν))²`` and the turbine delivers ``T_t = TR(ν)·T_p``; the stator
    takes ``T_t − T_p`` from the housing.  ``K`` [rad/s/sqrt(N·m)] is the capacity factor
    and ``TR`` the torque ratio, piecewise-linear tables over ``ν`` (held constant outside).
    The stator's one-way clutch is in the tables: it holds the stator (``TR > 1``) below the
    coupling point and frees it there (``TR = 1``).  The table ends at or below the
    coupling point ``ν_c < 1``; above it the torque falls linearly to zero at ``ν = 1``
    (``f = (1 − ν)/(1 − ν_c)``, else ``f = 1``): no torque at equal speeds.
    Coast (``ω_t > ω_p``): the turbine drives the pump as a fluid coupling (the stator
    freewheels, ``TR = 1``) with the same law at ``ν = ω_p/ω_t``.
    The loss ``T_p·ω_p − T_t·ω_t`` is booked in ``W_damping``.  The torques are continuous
    through ``ν = 1`` (zero on both sides), so the switch between drive and coast is no
    event: a locked lock-up clutch holds the speeds equal to round-off, where an event
    function ``ω_p − ω_t`` would fire at every step.  Rotation forwards (the faster side
    at ``ω > 0``).
    """

    kind = "torque_converter"
    title = "hydrodynamic torque converter (capacity factor and torque ratio tables)"
    flanges = ("pump", "turbine", "support")
    grounded = ("support",)

    def __init__(self, name, speed_ratio, K, torque_ratio, **values):
        super().__init__(name, **values)
        o = self.label
        sr, k = check_table(o, "speed_ratio and K", speed_ratio, K)
        _, tr = check_table(o, "speed_ratio and torque_ratio", speed_ratio, torque_ratio)
        if sr[0] < 0.0 or sr[-1] >= 1.0:
            raise ValueError(f"{o}: speed_ratio = {list(sr)} must lie in [0, 1) (the table "
                             "ends at the coupling point; the torque falls to 0 at 1)")
        nu = np.linspace(0.0, 1.0, 2001)
        eta = nu * np.interp(nu, sr, tr)
        if np.max(eta) > 1.0 + 1e-12:
            at = float(nu[np.argmax(eta)])
            raise ValueError(f"{o}: torque_ratio gives an efficiency speed_ratio·torque_ratio "
                             f"= {np.max(eta):.4g} > 1 at speed ratio {at:.4g}: a converter "
                             "cannot deliver more power than it takes (the torque ratio at "
                             "the coupling point must be <= 1)")
        for i, (x, kk, t) in enumerate(zip(sr, k, tr)):
            if kk <= 0.0:
                raise ValueError(f"{o}: K[{i}] = {kk:g} rad/s/sqrt(N·m) at speed ratio {x:g} "
                                 "must be > 0 (a capacity factor)")
            if t <= 0.0:
                raise ValueError(f"{o}: torque_ratio[{i}] = {t:g} at speed ratio {x:g} must "
                                 "be > 0")
        self.speed_ratio, self.K, self.torque_ratio = sr, k, tr

    def options(self):
        return (len(self.speed_ratio),)

    def described_values(self):
        return {"K": table_entry("capacity factor over the speed ratio ω_t/ω_p",
                                 self.speed_ratio, "-", self.K, "rad/s/sqrt(N·m)"),
                "torque_ratio": table_entry("torque ratio over the speed ratio ω_t/ω_p",
                                            self.speed_ratio, "-", self.torque_ratio, "-")}

    def pack(self):
        d = dict(self.values)
        d["K_table"] = np.concatenate([self.speed_ratio, self.K])
        d["TR_table"] = np.concatenate([self.speed_ratio, self.torque_ratio])
        d["nu_c"] = self.speed_ratio[-1]
        return d

    def _capacity(self, e, nu: str, tag: str) -> tuple[str, str]:
        """``g(ν) = f(ν)/K(ν)²`` and ``dg/dν`` (locals suffixed ``tag``)."""
        k, dk = e.lookup("K_table", nu, f"k{tag}")
        nc = e.par("nu_c")
        f = e.let(f"f{tag}", f"1.0 if {nu} <= {nc} else (1.0 - {nu}) / (1.0 - {nc})")
        df = e.let(f"df{tag}", f"0.0 if {nu} <= {nc} else -1.0 / (1.0 - {nc})")
        g = e.let(f"g{tag}", f"{f} / ({k} * {k})")
        dg = e.let(f"dg{tag}", f"{df} / ({k} * {k}) - 2.0 * {f} * {dk} / ({k} * {k} * {k})")
        return g, dg

    def emit(self, e):
        ws = e.w("support")
        wp = e.let("wp", f"{e.w('pump')} - {ws}")
        wt = e.let("wt", f"{e.w('turbine')} - {ws}")
        drive = e.let("drive", f"{wp} >= {wt}")
        hi = e.let("hi", f"{wp} if {drive} else {wt}")
        lo = e.let("lo", f"{wt} if {drive} else {wp}")
        on = e.let("on", f"{hi} > {W_EPS!r}")
        nu = e.let("nu", f"{lo} / {hi} if {on} else 1.0")
        g, dg = self._capacity(e, nu, "")
        tr, dtr = e.lookup("TR_table", nu, "tr")
        e.line(f"if not {drive}:\n    {tr} = 1.0\n    {dtr} = 0.0")
        # magnitude T = hi²·g(ν) and its partials by the fast (hi) and slow (lo) side
        T = e.let("T", f"{hi} * {hi} * {g} if {on} else 0.0")
        dhi = e.let("dhi", f"2.0 * {hi} * {g} - {dg} * {lo} if {on} else 0.0")
        dlo = e.let("dlo", f"{hi} * {dg} if {on} else 0.0")
        # pump absorbs tp, turbine delivers tt (drive: T, TR·T; coast: −T, −T)
        tp = e.let("tp", f"{T} if {drive} else -{T}")
        tt = e.let("tt", f"{tr} * {T} if {drive} else -{T}")
        dtp_p = e.let("dtp_p", f"{dhi} if {drive} else -{dlo}")
        dtp_t = e.let("dtp_t", f"{dlo} if {drive} else -{dhi}")
        # drive: dν/dω_p = −ν/ω_p, dν/dω_t = 1/ω_p
        dtt_p = e.let("dtt_p", f"({tr} * {dhi} - {dtr} * {nu} / {hi} * {T}) if ({drive} and "
                               f"{on}) else (0.0 if {drive} else -{dlo})")
        dtt_t = e.let("dtt_t", f"({tr} * {dlo} + {dtr} / {hi} * {T}) if ({drive} and {on}) "
                               f"else (0.0 if {drive} else -{dhi})")
        e.torque("pump", f"-{tp}")
        e.torque("turbine", tt)
        e.torque("support", f"{tp} - {tt}")
        # partials of the torques on (pump, turbine) by the pump's and the turbine's speed;
        # the support's speed enters with the opposite sign of both relative speeds, and
        # the support's torque is minus the other two
        by = {"pump": (f"-{dtp_p}", dtt_p), "turbine": (f"-{dtp_t}", dtt_t)}
        by["support"] = tuple(f"(-({by['pump'][k]}) - ({by['turbine'][k]}))" for k in (0, 1))
        for fl, (dp, dt) in by.items():
            e.dtorque("pump", e.kw(fl), dp)
            e.dtorque("turbine", e.kw(fl), dt)
            e.dtorque("support", e.kw(fl), f"-({dp}) - ({dt})")
        loss = e.let("loss", f"{tp} * {wp} - {tt} * {wt}")
        e.power("damp", loss)
        lp = e.let("lp", f"{dtp_p} * {wp} + {tp} - {dtt_p} * {wt}")
        lt = e.let("lt", f"{dtp_t} * {wp} - {dtt_t} * {wt} - {tt}")
        e.dpower("damp", e.kw("pump"), lp)
        e.dpower("damp", e.kw("turbine"), lt)
        e.dpower("damp", e.kw("support"), f"-({lp}) - ({lt})")
        e.output(f"T_pump_{self.name}", "N·m", tp)
        e.output(f"T_turbine_{self.name}", "N·m", tt)
        e.output(f"speed_ratio_{self.name}", "-", f"{wt} / {wp} if abs({wp}) > {W_EPS!r} "
                                                  "else 0.0")
