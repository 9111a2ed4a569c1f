"""The launch metrics and warnings of a driveline run (a :class:`~clutchsim.core.Result`).

This module reads results only; running a scenario is :mod:`clutchsim.scenario.run`
(the dependency runs one way: scenario -> driveline/network -> core)."""

from __future__ import annotations

import math
from dataclasses import replace
from types import MappingProxyType

import numpy as np

from ..analysis import launch_quality as lq
from ..core import Outcome, Result
from .chain import ENERGY_STATES

__all__ = ["LOCK_HOLD", "LOCK_SLIP", "STEP_RATE_LIMIT", "energy_balance", "launch_metrics",
           "launch_warnings", "with_weighted_acceleration"]

#: steps per simulated second above which a run is warned about [1/s].  The shipped
#: scenarios take 7 to 1,900 (measured: default launch 365-530, ten launches 440-610, tip-out
#: 1,850); a model-(6) clutch ringing after lock-up takes 17,000-37,000.
STEP_RATE_LIMIT = 5000.0
#: ... but never below this many steps in all (a very short run may be dense) [-]
STEP_COUNT_FLOOR = 10_000
#: slip below which an engaged clutch counts as held [rad/s], and for how long [s] at least
LOCK_SLIP = 1.0
LOCK_HOLD = 0.05


def with_weighted_acceleration(res: Result) -> Result:
    """``res`` with the signal ``a_weighted`` [m/s²]: ``a_vehicle`` weighted with ISO
    2631-1 W_d (:func:`clutchsim.analysis.launch_quality.weighted_acceleration_mps2`);
    ``res`` itself when it has no ``a_vehicle``."""
    if "a_vehicle" not in res.signals or "a_weighted" in res.signals:
        return res
    aw = lq.weighted_acceleration_mps2(res.t, res["a_vehicle"])
    aw.flags.writeable = False
    return replace(res, data=MappingProxyType({**res.data, "a_weighted": aw}),
                   units=MappingProxyType({**res.units, "a_weighted": "m/s²"}))


def energy_balance(res: Result) -> dict:
    """Energy account of a run [J] and ``energy_balance_rel``.

    ``residual = W_in - ΔE_kinetic - ΔE_spring - W_friction - W_damping - W_road - E_grade
    - W_sync``; ``energy_balance_rel = |residual| / max(|W_in|, E_kinetic(0), max E_kinetic)``.
    """
    out = {k: float(res[k][-1]) for k in ENERGY_STATES}
    ke, pe = res["E_kinetic"], res["E_spring"]
    d_ke, d_pe = float(ke[-1] - ke[0]), float(pe[-1] - pe[0])
    resid = out["W_in"] - d_ke - d_pe - sum(out[k] for k in ENERGY_STATES[1:])
    scale = max(abs(out["W_in"]), float(np.max(ke)), 1e-30)
    out.update(delta_E_kinetic=d_ke, delta_E_spring=d_pe, residual=resid,
               energy_balance_rel=abs(resid) / scale)
    return out


def _held(res: Result, clutch: str) -> bool:
    """Did the engaged clutch hold (lock) at some time: a switching model's locked flag, or
    a slip below LOCK_SLIP for LOCK_HOLD seconds on end while engaged."""
    lk = f"{clutch}.locked"
    if lk in res.signals and np.any((res[lk] > 0.5) & (res.t > res.t[0])):
        return True
    w_name, c_name = f"w_slip_{clutch}", f"capacity_{clutch}"
    if w_name not in res.signals or c_name not in res.signals or res.t.size < 2:
        return False
    cap = res[c_name]
    ok = (cap > 0.5 * np.max(cap)) & (np.abs(res[w_name]) < LOCK_SLIP) if np.max(cap) > 0 \
        else np.zeros(res.t.size, dtype=bool)
    if not np.any(ok):
        return False
    # the start of the run of held samples each sample belongs to
    starts = ok & np.concatenate(([True], ~ok[:-1]))
    first = np.maximum.accumulate(np.where(starts, np.arange(ok.size), 0))
    return bool(np.any(ok & (res.t - res.t[first] >= LOCK_HOLD)))


def _ringing(res: Result, clutch: str) -> str | None:
    """The warning for a contact whose torque swings, after it first held, further both
    ways than its capacity (half its peak-to-peak above the capacity), else None."""
    t_name, w_name, c_name = f"T_friction_{clutch}", f"w_slip_{clutch}", f"capacity_{clutch}"
    if not all(n in res.signals for n in (t_name, w_name, c_name)):
        return None
    cap, torque, w = res[c_name], res[t_name], np.abs(res[w_name])
    if np.max(cap) <= 0:
        return None
    engaged = cap > 0.5 * np.max(cap)
    touch = np.flatnonzero(engaged & (w < LOCK_SLIP))
    if not touch.size:
        return None
    win = engaged & (np.arange(res.t.size) >= touch[0])
    amplitude = 0.5 * (np.max(torque[win]) - np.min(torque[win]))
    capacity = float(np.max(cap[win]))
    if amplitude <= capacity:
        return None
    t0 = float(res.t[touch[0]])
    crossings = [t for t in _event_times(res, clutch) if t >= t0]
    rate = ""
    if len(crossings) > 2 and crossings[-1] > crossings[0]:
        hz = 0.5 * (len(crossings) - 1) / (crossings[-1] - crossings[0])
        rate = (f" with {len(crossings):,} events of {clutch!r} (~{hz:.0f} Hz if each is a "
                "slip reversal)")
    return (f"contact {clutch!r} rings after lock-up: from t = {t0:.3g} s its torque swings "
            f"±{amplitude:.0f} N·m{rate}, above its capacity {capacity:.0f} N·m, so it keeps "
            f"slipping back and forth instead of holding (largest slip afterwards "
            f"{float(np.max(w[win])):.3g} rad/s). Cause: a locked contact with too little "
            "damping (model (6): its only damping is k_v) or a friction torque that falls "
            "with slip speed (judder: k_din < 1 with a small omega0). Remedy: raise the "
            "contact damping (k_v), use a friction curve that does not fall steeply "
            "(k_din nearer 1, a larger omega0), add driveline damping, or compare with "
            "coulomb-robust; do not trust this run's torques and lock-up time")


def launch_warnings(res: Result, clutch: str = "clutch", *, expect_lockup: bool = True,
                    friction: bool = True) -> list[str]:
    """Reasons not to trust a run that completed, each with its cause and remedy.

    * the clutch never held although ``expect_lockup`` (see
      :func:`clutchsim.scenario.run.expects_lockup`);
    * (``friction``: the element is a friction clutch) its contact rings after lock-up
      with a torque amplitude above its capacity;
    * the step count is far above what the scenarios need: more than
      :data:`STEP_RATE_LIMIT` steps per simulated second (and more than
      :data:`STEP_COUNT_FLOOR` steps).

    A failed run gets none (its outcome and message say what went wrong).
    """
    if res.status == "failed" or res.t.size < 2:
        return []
    out = []
    span = float(res.t[-1] - res.t[0])
    if expect_lockup and f"w_slip_{clutch}" in res.signals and not _held(res, clutch):
        w = np.abs(res[f"w_slip_{clutch}"])
        cap = res[f"capacity_{clutch}"]
        engaged = cap > 0.5 * np.max(cap) if np.max(cap) > 0 else np.zeros(w.size, bool)
        if not np.any(engaged):
            cause = ("it never engaged (its capacity stayed below half its largest value "
                     f"{float(np.max(cap)):.0f} N·m)")
        elif np.min(w[engaged]) >= LOCK_SLIP:
            cause = (f"its slip never fell below {LOCK_SLIP:g} rad/s while engaged (smallest "
                     f"{float(np.min(w[engaged])):.3g} rad/s): the capacity "
                     f"{float(np.max(cap)):.0f} N·m is too low for the torque it must carry, "
                     "or the run is too short")
        else:
            cause = (f"its slip came near zero but never stayed below {LOCK_SLIP:g} rad/s for "
                     f"{LOCK_HOLD:g} s (largest slip after engagement "
                     f"{float(np.max(w[engaged])):.3g} rad/s): stick-slip or judder")
        out.append(f"clutch {clutch!r} never locked up although the scenario expects it: "
                   f"{cause}. Remedy: raise the clamp load or capacity, lengthen t_end, use "
                   "a friction model or parameters that can hold (see the ringing warning if "
                   "there is one), or, if the clutch is meant to slip, set [scenario] "
                   "expect_lockup = false")
    if friction:
        ring = _ringing(res, clutch)
        if ring:
            out.append(ring)
    steps = res.stats.steps
    if span > 0 and steps > STEP_COUNT_FLOOR and steps / span > STEP_RATE_LIMIT:
        n_ev = res.stats.events
        out.append(f"the run took {steps:,} steps, {steps / span:,.0f} per simulated second, "
                   f"far above the {STEP_RATE_LIMIT:,.0f}/s that clutchsim's scenarios need "
                   f"(usually 300-2,000/s), with {n_ev:,} events. Cause: something fast was "
                   "excited or keeps switching (an undamped contact mode, stick-slip, "
                   "chattering events); the result may be right but is costly and suspect. "
                   "Remedy: look at the slip speeds and the events; add contact damping or "
                   "choose a smoother friction model or reset policy; if the fast dynamics is "
                   "real, this warning can be ignored")
    return out


def _source(res: Result, event) -> str:
    """The component ``event`` belongs to (the network plant declares each event's source,
    with the components' kinds in ``metadata["kinds"]``)."""
    return event.source


def _ended_by(res: Result) -> str:
    """The component whose event ended the run ("" when none did)."""
    return res.event_source if res.event else ""


def _kind(res: Result, component: str) -> str:
    return res.metadata.get("kinds", {}).get(component, "")


def _event_times(res: Result, component: str) -> list[float]:
    """Times [s] of the located events of ``component``."""
    return [e.t for e in res.events if _source(res, e) == component]


def _lockup_time(res: Result, clutch: str) -> float | None:
    """:func:`clutchsim.analysis.launch_quality.lockup_time_s` of ``clutch`` in ``res``:
    engaged = capacity above half its largest value; the clutch's located events."""
    name, c_name = f"w_slip_{clutch}", f"capacity_{clutch}"
    if name not in res.signals or c_name not in res.signals:
        return None
    cap = res[c_name]
    if res.t.size < 2 or np.max(cap) <= 0:
        return None
    lk = f"{clutch}.locked"
    events = _event_times(res, clutch)
    return lq.lockup_time_s(res.t, res[name], cap > 0.5 * np.max(cap),
                            locked=res[lk] if lk in res.signals else None,
                            event_times_s=events, lock_slip_radps=LOCK_SLIP)


def _quality(res: Result, clutch: str, lining: tuple | None) -> dict:
    """The launch-quality metrics of docs/launch-quality.md (None where a signal is
    missing or a value is not finite)."""
    keys = ("engagement_start_s", "lockup_time_s", "vdv_mps175", "aw_rms_mps2",
            "jerk_peak_mps3", "jerk_rms_mps3", "lockup_shock_mps2",
            "friction_energy_density_J_mm2", "friction_power_density_peak_W_mm2",
            "engine_dip_rpm", "engine_flare_rpm")
    m: dict = dict.fromkeys(keys)
    if res.t.size < 2:
        return m
    t, sig = res.t, res.signals
    t_lock = m["lockup_time_s"] = _lockup_time(res, clutch)
    t_eng = None
    if f"T_friction_{clutch}" in sig:
        t_eng = m["engagement_start_s"] = lq.engagement_start_s(t, res[f"T_friction_{clutch}"])
    if "a_vehicle" in sig:
        a = res["a_vehicle"]
        aw = res["a_weighted"] if "a_weighted" in sig else lq.weighted_acceleration_mps2(t, a)
        m["vdv_mps175"] = lq.vdv_mps175(t, aw)
        m["aw_rms_mps2"] = lq.rms(t, aw)
        tu, jerk = lq.jerk_mps3(t, a)
        m["jerk_peak_mps3"] = float(np.max(np.abs(jerk)))
        m["jerk_rms_mps3"] = lq.rms(tu, jerk)
        m["lockup_shock_mps2"] = lq.lockup_shock_mps2(t, a, t_lock)
    if lining is not None and f"P_{clutch}" in sig:
        e, p = lq.friction_densities(t, res[f"P_{clutch}"], lq.lining_area_mm2(*lining))
        m["friction_energy_density_J_mm2"], m["friction_power_density_peak_W_mm2"] = e, p
    if "omega_engine" in sig:
        m["engine_dip_rpm"], m["engine_flare_rpm"] = lq.engine_dip_flare_rpm(
            t, res["omega_engine"], t_eng, t_lock)
    # a run that failed on a non-finite state has no value to report (JSON has no NaN)
    return {k: v if v is None or math.isfinite(v) else None for k, v in m.items()}


def launch_metrics(res: Result, clutch: str = "clutch", *, lining: tuple | None = None
                   ) -> dict:
    """Per-run metrics: completed, outcome, message, warnings (``res.warnings``: see
    :func:`launch_warnings`), the launch-quality metrics of docs/launch-quality.md
    (engagement_start_s, lockup_time_s, vdv_mps175, aw_rms_mps2, jerk_peak_mps3,
    jerk_rms_mps3, lockup_shock_mps2, friction_energy_density_J_mm2,
    friction_power_density_peak_W_mm2, engine_dip_rpm, engine_flare_rpm; the densities
    need ``lining`` = ``(r_inner [m], r_outer [m], faces [-])``), slip_energy_J,
    peak_lining_temp_C, engine_speed_min_rpm, engine_stalled, energy_balance_rel,
    judder_amplitude_Nm (:func:`clutchsim.analysis.judder_amplitude`), steps, rhs_evals,
    events, min_step_s, wall_s."""
    m: dict = {"completed": res.status == "completed", "outcome": str(res.outcome),
               "message": res.message, "warnings": list(res.warnings)}
    if res.outcome == Outcome.CHATTER and _ended_by(res) == clutch:
        m["message"] = ("stopped by chatter detection at clutch lock-up (the slip speed of "
                        f"{clutch!r} reached zero and the switching law re-fired): "
                        + res.message)
    m.update(_quality(res, clutch, lining))
    p_name = f"P_{clutch}"
    m["slip_energy_J"] = float(np.trapezoid(np.abs(res[p_name]), res.t)) \
        if p_name in res.signals and len(res.t) > 1 else None
    temps = [s for s in res.signals if s.startswith("theta_")]
    m["peak_lining_temp_C"] = float(np.max(res[temps[0]])) if temps else None
    eng = [s for s in res.signals if s == "omega_engine"]
    m["engine_speed_min_rpm"] = float(np.min(res[eng[0]]) * 30 / math.pi) if eng else None
    m["engine_stalled"] = (res.outcome == Outcome.EVENT_FAILED
                           and _kind(res, _ended_by(res)) == "engine")
    if m["engine_stalled"]:
        m["outcome"] = "stalled"
    m["energy_balance_rel"] = energy_balance(res)["energy_balance_rel"]
    from ..analysis.judder import judder_amplitude
    m["judder_amplitude_Nm"] = judder_amplitude(res, clutch)
    st = res.stats
    m.update(steps=st.steps, rhs_evals=st.rhs_evals, events=st.events,
             min_step_s=st.min_step_s, wall_s=st.wall_s)
    return m
