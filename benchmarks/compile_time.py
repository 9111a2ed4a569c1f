"""Compile time: an empty cache, a new topology, and a second process (issue 14).

Every measurement runs in a fresh interpreter whose ``NUMBA_CACHE_DIR`` is one temporary
directory, so the steps build on each other exactly as a user's first day does:

1. ``empty_cache``: the default launch (``examples/launch.toml``, model (6)) with nothing
   compiled: the integrators, the friction kernels, the metrics kernel and the launch's
   generated plant compile;
2. ``new_topology``: each scenario of ``--scenario`` (default: ElasticBearing,
   SimpleGearShift, CoupledClutches, the dual-mass-flywheel launch and the closed-loop
   launch), a network the cache has not seen, with everything shared already cached: only
   its generated plant compiles (the integrators are shared through function values);
3. ``second_process``: the same scenario again in a new process: the plant is loaded from
   the cache.

For each: ``import_s`` (``import clutchsim``), ``first_run_s`` (scenario build and the first
``run_scenario``, compilation or loading included) and ``warm_run_s`` (the same run again in
that process: what compiling cost is ``first_run_s − warm_run_s``).  Targets (issue 14): the
first compilation of a new topology ≤ 15 s, a second process loads it in ≤ 1 s.

Prints one JSON object on the last stdout line.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from _common import emit

REPO = Path(__file__).resolve().parents[1]
DEFAULT_SCENARIOS = ("elastic_bearing", "simple_gear_shift", "coupled_clutches", "launch_dmf",
                     "launch_closed_loop")

_CHILD = r"""
import json, sys, time
t0 = time.perf_counter()
import clutchsim
from clutchsim.scenario import run_scenario
t1 = time.perf_counter()
path = sys.argv[1]
r = run_scenario(path)
t2 = time.perf_counter()
run_scenario(path)
t3 = time.perf_counter()
print(json.dumps({"import_s": t1 - t0, "first_run_s": t2 - t1, "warm_run_s": t3 - t2,
                  "completed": bool(r.metrics["completed"])}))
"""


def _child(scenario: str, cache: str) -> dict:
    env = dict(os.environ, NUMBA_CACHE_DIR=cache)
    done = subprocess.run([sys.executable, "-c", _CHILD, scenario], capture_output=True,
                          text=True, env=env, cwd=REPO, check=False)
    if done.returncode != 0:
        raise SystemExit(f"{scenario}: the child process failed:\n{done.stderr[-2000:]}")
    return json.loads(done.stdout.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenario", action="append", default=None, metavar="NAME",
                    help="an example's name (examples/NAME.toml); repeatable")
    a = ap.parse_args()
    names = a.scenario or list(DEFAULT_SCENARIOS)
    for name in names:
        if not (REPO / "examples" / f"{name}.toml").is_file():
            raise SystemExit(f"--scenario {name!r}: no examples/{name}.toml")
    out: dict = {"load_before": os.getloadavg()}
    with tempfile.TemporaryDirectory(prefix="clutchsim-compile-") as cache:
        out["empty_cache"] = _child(str(REPO / "examples" / "launch.toml"), cache)
        print(f"empty cache, default launch: {out['empty_cache']}", file=sys.stderr)
        rows = {}
        for name in names:
            path = str(REPO / "examples" / f"{name}.toml")
            first = _child(path, cache)
            second = _child(path, cache)
            rows[name] = {"new_topology": first, "second_process": second}
            print(f"{name}: new {first}, second {second}", file=sys.stderr)
        out["topologies"] = rows
    firsts = [r["new_topology"]["first_run_s"] for r in rows.values()]
    seconds = [r["second_process"]["first_run_s"] for r in rows.values()]
    out.update(max_new_topology_s=max(firsts), max_second_process_s=max(seconds),
               target_new_topology_s=15.0, target_second_process_s=1.0)
    emit(out)


if __name__ == "__main__":
    main()
