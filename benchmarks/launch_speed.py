"""Speed of one default launch (model (6), mykhailevych2020) against scipy ``solve_ivp``.

Problem: the packaged passenger-car launch (examples/launch.toml: 5 inertias, two-stage
damper, gearbox, driveshaft, engine with idle governor, thermal nodes; 0–4 s; rodas4,
rtol = atol = 1e-8, outputs every 2 ms) with friction model (6) on the clutch.  Compared:

* clutchsim: ``run_scenario`` (compiled RODAS4 with located events and resets);
* scipy ``solve_ivp`` RK45 and LSODA through clutchsim's scipy backend (terminal events,
  the plant's reset map, restart), calling the plant's **compiled** right-hand side: the
  same equations, with scipy's per-step Python overhead only.

MISSING (issue 7 asks for it): a hand-written plain-Python RHS of the driveline equations.
Running the plant's own source uncompiled (``NUMBA_DISABLE_JIT=1``) does not work: the
core's system dispatch (``system_outputs``) is only callable from compiled code.  The
baselines below are therefore *faster* than the plain-Python baseline of the issue, and the
ratios are lower bounds of the ratios the issue asks for.

Each scipy baseline runs in a child process with a time limit (``--scipy-timeout``); a
baseline that does not finish is reported as ``null`` with the limit as a lower bound.
``max_abs_speed_diff_rpm``: the largest difference of the engine, disc and wheel speeds
between clutchsim and each baseline on the common 2 ms output grid.

Prints one JSON object on the last stdout line.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np
from _common import emit, median_ms

SPEEDS = ("omega_engine", "omega_disc", "omega_wheels")
_CHILD = rf"""
import json, sys, time, numpy as np
from clutchsim.scenario import load_scenario
from clutchsim.driveline.run import run_scenario
method, repeats, t_end, out = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), sys.argv[4]
sc = load_scenario(None, overrides=[f"scenario.t_end={{t_end}}", "solver.wall_time=100000"])
times, lr = [], None
for _ in range(repeats):
    t0 = time.perf_counter()
    lr = run_scenario(sc, "mykhailevych2020", solver=method)
    times.append((time.perf_counter() - t0) * 1e3)
r = lr.result
np.savez(out, t=r.t, **{{k: r[k] for k in {SPEEDS!r}}})
print(json.dumps({{"times_ms": times, "status": r.status, "rhs_evals": r.stats.rhs_evals}}))
"""


def scipy_baseline(method, repeats, t_end, rhs, timeout):
    env = dict(os.environ)
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "speeds.npz")
        try:
            done = subprocess.run([sys.executable, "-c", _CHILD, method, str(repeats),
                                   str(t_end), out], capture_output=True, text=True,
                                  env=env, timeout=timeout, check=True)
        except subprocess.TimeoutExpired:
            return None, None, f"did not finish within {timeout:g} s"
        except subprocess.CalledProcessError as exc:
            return None, None, "failed: " + exc.stderr.strip().splitlines()[-1]
        info = json.loads(done.stdout.strip().splitlines()[-1])
        return info, dict(np.load(out)), ""


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--scipy-repeats", type=int, default=5)
    ap.add_argument("--t-end", type=float, default=4.0)
    ap.add_argument("--scipy-rhs", choices=("numba",), default="numba")
    ap.add_argument("--scipy-timeout", type=float, default=1800.0)
    a = ap.parse_args()
    from clutchsim.driveline.run import run_scenario
    from clutchsim.scenario import load_scenario
    sc = load_scenario(None, overrides=[f"scenario.t_end={a.t_end}"])
    ms, lr = median_ms(lambda: run_scenario(sc, "mykhailevych2020"), repeats=a.repeats)
    ref = lr.result
    out = {"problem": f"default launch, model (6), 0-{a.t_end:g} s, rtol=atol=1e-8",
           "clutchsim_ms": ms, "clutchsim_status": ref.status,
           "clutchsim_rhs_evals": ref.stats.rhs_evals, "scipy_rhs": a.scipy_rhs}
    diffs = []
    for method, key in (("scipy-rk45", "rk45"), ("scipy-lsoda", "lsoda")):
        info, sp, why = scipy_baseline(method, a.scipy_repeats, a.t_end, a.scipy_rhs,
                                       a.scipy_timeout)
        if info is None:
            out[f"scipy_{key}_ms"] = None
            out[f"ratio_vs_{key}"] = None
            out[f"scipy_{key}_note"] = why
            print(f"scipy {key}: {why}", file=sys.stderr)
            continue
        out[f"scipy_{key}_ms"] = float(np.median(info["times_ms"]))
        out[f"scipy_{key}_runs"] = len(info["times_ms"])
        out[f"scipy_{key}_status"] = info["status"]
        out[f"ratio_vs_{key}"] = out[f"scipy_{key}_ms"] / ms
        d = max(float(np.max(np.abs(np.interp(ref.t, sp["t"], sp[s]) - ref[s])))
                for s in SPEEDS) * 30 / np.pi
        out[f"max_abs_speed_diff_rpm_{key}"] = d
        diffs.append(d)
    out["max_abs_speed_diff_rpm"] = max(diffs) if diffs else None
    emit(out)


if __name__ == "__main__":
    main()
