"""Throughput of ``clutchsim.sweep`` on launch variants (metrics only).

Problem: the packaged default launch with model (6) (examples/launch.toml, 0–4 s, with the
scenario's solver settings: rodas5p, rtol = 3e-6, atol = 1e-8), seeded Monte Carlo over vehicle mass (uniform 1100–1500 kg) and road
grade (uniform 0–8 %).  Measured:

* ``runs`` variants in-process on all cores (threads; the compiled integrator releases the
  GIL): ``wall_s``, ``runs_per_s``, ``peak_rss_mb`` (this process, ru_maxrss);
* ``--scaling-runs`` variants on 1 and on 2 threads: ``runs_per_s_1_worker``,
  ``runs_per_s_2_workers`` and their ratio;
* ``--dask-runs`` variants on a Dask LocalCluster (2 worker processes, 1 thread each) and
  in this process on 2 threads, alternated ``--dask-rounds`` times (medians), cluster
  start-up excluded (``dask_local_runs_per_s``, ``dask_in_process_runs_per_s``, their time
  ratio ``dask_vs_in_process``) and included (``dask_local_incl_startup_runs_per_s``).
  1,000 runs by default: the ``--scaling-runs`` sweep's 7 chunks of 32 on 2 workers are
  4 against 3 by construction and its ratio moved between 1.08 and 1.67 from run to run.
  Start-up is the cluster plus a two-launch sweep on every worker (``_warm_worker``: each
  worker process loads the compiled plant and the batch loop from the numba cache once,
  ~1-2 s, which would otherwise land inside the timed runs of whichever worker meets its
  first chunk there).

The split of the ``runs`` sweep: ``cpu_ms_per_run`` (this process's CPU time, all threads:
the integrator, the metrics kernel and the Python around them, per run),
``loop_wall_ms_per_run`` (the compiled loops' own wall time, summed over the threads, per
run: the ``wall_s`` metric), ``idle_core_fraction`` (1 − CPU time / (cores × wall time):
core time this process left unused, to the other processes of a shared machine, to the
GIL, or to the tail of the last chunks) and ``load_avg_1min`` at the end.

The variants of a chunk run in one compiled call (``clutchsim.analysis.launch_batch``: the
integrator and the metrics kernel for each, ``batched_runs`` of them), so the Python time
per run is what is left outside it: ``python_ms_per_run`` = (this process's CPU time −
the batches' compiled wall time, ``batch_loop_ms_per_run``) per run of the ``runs`` sweep
(the variants' parameter vectors and initial states, the rows, the chunk files and the
sweep's start-up spread over the runs), and ``python_ms_per_run_1_worker`` = (wall on 1
thread − the batches' wall) per run of the ``--scaling-runs`` sweep.  Also
``setup_ms_per_run`` as before the batches: wall per run on 1 thread minus the
integrator's own wall time (the metrics kernel, compiled, counts as setup there).
Issue 7 asks for 10,000 runs (the default; ~3 min on the 2-core project machine at ~30 ms
per launch); ``--runs`` sets a smaller count (the result says which was used).

Prints one JSON object on the last stdout line.
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import sys
import tempfile
import time

from _common import emit

VARY = {"vehicle.mass": "uniform(1100, 1500)", "vehicle.grade": "uniform(0, 8)"}


def _warm_worker():
    """Load the compiled launch plant and the sweep's batch loop in this (worker)
    process: a sweep of two default launches, in the worker itself."""
    from clutchsim.studies.sweeps import SweepOptions, sweep
    with tempfile.TemporaryDirectory(prefix="clutchsim-warm-") as d:
        res = sweep(None, {"vehicle.mass": [1200.0, 1300.0]}, SweepOptions(workers=1),
                    out=os.path.join(d, "w"), load=False)
    return res.batched_runs == 2 and res.status_counts == {"completed": 2}


def run(out, n, metrics=None, **options):
    """A sweep of ``n`` samples (``options``: SweepOptions' fields); (wall [s], result)."""
    from clutchsim.studies.sweeps import SweepOptions, SweepSpec, sweep
    t0 = time.perf_counter()
    res = sweep(None, SweepSpec(VARY, samples=n, seed=1, metrics=metrics),
                SweepOptions(**options), out=out, load=False)
    return time.perf_counter() - t0, res


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=10_000)
    ap.add_argument("--scaling-runs", type=int, default=200)
    ap.add_argument("--no-dask", action="store_true")
    ap.add_argument("--dask-runs", type=int, default=1000,
                    help="variants of each Dask and in-process comparison sweep")
    ap.add_argument("--dask-rounds", type=int, default=3,
                    help="alternations of the comparison (medians)")
    a = ap.parse_args()
    import pyarrow.parquet as pq
    tmp = tempfile.TemporaryDirectory(prefix="clutchsim-bench-")
    d = tmp.name
    run(os.path.join(d, "warm"), 2, workers=1)          # compile / load the numba cache
    from clutchsim.studies.sweeps import DEFAULT_METRICS
    cpu0 = time.process_time()
    wall, res = run(os.path.join(d, "main"), a.runs, metrics=[*DEFAULT_METRICS, "wall_s"])
    cpu = time.process_time() - cpu0
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    loops = pq.read_table(res.path / "results.parquet", columns=["wall_s"])["wall_s"]
    loop_s = sum(v for v in loops.to_pylist() if v is not None)
    workers = os.cpu_count()
    # the compiled loops' own time: the batches' (integrator and metrics kernel) when every
    # run was batched, else the integrators' (the wall_s column)
    compiled_s = res.batch_loop_wall_s if res.batched_runs == a.runs else loop_s
    out = {"runs": a.runs, "wall_s": wall, "runs_per_s": a.runs / wall, "peak_rss_mb": rss,
           "status_counts": res.status_counts, "workers": workers,
           "cpu_ms_per_run": cpu / a.runs * 1e3,
           "loop_wall_ms_per_run": loop_s / a.runs * 1e3,
           "batched_runs": res.batched_runs,
           "batch_loop_ms_per_run": res.batch_loop_wall_s / a.runs * 1e3,
           "python_ms_per_run": (cpu - compiled_s) / a.runs * 1e3,
           "idle_core_fraction": 1.0 - cpu / (workers * wall),
           "load_avg_1min": os.getloadavg()[0]}
    w1, r1 = run(os.path.join(d, "w1"), a.scaling_runs, workers=1, metrics=["wall_s"])
    integ = pq.read_table(r1.path / "results.parquet", columns=["wall_s"])["wall_s"]
    integ_s = sum(v for v in integ.to_pylist() if v is not None)
    w2, _ = run(os.path.join(d, "w2"), a.scaling_runs, workers=2)
    out.update(scaling_runs=a.scaling_runs, runs_per_s_1_worker=a.scaling_runs / w1,
               runs_per_s_2_workers=a.scaling_runs / w2, speedup_1_to_2=w1 / w2,
               setup_ms_per_run=(w1 - integ_s) / a.scaling_runs * 1e3,
               python_ms_per_run_1_worker=(w1 - (r1.batch_loop_wall_s if r1.batched_runs
                                                 == a.scaling_runs else integ_s))
               / a.scaling_runs * 1e3,
               integrator_ms_per_run=integ_s / a.scaling_runs * 1e3)
    if not a.no_dask:
        from distributed import Client, LocalCluster
        t0 = time.perf_counter()
        cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                               dashboard_address=None)
        client = Client(cluster)
        client.run(lambda: __import__("clutchsim.studies.sweeps.runner"))
        warm = client.run(_warm_worker)                      # every worker loads the cache
        if not all(warm.values()):
            print(f"warm-up launch failed on a worker: {warm}", file=sys.stderr)
        run(os.path.join(d, "dwarm"), 2, backend=client)    # and the sweep path once
        startup = time.perf_counter() - t0
        n = a.dask_runs
        wd, wt = [], []
        for k in range(a.dask_rounds):                      # alternated: the same load
            wt.append(run(os.path.join(d, f"tround{k}"), n)[0])
            wd.append(run(os.path.join(d, f"dask{k}"), n, backend=client)[0])
        client.close()
        cluster.close()
        wd, wt = statistics.median(wd), statistics.median(wt)
        out.update(dask_runs=n, dask_local_runs_per_s=n / wd,
                   dask_local_incl_startup_runs_per_s=n / (wd + startup),
                   dask_startup_s=startup, dask_in_process_runs_per_s=n / wt,
                   dask_vs_in_process=wd / wt)
    else:
        out["dask_local_runs_per_s"] = None
    tmp.cleanup()
    print(f"{out['runs']} runs at {out['runs_per_s']:.2f} runs/s", file=sys.stderr)
    emit(out)


if __name__ == "__main__":
    main()
