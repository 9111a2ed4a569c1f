"""Where the time of one default launch goes, and how low it can go.

An analysis, not a race: it has no baseline of its own.  It answers the question behind the
≤ 3 ms target of ``launch_speed.py`` (issue 15): how many steps does the default launch
(examples/launch.toml, model (6), 0–4 s, its own method and tolerances) need, what does each
one cost, and what is left at looser tolerances.  Rows (all in this process, medians of
``--repeats`` runs after a warm-up):

* a tolerance ladder of the scenario's method from rtol 1e-7 to 1e-3 (atol = rtol/100, as
  in ``launch_speed.py``'s ladder), with the largest engine, disc and wheel speed error
  against a tight run (rtol 1e-10) on the output times both share, steps, right-hand
  sides, Jacobians, events and the integrator's own time;
* the scenario as it is (its rtol and atol); ``simulate`` alone (no launch metrics) on the
  scenario's output grid, every 20 ms, and with one output row at the end (what recording
  the output signals costs; a grid coarser than 10 ms is refused for a run with launch
  metrics, so these rows time the integration alone); the I controller instead of the
  predictive one, and RODAS4;
* the scenario with the clutch's contact mode damped (``k_v`` 0.05 → 10 N·m·s/rad): how
  many of the steps the lightly damped pre-sliding spring of model (6) takes
  (T_stat/φ0 = 2.4e5 N·m/rad on the disc, ~670 Hz) and how many the rest of the driveline
  needs (another model, so no speed error is given).

For the scenario row it says where the right-hand sides and event evaluations come from
(``step_cost.accounts``).  It also times the compiled plant alone (a compiled loop calling
the right-hand side, the event functions, the outputs and the exact Jacobian at one state
of the launch) and derives the per-step budget a 3 ms launch would leave.

Prints one JSON object on the last stdout line.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numba
import numpy as np
from _common import c_function_values, emit
from _launch_plain import SPEEDS
from step_cost import accounts

from clutchsim.core.methods import get_method
from clutchsim.core.system import has_jacobian

MODEL = "mykhailevych2020"
LADDER = (1e-7, 3e-7, 1e-6, 1e-5, 1e-4, 1e-3)
TARGET_MS = 3.0


def _load(overrides):
    from clutchsim.scenario import load_scenario
    return load_scenario(None, overrides=["solver.wall_time=1000", *overrides])


def _speed_error_rpm(res, ref) -> float:
    """Largest speed difference [rpm] on the output times the two runs share (both write
    rows on the same dt_out grid; interpolating between rows would add its own error)."""
    i = np.clip(np.searchsorted(ref.t, res.t), 1, ref.t.size - 1)
    i = np.where(np.abs(ref.t[i - 1] - res.t) < np.abs(ref.t[i] - res.t), i - 1, i)
    same = np.abs(ref.t[i] - res.t) <= 1e-9
    return max(float(np.max(np.abs(res[k][same] - ref[k][i[same]]))) for k in SPEEDS) \
        * 30.0 / np.pi


def _row(name, overrides, ref, repeats, same_model=True, dt_out=None):
    """One row: ``run_scenario`` (the run and its launch metrics), or with ``dt_out`` [s]
    ``simulate`` alone on that output grid (a grid coarser than the metrics allow,
    :data:`clutchsim.analysis.launch_metrics.DT_OUT_MAX_S`: what recording rows costs)."""
    from dataclasses import replace

    from clutchsim.core import simulate
    from clutchsim.scenario import run_scenario
    sc = _load(overrides)
    system = sc.network(MODEL).build(sc.inputs0())
    if dt_out is None:
        def run():
            return run_scenario(sc, MODEL).result
    else:
        inputs = {n: sc.inputs[n] for n in system.input_names}
        opts = replace(sc.options, dt_out=dt_out)

        def run():
            return simulate(system, (0.0, sc.t_end), inputs, solver=sc.solver, options=opts)
    res = run()
    total, integ = [], []
    for _ in range(repeats):
        t0 = time.perf_counter()
        res = run()
        total.append((time.perf_counter() - t0) * 1e3)
        integ.append(res.stats.wall_s * 1e3)
    s = res.stats
    kind = "exact" if has_jacobian(system.tag) else "finite differences"
    return {"case": name, "status": res.status, "ms": statistics.median(total),
            "integrator_ms": statistics.median(integ), "steps": s.steps,
            "rejected": s.rejected, "rhs_evals": s.rhs_evals, "jacobians": s.jacobians,
            "events": s.events, "output_rows": int(res.t.size),
            "speed_error_rpm": _speed_error_rpm(res, ref) if same_model else None,
            "accounts": accounts(s, get_method(sc.solver).stages, system, kind)}


@numba.njit(inline="always")
def _a(x):
    return np.int64(x.ctypes.data)


@numba.njit
def _call_in_loop(f, n, t, y, u, p, dy):
    # f: the C function at its address, pointers as int64 (_common.c_function_values)
    s = 0.0
    for _ in range(n):
        y[0] += 1e-12            # keep the compiler from hoisting the call
        f(t, _a(y), _a(u), _a(p), _a(dy))
        s += dy[0]
    return s


@numba.njit
def _jac_in_loop(f, n, t, y, u, p, J):
    s = 0.0
    for _ in range(n):
        y[0] += 1e-12
        f(t, _a(y), _a(u), _a(p), _a(J), J.shape[1])
        s += J[0, 0]
    return s


def _plant_ns(n: int = 200_000) -> dict:
    """Nanoseconds per call of the launch plant's rhs, events, outputs and exact Jacobian
    at t = 0.9 s of the default launch (clutch slipping), best of 5 loops of ``n`` calls
    (``n/10`` for the Jacobian)."""
    from clutchsim.core.system import plant_functions
    from clutchsim.scenario import run_scenario
    sc = _load([])
    res = run_scenario(sc, MODEL).result
    u0 = {name: float(np.asarray(sig(0.0)).ravel()[0]) for name, sig in sc.inputs.items()}
    system = sc.network(MODEL).build(u0)
    fns = plant_functions(system.tag)
    i = int(np.searchsorted(res.t, 0.9))
    y = np.array([res[name][i] for name in system.state_names])
    u = np.array([res[name][i] for name in system.input_names])
    out = {}
    cf = c_function_values(system)      # the C functions, as the engine calls them
    cases = [("rhs", cf["rhs"], np.empty(y.size), _call_in_loop, n),
             ("events", cf["events"], np.empty(len(system.event_names)), _call_in_loop, n),
             ("outputs", cf["outputs"], np.empty(len(system.output_names)), _call_in_loop, n)]
    if fns.has_jac:
        cases.append(("jac", cf["jac"], np.zeros((y.size, y.size)), _jac_in_loop, n // 10))
    for name, fn, buf, loop, calls in cases:
        loop(fn, 10, 0.9, y, u, system.params, buf)
        best = np.inf
        for _ in range(5):
            t0 = time.perf_counter()
            loop(fn, calls, 0.9, y, u, system.params, buf)
            best = min(best, time.perf_counter() - t0)
        out[f"{name}_ns"] = best / calls * 1e9
    return out


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeats", type=int, default=15)
    a = ap.parse_args(argv)
    from clutchsim.scenario import run_scenario
    ref = run_scenario(_load(["solver.rtol=1e-10", "solver.atol=1e-12"]), MODEL).result
    sc = _load([])
    own = f"{sc.solver} rtol {sc.options.rtol:g} atol {sc.options.atol:g}"
    rows = [_row(f"{sc.solver} rtol {rt:g} (atol rtol/100)",
                 [f"solver.rtol={rt!r}", f"solver.atol={rt / 100!r}"], ref, a.repeats)
            for rt in LADDER]
    rows += [
        _row(f"the scenario: {own}", [], ref, a.repeats),
        _row("  simulate alone, as the scenario", [], ref, a.repeats, dt_out=sc.options.dt_out),
        _row("  simulate alone, outputs every 20 ms", [], ref, a.repeats, dt_out=0.02),
        _row("  simulate alone, one output row at the end", [], ref, a.repeats,
             dt_out=sc.t_end),
        _row("  controller I", ["solver.controller='I'"], ref, a.repeats),
        _row("  rodas4", ["solver.method='rodas4'"], ref, a.repeats),
        _row("  contact mode damped (k_v = 10)",
             ["coupling[0].friction.overrides.k_v=10.0"], ref, a.repeats, same_model=False),
    ]
    for r in rows:
        print(f"{r['case']:44s} {r['ms']:7.2f} ms (integrator {r['integrator_ms']:6.2f}) "
              f"{r['steps']:6,d} steps {r['rejected']:4d} rejected {r['rhs_evals']:7,d} RHS "
              f"{r['events']:4d} events  error "
              + ("-" if r["speed_error_rpm"] is None else f"{r['speed_error_rpm']:.3g} rpm")
              + f"  {r['status']}")
    plant = _plant_ns()
    print("compiled plant, ns per call: " + ", ".join(f"{k[:-3]} {v:.0f}"
                                                      for k, v in plant.items()))
    base = rows[len(LADDER)]
    budget_ns = TARGET_MS * 1e6 / base["steps"]
    result = {"rows": rows, **plant, "scenario": own,
              "steps_at_scenario_tolerance": base["steps"],
              **base["accounts"],
              f"budget_ns_per_step_for_{TARGET_MS:g}ms": budget_ns,
              "rhs_calls_per_step": base["rhs_evals"] / base["steps"],
              "budget_in_rhs_calls_per_step": budget_ns / plant["rhs_ns"]}
    print(f"the scenario ({own}): right-hand sides by source {base['accounts']['rhs_by_source']}"
          f"; event evaluations by source {base['accounts']['event_evals_by_source']}")
    print(f"a {TARGET_MS:g} ms launch leaves {budget_ns:.0f} ns per step at the scenario's "
          f"tolerance = {result['budget_in_rhs_calls_per_step']:.1f} right-hand sides; a step "
          f"takes {result['rhs_calls_per_step']:.1f} (plus its Jacobian, matrix inverse, solves, event "
          "checks and output rows)")
    emit(result)
    return result


if __name__ == "__main__":
    main()
