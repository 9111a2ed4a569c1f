"""Fuzz the network plant: ``python scripts/fuzz_networks.py --count 2000 --seed 1``.

Generates random valid networks (``tests/network/_fuzz.py``: 2-6 inertias, clutches and
brakes with every friction model, springs, lash, ideal and lossy gears, one-way clutches,
torque sources and commands that start at 0, cross 0, step, ramp and oscillate), runs each
and checks the physics invariants, the energy balance and the agreement with a tight
rerun (a network that amplifies tolerance-level errors, where a tight run from initial
speeds perturbed by the loose tolerance, the loose run at 1.25 times its tolerance or the
tight run against a tighter one moves as far, is counted as sensitive, not as a problem:
tests/network/_fuzz.py).  Prints one line per problem and per sensitive
network and a summary (networks run, refused with a clear error, outcomes, problems,
sensitive); exit 1 when any problem was found.
"""

from __future__ import annotations

import argparse
import collections
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "network"))

import _fuzz
import numpy as np
from hypothesis import HealthCheck, Phase, given, seed, settings


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--count", type=int, default=2000, help="networks to run")
    ap.add_argument("--seed", type=int, default=1, help="hypothesis seed")
    ap.add_argument("--variants", type=int, default=10,
                    help="runs per topology (other inertias, speeds and torques on the "
                         "same compiled plant)")
    args = ap.parse_args()
    tally: collections.Counter = collections.Counter()
    problems = []
    sensitive = []      # networks whose final state depends on the tolerance (_fuzz)
    t0 = time.perf_counter()

    rng = np.random.default_rng(args.seed)
    topologies = -(-args.count // max(args.variants, 1))

    @seed(args.seed)
    @settings(max_examples=topologies, deadline=None, database=None,
              suppress_health_check=list(HealthCheck), phases=[Phase.generate])
    @given(_fuzz.cases())
    def one(case):
        for k in range(max(args.variants, 1)):
            if sum(tally.values()) >= args.count:
                return
            c = case if k == 0 else _fuzz.variant(case, rng)
            try:
                res = _fuzz.run(c, _fuzz.LOOSE)
                tally[str(res.outcome)] += 1
            except _fuzz.NetworkError:
                tally["refused"] += 1
                return
            notes: list = []
            found = _fuzz.check_run(c, res, notes)
            if notes:
                sensitive.append(c)
                print(f"SENSITIVE {notes}\n{c!r}\n", flush=True)
            if found:
                problems.append((c, found))
                print(f"PROBLEM (the run: {res.outcome} at t = {res.t[-1]:.9g} s) {found}\n"
                      f"{c!r}\n", flush=True)
            n = sum(tally.values())
            if n % 50 == 0:
                print(f"{n} networks, {len(problems)} problems, "
                      f"{time.perf_counter() - t0:.0f} s", file=sys.stderr, flush=True)

    one()
    n = sum(tally.values())
    print(f"{n} networks in {time.perf_counter() - t0:.0f} s (seed {args.seed}): "
          + ", ".join(f"{k} {v}" for k, v in sorted(tally.items()))
          + f"; {len(problems)} with problems; {len(sensitive)} sensitive (they amplify "
          "tolerance-level errors: not counted)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
