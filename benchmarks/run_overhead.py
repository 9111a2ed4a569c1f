"""The Python time per driveline run outside the compiled integration loop, by part.

Problem: the packaged default launch (examples/launch.toml: model (6), 0-4 s, RODAS5P at
rtol 3e-6, atol 1e-8), its system built once, run in-process on one thread.  Every part is
timed with the thread's CPU time (``time.thread_time_ns``), which a shared machine
distorts less than wall time, and reported as the minimum over ``--calls`` calls (after
one warm-up call), in milliseconds:

* ``integrator_ms``: the C engine's call alone (the callable
  ``clutchsim.core.cengine.engine_for`` returns; timed by a wrapper around it);
* ``simulate_python_ms``: ``simulate`` minus its compiled loop (option packing, the
  outcome and message, the result's columns and events);
* ``warnings_ms``: ``launch_warnings`` (lock-up hold test, ringing test, step rate);
* ``weighting_ms``: ``with_weighted_acceleration`` (the ISO 2631-1 W_d signal);
* ``metrics_ms``: ``launch_metrics`` on the result with the weighted signal;
* ``run_system_python_ms``: ``scenario.run.run_system`` (all of the above: what a sweep
  run costs besides its parameter vector) minus its compiled loop;
* ``run_system_ms``: ``run_system`` in all;
* ``parts_ms``: the public analysis functions alone on the same run's arrays
  (``clutchsim.analysis.launch_quality`` and ``judder_amplitude``, ``energy_balance``),
  the breakdown of ``weighting_ms`` and ``metrics_ms``;
* ``sweep_python_ms_per_run`` (unless ``--no-sweep``): ``sweep(None, {mass, grade},
  samples=--sweep-runs, workers=1, load=False)``, the process CPU time minus the compiled
  batch loops' thread CPU time (``sweep_loop_ms_per_run``: integrator and metrics kernel
  of each variant, ``clutchsim.analysis.launch_batch``), per run (the variant's parameter vector
  and initial state, the row, the chunk files, and the sweep's fixed cost spread over the
  runs); ``sweep_runs_per_s_1_thread`` its runs per wall second.  Its split, means over
  the runs of that sweep (thread CPU): ``sweep_variant_values_ms_per_run`` (the variant's
  parameter vector and initial state, ``VariantPlan.values``),
  ``sweep_run_batch_python_ms_per_run`` (``scenario.run.run_batch`` minus its compiled
  loop: the loop's arguments and the rows' metrics and warnings), and ``sweep_fixed_ms``
  (a whole 2-run sweep minus its loops: the checks of the varied keys, the plan, the
  manifest, the files).

Runs in the tree it is started from (``PYTHONPATH=src``), so the same script measures a
checkout of an older commit.  Prints one JSON object on the last stdout line.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time

from _common import emit

VARY = {"vehicle.mass": "uniform(1100, 1500)", "vehicle.grade": "uniform(0, 8)"}


def _min_ms(fn, calls: int, inner=None) -> float:
    """Smallest thread CPU time of ``fn()`` over ``calls`` calls [ms], minus the
    integrator's thread CPU time spent inside it when ``inner`` (a list the wrapped loop
    appends to) is given."""
    fn()
    best = float("inf")
    for _ in range(calls):
        if inner is not None:
            inner.clear()
        t0 = time.thread_time_ns()
        fn()
        dt = time.thread_time_ns() - t0 - (sum(inner) if inner is not None else 0)
        best = min(best, dt)
    return best * 1e-6


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--calls", type=int, default=300)
    ap.add_argument("--sweep-runs", type=int, default=200)
    ap.add_argument("--no-sweep", action="store_true")
    a = ap.parse_args()

    import importlib

    from clutchsim.analysis import judder_amplitude
    from clutchsim.analysis import launch_quality as lq
    sim_mod = importlib.import_module("clutchsim.core.simulate")
    dm = importlib.import_module("clutchsim.analysis.launch_metrics")
    from clutchsim.scenario import resolve_scenario
    from clutchsim.scenario import run as run_mod

    inner: list[int] = []
    raw = sim_mod.ce.engine_for

    def timed_engine_for(args, n_states):
        engine = raw(args, n_states)

        def timed(a):
            t0 = time.thread_time_ns()
            out = engine(a)
            inner.append(time.thread_time_ns() - t0)
            return out
        return timed

    sim_mod.ce.engine_for = timed_engine_for      # before the first run prepares its engine

    sc = resolve_scenario(None)
    model = sc.models[0] if sc.models else None
    system = sc.network(model).build(sc.inputs0())
    inputs = {n: sc.inputs[n] for n in system.input_names}
    clutch, lining = sc.clutch, run_mod.lining_geometry(sc)
    expect, friction = (run_mod.expects_lockup(sc, system.metadata["kinds"]),
                        run_mod._is_friction_clutch(sc))

    def simulate():
        return sim_mod.simulate(system, (0.0, sc.t_end), inputs, solver=sc.solver,
                                options=sc.options)

    res = simulate()
    res_w = dm.with_weighted_acceleration(res)
    t, acc = res.t, res["a_vehicle"]
    out = {"calls": a.calls, "model": str(model), "rows": int(res.t.size),
           "columns": len(res.signals), "events": len(res.events),
           "load_avg_1min": os.getloadavg()[0]}
    out["integrator_ms"] = _min_of_inner(simulate, a.calls, inner)
    out["simulate_python_ms"] = _min_ms(simulate, a.calls, inner)
    out["warnings_ms"] = _min_ms(lambda: dm.launch_warnings(
        res, clutch, expect_lockup=expect, friction=friction), a.calls)
    out["weighting_ms"] = _min_ms(lambda: dm.with_weighted_acceleration(res), a.calls)
    out["metrics_ms"] = _min_ms(lambda: dm.launch_metrics(res_w, clutch, lining=lining),
                                a.calls)
    out["run_system_python_ms"] = _min_ms(lambda: run_mod.run_system(sc, system, model),
                                          a.calls, inner)
    out["run_system_ms"] = _min_ms(lambda: run_mod.run_system(sc, system, model), a.calls)

    t_lock = dm._lockup_time(res, clutch)
    t_eng = lq.engagement_start_s(t, res[f"T_friction_{clutch}"])
    aw = res_w["a_weighted"]
    parts = {
        "weighted_acceleration_mps2": lambda: lq.weighted_acceleration_mps2(t, acc),
        "vdv_mps175": lambda: lq.vdv_mps175(t, aw),
        "rms(aw)": lambda: lq.rms(t, aw),
        "jerk_mps3": lambda: lq.jerk_mps3(t, acc),
        "lockup_time (launch_metrics._lockup_time)": lambda: dm._lockup_time(res, clutch),
        "engagement_start_s": lambda: lq.engagement_start_s(t, res[f"T_friction_{clutch}"]),
        "lockup_shock_mps2": lambda: lq.lockup_shock_mps2(t, acc, t_lock),
        "friction_densities": lambda: lq.friction_densities(t, res[f"P_{clutch}"], 1e4),
        "engine_dip_flare_rpm": lambda: lq.engine_dip_flare_rpm(t, res["omega_engine"],
                                                                t_eng, t_lock),
        "judder_amplitude": lambda: judder_amplitude(res, clutch),
        "energy_balance": lambda: dm.energy_balance(res),
    }
    out["parts_ms"] = {k: _min_ms(f, a.calls) for k, f in parts.items()}

    if not a.no_sweep:
        from clutchsim.studies.sweeps import SweepOptions, SweepSpec, sweep
        one = SweepOptions(workers=1)
        parts = _sweep_parts(run_mod, dm)
        with tempfile.TemporaryDirectory(prefix="clutchsim-overhead-") as d:
            sweep(None, SweepSpec(VARY, samples=2, seed=1), one, out=os.path.join(d, "warm"),
                  load=False)
            inner.clear()
            for v in parts.values():
                v.clear()
            c0 = time.process_time_ns()
            sweep(None, SweepSpec(VARY, samples=2, seed=2), one, out=os.path.join(d, "two"),
                  load=False)
            fixed = time.process_time_ns() - c0 - sum(parts["loop"])
            inner.clear()
            for v in parts.values():
                v.clear()
            c0, w0 = time.process_time_ns(), time.perf_counter()
            sweep(None, SweepSpec(VARY, samples=a.sweep_runs, seed=1), one,
                  out=os.path.join(d, "s"), load=False)
            cpu, wall = time.process_time_ns() - c0, time.perf_counter() - w0
            n = a.sweep_runs
            loop = sum(parts["loop"])
            out["sweep_runs"] = n
            out["sweep_python_ms_per_run"] = (cpu - loop) * 1e-6 / n
            out["sweep_loop_ms_per_run"] = loop * 1e-6 / n
            out["sweep_runs_per_s_1_thread"] = n / wall
            # the split of sweep_python_ms_per_run (means over the runs, thread CPU)
            out["sweep_fixed_ms"] = fixed * 1e-6
            out["sweep_variant_values_ms_per_run"] = sum(parts["values"]) * 1e-6 / n
            out["sweep_run_batch_python_ms_per_run"] = \
                (sum(parts["run_batch"]) - loop) * 1e-6 / n
    out["load_avg_1min_end"] = os.getloadavg()[0]
    print(f"Python per run_system: {out['run_system_python_ms']:.3f} ms "
          f"(integrator {out['integrator_ms']:.3f} ms)", file=sys.stderr)
    emit(out)


def _sweep_parts(run_mod, dm) -> dict:
    """Wrap the variant's values (``VariantPlan.values``), ``run_batch`` and the compiled
    batch loop with thread CPU timers; returns their lists of times [ns]."""
    from clutchsim.analysis import launch_batch as batch
    from clutchsim.scenario import variants
    parts: dict = {"values": [], "run_batch": [], "loop": []}

    def timer(fn, into):
        def timed(*args, **kw):
            t0 = time.thread_time_ns()
            res = fn(*args, **kw)
            into.append(time.thread_time_ns() - t0)
            return res
        return timed

    variants.VariantPlan.values = timer(variants.VariantPlan.values, parts["values"])
    run_mod.run_batch = timer(run_mod.run_batch, parts["run_batch"])
    entry = batch._entry
    batch._entry = lambda args: timer(entry(args), parts["loop"])
    return parts


def _min_of_inner(fn, calls: int, inner: list) -> float:
    """Smallest thread CPU time of the compiled loop inside ``fn()`` over ``calls`` [ms]."""
    best = float("inf")
    for _ in range(calls):
        inner.clear()
        fn()
        best = min(best, sum(inner))
    return best * 1e-6


if __name__ == "__main__":
    main()
