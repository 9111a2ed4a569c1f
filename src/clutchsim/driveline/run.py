"""Run a scenario with one or several friction models and compute the launch metrics."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..core import Outcome, Result, SolverOptions, simulate
from .chain import ENERGY_STATES

__all__ = ["LaunchResult", "energy_balance", "launch_metrics", "run_scenario"]


@dataclass(frozen=True)
class LaunchResult:
    """One run: the core :class:`~clutchsim.core.Result`, the model and its metrics."""

    model: str
    result: Result
    metrics: dict


def run_scenario(scenario=None, model: str | None = None, *, overrides=None,
                 solver: str | None = None, options: SolverOptions | None = None
                 ) -> LaunchResult:
    """Simulate ``scenario`` (default: the packaged launch) with ``model`` on its clutch.

    Parameters
    ----------
    scenario : Scenario, str, Path or None
        A loaded scenario or a path (``None``: the default launch).
    model : str, optional
        Friction model for the element ``scenario.clutch`` (default: the first of
        ``scenario.models``, else the element's own model).
    overrides : sequence of str, optional
        ``key.path=value`` assignments (only with a path or None).
    solver : str, optional
    options : SolverOptions, optional
        Replace the scenario's solver settings.
    """
    from ..scenario import Scenario, load_scenario
    from ..scenario.loader import apply_overrides, parse_scenario
    if not isinstance(scenario, Scenario):
        scenario = load_scenario(scenario, overrides=overrides)
    elif overrides:
        data = apply_overrides(scenario.data, overrides, scenario.file)
        scenario = parse_scenario(data, text=scenario.text, file=scenario.file)
    if model is None and scenario.models:
        model = scenario.models[0]
    chain = scenario.chain(model)
    t0 = 0.0
    u0 = {name: float(np.asarray(sig(t0)).ravel()[0]) for name, sig in scenario.inputs.items()}
    system = chain.build(u0)
    inputs = {n: scenario.inputs[n] for n in system.input_names}
    opts = options if options is not None else scenario.options
    res = simulate(system, (t0, scenario.t_end), inputs, solver=solver or scenario.solver,
                   options=opts)
    name = system.metadata["models"].get(scenario.clutch, model or "")
    return LaunchResult(name, res, launch_metrics(res, clutch=scenario.clutch))


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


def _first_lock(res: Result, clutch: str) -> float | None:
    lk = f"{clutch}.locked"
    if lk in res.signals and np.any(res[lk] > 0.5):   # a switching model: the first lock
        idx = np.flatnonzero((res[lk] > 0.5) & (res.t > 0))
        return float(res.t[idx[0]]) if idx.size else None
    name = f"w_slip_{clutch}"
    if name not in res.signals:
        return None
    w = np.abs(res[name])
    cap = res[f"capacity_{clutch}"]
    if w.size < 2 or np.max(cap) <= 0:
        return None
    engaged = cap > 0.5 * np.max(cap)
    # lock-up: from here on the engaged clutch never slips faster than 1 rad/s again
    slipping = np.flatnonzero(engaged & (w >= 1.0))
    if not engaged[-1] or w[-1] >= 1.0:
        return None
    i = slipping[-1] + 1 if slipping.size else int(np.argmax(engaged))
    return float(res.t[min(i, w.size - 1)])


def launch_metrics(res: Result, clutch: str = "clutch") -> dict:
    """Per-run metrics: completed, message, lockup_time_s, slip_energy_J, peak_lining_temp_C,
    max_jerk_mps3, engine_speed_min_rpm, engine_stalled, energy_balance_rel, steps, rhs_evals,
    events, min_step_s, wall_s."""
    m: dict = {"completed": res.status == "completed", "outcome": str(res.outcome),
               "message": res.message, "warnings": list(res.warnings)}
    if res.outcome == Outcome.CHATTER and res.event.startswith(f"{clutch}:"):
        m["message"] = ("stopped by chatter detection at clutch lock-up (the slip speed of "
                        f"{clutch!r} reached zero and the switching law re-fired): "
                        + res.message)
    m["lockup_time_s"] = _first_lock(res, clutch)
    p_name = f"P_{clutch}"
    m["slip_energy_J"] = float(np.trapezoid(np.abs(res[p_name]), res.t)) \
        if p_name in res.signals and len(res.t) > 1 else None
    temps = [s for s in res.signals if s.startswith("theta_")]
    m["peak_lining_temp_C"] = float(np.max(res[temps[0]])) if temps else None
    if "a_vehicle" in res.signals and len(res.t) > 2:
        a = res["a_vehicle"]
        dt = np.diff(res.t)
        ok = dt > 1e-9
        jerk = np.diff(a)[ok] / dt[ok]
        m["max_jerk_mps3"] = float(np.max(np.abs(jerk))) if jerk.size else 0.0
    else:
        m["max_jerk_mps3"] = None
    eng = [s for s in res.signals if s == "omega_engine"]
    m["engine_speed_min_rpm"] = float(np.min(res[eng[0]]) * 30 / math.pi) if eng else None
    m["engine_stalled"] = (res.outcome == Outcome.EVENT_FAILED
                           and res.event.startswith("engine stalled"))
    if m["engine_stalled"]:
        m["outcome"] = "stalled"
    m["energy_balance_rel"] = energy_balance(res)["energy_balance_rel"]
    st = res.stats
    m.update(steps=st.steps, rhs_evals=st.rhs_evals, events=st.events,
             min_step_s=st.min_step_s, wall_s=st.wall_s)
    return m
