"""Run one chunk of variants (the unit of work of every backend; picklable, module level)."""

from __future__ import annotations

import math
import threading
from dataclasses import replace

__all__ = ["DEFAULT_METRICS", "METRICS", "run_chunk", "run_variant", "variant_plan"]

#: the ``warnings`` column joins a run's warnings with this

#: metric -> (unit, kind) ; kind: float, int or bool
METRICS = {
    "engagement_start_s": ("s", "float"),
    "lockup_time_s": ("s", "float"),
    "vdv_mps175": ("m/s^1.75", "float"),
    "aw_rms_mps2": ("m/s²", "float"),
    "jerk_peak_mps3": ("m/s³", "float"),
    "jerk_rms_mps3": ("m/s³", "float"),
    "lockup_shock_mps2": ("m/s²", "float"),
    "friction_energy_density_J_mm2": ("J/mm²", "float"),
    "friction_power_density_peak_W_mm2": ("W/mm²", "float"),
    "engine_dip_rpm": ("rpm", "float"),
    "engine_flare_rpm": ("rpm", "float"),
    "slip_energy_J": ("J", "float"),
    "peak_lining_temp_C": ("°C", "float"),
    "engine_speed_min_rpm": ("rpm", "float"),
    "engine_stalled": ("-", "bool"),
    "energy_balance_rel": ("-", "float"),
    "judder_amplitude_Nm": ("N·m", "float"),
    "steps": ("-", "int"),
    "rhs_evals": ("-", "int"),
    "events": ("-", "int"),
    "min_step_s": ("s", "float"),
    "wall_s": ("s", "float"),
}
#: everything but ``wall_s``, which differs between runs of the same variant
DEFAULT_METRICS = tuple(m for m in METRICS if m != "wall_s")


def run_variant(job: dict, values: tuple) -> tuple[dict, object]:
    """One run: ``(row, frame)``; ``frame`` is the time series (only with keep_traces).

    The variant is a set of values on the scenario's network, built once per sweep and
    process (:class:`clutchsim.scenario.variants.VariantPlan`); keys that change more
    than a component value rebuild the scenario for the variant.  A run that fails
    (stall, NaN, budget) or whose parameters are invalid becomes a row with its status
    and message; this function does not raise for those.  ``outcome`` is the
    machine-readable reason (the launch metrics' ``outcome``: ``completed``, ``stalled``,
    ``chatter``, ``budget``, ...; ``error`` for invalid parameters) and ``warnings`` the
    run's warnings (a list of str).
    """
    from ..scenario.loader import with_solver_options
    from ..scenario.run import run_system
    row: dict = {"status": "error", "outcome": "error", "message": "", "warnings": []}
    frame = None
    try:
        plan = variant_plan(job)
        changes = tuple(zip(job["keys"], values))
        system = plan.system(changes)
        sc = plan.scenario
        if system is None:
            sc, system = plan.rebuilt(changes)
            sc = with_solver_options(sc, job.get("options"))
        options = sc.options
        cap = job.get("max_output")
        if cap is not None and options.dt_out == 0 and options.max_output > cap:
            options = replace(options, max_output=int(cap))
        lr = run_system(sc, system, job["model"], options=options)
    except (ValueError, ArithmeticError, KeyError, TypeError) as exc:
        row["message"] = f"{type(exc).__name__}: {exc}"
        return row, frame
    row["status"] = lr.result.status
    row["outcome"] = lr.metrics["outcome"]
    row["message"] = lr.metrics["message"]
    row["warnings"] = list(lr.metrics["warnings"])
    for m in job["metrics"]:
        v = lr.metrics.get(m)
        if isinstance(v, float) and not math.isfinite(v):
            v = None
        row[m] = v
    if job["keep_traces"]:
        frame = lr.result.to_frame()
    return row, frame


#: sweep id -> its VariantPlan in this process (threads share it; a few sweeps are kept)
_PLANS: dict = {}
_PLANS_LOCK = threading.Lock()


def variant_plan(job: dict):
    """The :class:`~clutchsim.scenario.variants.VariantPlan` of ``job``'s base scenario
    and model, built once per process (a Dask worker builds its own)."""
    plan = _PLANS.get(job["sweep_id"])
    if plan is None:
        with _PLANS_LOCK:
            plan = _PLANS.get(job["sweep_id"])
            if plan is None:
                from ..scenario.loader import parse_scenario, with_solver_options
                from ..scenario.variants import VariantPlan
                sc = with_solver_options(parse_scenario(job["data"], text=job["text"],
                                                        file=job["file"]), job.get("options"))
                plan = VariantPlan(sc, job["model"])
                while len(_PLANS) >= 4:
                    _PLANS.pop(next(iter(_PLANS)))
                _PLANS[job["sweep_id"]] = plan
    return plan


def run_chunk(job: dict, runs: list) -> dict:
    """Run ``runs`` = ``[(run_id, values), ...]`` one after the other.

    Returns ``{"rows": [...], "traces": {run_id: DataFrame}}``.
    """
    rows, traces = [], {}
    for run_id, values in runs:
        row, frame = run_variant(job, values)
        row["run"] = run_id
        row.update(zip(job["keys"], values))
        rows.append(row)
        if frame is not None:
            traces[run_id] = frame
    return {"rows": rows, "traces": traces}
