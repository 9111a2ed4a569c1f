"""Throughput of ``clutchsim uq`` on the default launch (issue 37), metrics only.

Three studies, each after a two-run warm-up that loads the compiled plant:

* ``grade_low``: Monte Carlo, vehicle mass uniform 1100–1500 kg and road grade uniform
  0–1.5 % (every launch completes the full 4 s), ``--runs`` runs;
* ``grade_high``: the same with grade uniform 0–8 % (the sweep benchmark's workload: about
  a third to a half of the launches stall the engine and stop at ~1.25 s);
* ``sobol4``: Sobol' first and total indices over four inputs (mass uniform 1100–1500 kg,
  grade uniform 0–1.5 %, the engine inertia ``inertia[0].J`` tnormal(0.15, 0.01, 0.12,
  0.18) kg·m², the friction parameter ``coupling[0].friction.overrides.phi0``
  lognormal(0.001, 0.1)), ``--sobol-base`` base samples: base × 6 runs.

For each: ``runs``, ``wall_s`` (the whole study: sampling, the sweep, the estimates,
the files; no figures), ``run_wall_s`` (the sweep alone), ``runs_per_s`` (runs /
run_wall_s), ``batch_loop_ms_per_run`` (the compiled batches' wall time summed over the
worker threads, per run), ``cpu_ms_per_run`` (this process's CPU time, all threads, per
run), ``analysis_s`` (wall_s − run_wall_s), and at the end ``peak_rss_mb`` (this process,
ru_maxrss) and ``load_avg_1min`` (the machine is shared: read the numbers against it).

Prints one JSON object on the last stdout line.
"""

from __future__ import annotations

import argparse
import os
import resource
import tempfile
import time

from _common import emit

LOW = {"vehicle.mass": "uniform(1100,1500)", "vehicle.grade": "uniform(0,1.5)"}
HIGH = {"vehicle.mass": "uniform(1100,1500)", "vehicle.grade": "uniform(0,8)"}
SOBOL4 = {**LOW, "inertia[0].J": "tnormal(0.15,0.01,0.12,0.18)",
          "coupling[0].friction.overrides.phi0": "lognormal(0.001,0.1)"}


def one(out, vary, method, samples):
    from clutchsim.studies.uq import uq
    cpu0 = time.process_time()
    t0 = time.perf_counter()
    r = uq(None, vary, method=method, samples=samples, seed=1, out=out)
    wall = time.perf_counter() - t0
    cpu = time.process_time() - cpu0
    return {"runs": r.samples, "wall_s": wall, "run_wall_s": r.run_wall_s,
            "runs_per_s": r.samples / r.run_wall_s, "analysis_s": wall - r.run_wall_s,
            "batched_runs": r.batched_runs, "cpu_ms_per_run": cpu / r.samples * 1e3,
            "batch_loop_ms_per_run": r.batch_loop_wall_s / r.samples * 1e3,
            "p_stalled": r.probabilities["stalled"]["p"],
            "load_avg_1min": os.getloadavg()[0]}, r


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=5000)
    ap.add_argument("--sobol-base", type=int, default=2048)
    ap.add_argument("--only", choices=("grade_low", "grade_high", "sobol4"))
    a = ap.parse_args()
    d = tempfile.TemporaryDirectory(prefix="clutchsim-uq-bench-").name
    from clutchsim.studies.sweeps import sweep
    sweep(None, {"vehicle.mass": [1200.0, 1300.0]}, out=os.path.join(d, "warm"), load=False)
    out = {"workers": os.cpu_count()}
    jobs = {"grade_low": (LOW, "mc", a.runs), "grade_high": (HIGH, "mc", a.runs),
            "sobol4": (SOBOL4, "sobol", a.sobol_base)}
    for name, (vary, method, n) in jobs.items():
        if a.only and name != a.only:
            continue
        out[name], r = one(os.path.join(d, name), vary, method, n)
        if name == "sobol4":
            out[name]["ST_lockup_time_s"] = {k: v["ST"] for k, v in
                                             r.sobol["lockup_time_s"].items()}
    out["peak_rss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    emit(out)


if __name__ == "__main__":
    main()
