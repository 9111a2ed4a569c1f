"""Run one chunk of variants (the unit of work of every backend; picklable, module level)."""

from __future__ import annotations

import math
import threading
from dataclasses import replace

__all__ = ["DEFAULT_METRICS", "METRICS", "result_columns", "run_chunk", "run_variant",
           "variant_plan"]

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
    "peak_heat_node_temp_C": ("°C", "float"),
    "peak_surface_temp_C": ("°C", "float"),
    "engine_speed_min_rpm": ("rpm", "float"),
    "engine_speed_max_rpm": ("rpm", "float"),
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


def run_variant(job: dict, values: tuple, plan=None, options=None) -> tuple[dict, object]:
    """One run: ``(row, frame)``; ``frame`` is the time series (only with keep_traces).

    The variant is a set of values on the scenario's network, built once per sweep and
    process (:class:`clutchsim.scenario.variants.VariantPlan`); keys that change more
    than a component value rebuild the scenario for the variant.  A run that fails
    (stall, NaN, budget) or whose parameters are invalid becomes a row with its status
    and message; this function does not raise for those.  ``outcome`` is the
    machine-readable reason (the launch metrics' ``outcome``: ``completed``, ``stalled``,
    ``chatter``, ``budget``, ...; ``error`` for invalid parameters) and ``warnings`` the
    run's warnings (a list of str).  ``plan`` and ``options``: the plan of ``job`` and
    its solver options with the output cap applied (:func:`_capped`), when the caller
    (:func:`run_chunk`, once per chunk) already has them.
    """
    from ...scenario.loader import with_solver_options
    from ...scenario.run import run_system
    row: dict = {"status": "error", "outcome": "error", "message": "", "warnings": []}
    frame = None
    try:
        if plan is None:
            plan = variant_plan(job)
            options = _capped(plan.scenario.options, job)
        changes = tuple(zip(job["keys"], values))
        system = plan.system(changes)
        sc = plan.scenario
        if system is None:
            sc, system = plan.rebuilt(changes)
            sc = with_solver_options(sc, job.get("options"))
            options = _capped(sc.options, job)
        lr = run_system(sc, system, job["model"], options=options)
    except (ValueError, ArithmeticError, KeyError, TypeError) as exc:
        row["message"] = f"{type(exc).__name__}: {exc}"
        return row, frame
    row = _row(job, lr.result.status, lr.metrics)
    if job["keep_traces"]:
        frame = lr.result.to_frame()
    return row, frame


def _row(job: dict, status: str, m: dict) -> dict:
    """A run's row (but its run id and varied values) from its status and metrics."""
    row = {"status": status, "outcome": m["outcome"], "message": m["message"],
           "warnings": list(m["warnings"])}
    for name in job["metrics"]:
        v = m.get(name)
        if isinstance(v, float) and not math.isfinite(v):
            v = None
        row[name] = v
    return row


def _capped(options, job: dict):
    """``options`` with the sweep's output cap (``job["max_output"]``) on a run that
    stores every step (``dt_out == 0``)."""
    cap = job.get("max_output")
    if cap is not None and options.dt_out == 0 and options.max_output > cap:
        return replace(options, max_output=int(cap))
    return options


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
                from ...scenario.loader import parse_scenario, with_solver_options
                from ...scenario.variants import VariantPlan
                sc = with_solver_options(parse_scenario(job["data"], text=job["text"],
                                                        file=job["file"]), job.get("options"))
                plan = VariantPlan(sc, job["model"])
                while len(_PLANS) >= 4:
                    _PLANS.pop(next(iter(_PLANS)))
                _PLANS[job["sweep_id"]] = plan
    return plan


def result_columns(keys, metrics) -> tuple:
    """The columns of the results, in their order: the run, the varied keys, the run's
    status, outcome, message and warnings, the metrics (the one place that lays them out:
    :func:`clutchsim.studies.sweeps.store.table_schema` types them, :func:`run_chunk` fills them)."""
    return ("run", *keys, "status", "outcome", "message", "warnings", *metrics)


def run_chunk(job: dict, runs: list) -> dict:
    """Run ``runs`` = ``[(run_id, values), ...]``.

    Returns ``{"columns": {name: [value per run]}, "n": len(runs), "traces": {run_id:
    DataFrame}, "batched": int, "batch_loop_wall_s": float}``: the chunk's table as one
    list per column (:func:`result_columns`), so that the writer builds it in one step.
    The plan and the capped solver options are looked up once per chunk, not per run.

    The variants that are parameter values on the scenario's network run in one compiled
    call (:func:`clutchsim.scenario.run.run_batch`: ``batched`` of them, whose compiled
    loop took ``batch_loop_wall_s``); the others (rebuild keys, values the checks refuse,
    a sweep that keeps traces, a scenario the batch cannot run) one by one
    (:func:`run_variant`).  Both give the same rows.
    """
    names = result_columns(job["keys"], job["metrics"])
    traces = {}
    plan = options = None
    try:
        plan = variant_plan(job)
        options = _capped(plan.scenario.options, job)
    except (ValueError, ArithmeticError, KeyError, TypeError):
        plan = None         # each run reports the error in its own row
    keys = job["keys"]
    rows: dict = {}
    loop_wall = 0.0
    if plan is not None and not job["keep_traces"] and job.get("batch", True):
        rows, loop_wall = _run_batched(job, plan, options, runs)
    n_batched = len(rows)
    for run_id, values in runs:
        if run_id in rows:
            continue
        row, frame = run_variant(job, values, plan, options)
        rows[run_id] = row
        if frame is not None:
            traces[run_id] = frame
    cols: dict = {n: [] for n in names}
    for run_id, values in runs:
        row = rows[run_id]
        row["run"] = run_id
        row.update(zip(keys, values))
        for n in names:
            cols[n].append(row.get(n))
    return {"columns": cols, "n": len(runs), "traces": traces,
            "batched": n_batched,
            "batch_loop_wall_s": loop_wall}


def _run_batched(job: dict, plan, options, runs: list) -> tuple[dict, float]:
    """``({run_id: row}, loop wall time [s])`` of the runs of ``runs`` that are values on
    the plan's network, run as one batch (none when the scenario cannot be batched)."""
    from ...scenario.run import run_batch
    if plan.batch_reason:
        return {}, 0.0
    ids, variants = [], []
    for run_id, values in runs:
        try:
            found = plan.values(tuple(zip(job["keys"], values)))
        except (ValueError, ArithmeticError, KeyError, TypeError):
            found = None        # run one by one: its row says why
        if found is not None:
            ids.append(run_id)
            variants.append(found)
    if not variants:
        return {}, 0.0
    try:
        done = run_batch(plan.scenario, plan.base_system(), variants, options=options)
    except (ValueError, ArithmeticError):
        return {}, 0.0          # e.g. a non-finite value: each run's row says which
    rows = {run_id: _row(job, status, m) for run_id, (status, m) in zip(ids, done)}
    return rows, sum(m["loop_wall_s"] for _s, m in done)
