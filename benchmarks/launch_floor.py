"""Where the time of one default launch goes, and how low it can go.

An analysis, not a race: it has no baseline and no target of its own.  It answers the
question behind the ≤ 2 ms target of ``launch_speed.py``: how many steps does the default
launch (examples/launch.toml, model (6), 0–4 s) need, what does each one cost, and what is
left at looser tolerances.  Rows (all in this process, medians of ``--repeats`` runs after a
warm-up):

* a tolerance ladder from rtol 1e-7 to 1e-3 (atol = rtol/100, as in the scenario), with
  the largest engine, disc and wheel speed error against a tight run (rtol 1e-10) on the
  output times both share, steps, right-hand sides, Jacobians, events and the
  integrator's own time;
* the scenario's tolerance with outputs every 20 ms instead of 2 ms (what recording the
  35 output signals costs);
* the scenario's tolerance with the clutch's contact mode damped (``k_v`` 0.05 → 10
  N·m·s/rad): how many of the steps the lightly damped pre-sliding spring of model (6)
  takes (T_stat/φ0 = 2.4e5 N·m/rad on the disc, ~670 Hz) and how many the rest of the
  driveline needs (another model, so no speed error is given);
* RODAS4 instead of ROS34PW2 at the scenario's tolerance (fewer steps, one Jacobian each).

It also times the compiled plant alone (a compiled loop calling the right-hand side, the
event functions, the outputs and the exact Jacobian at one state of the launch; since the
network issue the launch runs on its generated network plant) and derives the per-step
budget a 2 ms launch would leave.

Prints one JSON object on the last stdout line.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numba
import numpy as np
from _common import emit
from _launch_plain import SPEEDS

MODEL = "mykhailevych2020"
LADDER = (1e-7, 3e-7, 1e-6, 1e-5, 1e-4, 1e-3)
TARGET_MS = 2.0


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


def _row(name, overrides, ref, repeats, same_model=True):
    from clutchsim.scenario import run_scenario
    sc = _load(overrides)
    r = run_scenario(sc, MODEL)
    total, integ = [], []
    for _ in range(repeats):
        t0 = time.perf_counter()
        r = run_scenario(sc, MODEL)
        total.append((time.perf_counter() - t0) * 1e3)
        integ.append(r.result.stats.wall_s * 1e3)
    s = r.result.stats
    return {"case": name, "status": r.result.status, "ms": statistics.median(total),
            "integrator_ms": statistics.median(integ), "steps": s.steps,
            "rejected": s.rejected, "rhs_evals": s.rhs_evals, "jacobians": s.jacobians,
            "events": s.events, "output_rows": int(r.result.t.size),
            "speed_error_rpm": _speed_error_rpm(r.result, ref) if same_model else None}


@numba.njit
def _call_in_loop(f, n, t, y, u, p, dy):
    s = 0.0
    for _ in range(n):
        y[0] += 1e-12            # keep the compiler from hoisting the call
        f(t, y, u, p, dy)
        s += dy[0]
    return s


@numba.njit
def _jac_in_loop(f, n, t, y, u, p, J):
    s = 0.0
    for _ in range(n):
        y[0] += 1e-12
        f(t, y, u, p, J)
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
    system = sc.chain(MODEL).build(u0)
    fns = plant_functions(system.tag)
    i = int(np.searchsorted(res.t, 0.9))
    y = np.array([res[name][i] for name in system.state_names])
    u = np.array([res[name][i] for name in system.input_names])
    out = {}
    cases = [("rhs", fns.rhs, np.empty(y.size), _call_in_loop, n),
             ("events", fns.events, np.empty(len(system.event_names)), _call_in_loop, n),
             ("outputs", fns.outputs, np.empty(len(system.output_names)), _call_in_loop, n)]
    if fns.has_jac:
        cases.append(("jac", fns.jac, np.zeros((y.size, y.size)), _jac_in_loop, n // 10))
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
    rows = [_row(f"rtol {rt:g}", [f"solver.rtol={rt!r}", f"solver.atol={rt / 100!r}"],
                 ref, a.repeats) for rt in LADDER]
    rows += [
        _row("rtol 1e-6, outputs every 20 ms", ["solver.dt_out=0.02"], ref, a.repeats),
        _row("rtol 1e-6, contact mode damped (k_v = 10)",
             ["coupling[0].friction.overrides.k_v=10.0"], ref, a.repeats, same_model=False),
        _row("rtol 1e-6, rodas4", ["solver.method='rodas4'"], ref, a.repeats),
    ]
    for r in rows:
        print(f"{r['case']:44s} {r['ms']:7.2f} ms (integrator {r['integrator_ms']:6.2f}) "
              f"{r['steps']:6,d} steps {r['rhs_evals']:7,d} RHS {r['jacobians']:5d} J "
              f"{r['events']:4d} events  error "
              + ("-" if r["speed_error_rpm"] is None else f"{r['speed_error_rpm']:.3g} rpm")
              + f"  {r['status']}")
    plant = _plant_ns()
    print("compiled plant, ns per call: " + ", ".join(f"{k[:-3]} {v:.0f}"
                                                      for k, v in plant.items()))
    base = rows[LADDER.index(1e-6)]
    budget_ns = TARGET_MS * 1e6 / base["steps"]
    result = {"rows": rows, **plant,
              "steps_at_scenario_tolerance": base["steps"],
              "budget_ns_per_step_for_2ms": budget_ns,
              "rhs_calls_per_step": base["rhs_evals"] / base["steps"],
              "budget_in_rhs_calls_per_step": budget_ns / plant["rhs_ns"]}
    print(f"a 2 ms launch leaves {budget_ns:.0f} ns per step at rtol 1e-6 = "
          f"{result['budget_in_rhs_calls_per_step']:.1f} right-hand sides; a step takes "
          f"{result['rhs_calls_per_step']:.1f} (plus its LU, solves and event checks)")
    emit(result)
    return result


if __name__ == "__main__":
    main()
