"""The real-time kernel on a fuzzed set of launches: no mode chatter, no failure.

The default launch (examples/launch.toml, model (6) with its clamp reset) exported with
``clutchsim rt`` at ``--step`` (1 ms) for each vehicle mass of ``MASSES`` and road grade of
``GRADES`` (structural values: one export each), then driven on each export with
``--count``/(masses·grades) random command profiles (seeded): the clutch engaged by a ramp
of 0.05-2 s (0.05 s: a clutch dump) starting at 0.1-1 s, the throttle held at 5-80 % or
ramped between two such levels.  Each run is 4 s.

Counted per run: the status (a stalled engine stops the run: counted, not a failure of the
kernel), the clutch's events (slip reversals, where model (6)'s reset acts), and **mode
chatter**: a clutch event in each of ``CHATTER_STEPS`` (5) consecutive steps, a slip that
reverses at every step (the switching that a fixed-step kernel with a switching law shows
at lock-up).  Failures: a status of 2 (a singular matrix or a value that is not finite).
The last line of stdout is the JSON result.
"""

from __future__ import annotations

import argparse
import shutil
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from _common import emit

MASSES = (900.0, 1300.0, 1800.0, 2500.0)
GRADES = (-5.0, 0.0, 6.0, 12.0, 20.0)
CHATTER_STEPS = 5


def _commands(rng, t):
    t0 = rng.uniform(0.1, 1.0)
    dur = rng.uniform(0.05, 2.0)
    clutch = np.clip((t - t0) / dur, 0.0, 1.0)
    a, b = rng.uniform(0.05, 0.8, size=2)
    if rng.random() < 0.5:
        b = a
    throttle = a + (b - a) * np.clip(t / 4.0, 0.0, 1.0)
    return np.column_stack([clutch, throttle]), {"clutch_start_s": t0, "engage_s": dur,
                                                 "throttle": (a, b)}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--count", type=int, default=10_000)
    ap.add_argument("--step", type=float, default=1e-3)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args(argv)
    from clutchsim.fmu.realtime import RealtimeKernel, export_realtime
    rng = np.random.default_rng(args.seed)
    per = max(1, args.count // (len(MASSES) * len(GRADES)))
    n = round(4.0 / args.step)
    t = np.arange(n) * args.step
    work = Path(tempfile.mkdtemp(prefix="rt_fuzz."))
    tally = {"runs": 0, "completed": 0, "stalled": 0, "failed": 0, "chatter": 0,
             "events_max": 0, "events_median": 0.0}
    examples = []
    events = []
    t_start = time.perf_counter()
    try:
        for mass in MASSES:
            for grade in GRADES:
                d = work / f"m{mass:g}_g{grade:g}"
                export_realtime(None, d, step=args.step,
                                overrides=[f"vehicle.mass={mass}", f"vehicle.grade={grade}"])
                k = RealtimeKernel(d)
                order = ("w_slip_clutch", "omega_engine")
                for _ in range(per):
                    u, about = _commands(rng, t)
                    rec, status = k.run(u, record=order)
                    tally["runs"] += 1
                    w = rec[:, 0][~np.isnan(rec[:, 0])]
                    flips = np.signbit(w[1:]) != np.signbit(w[:-1])
                    events.append(int(flips.sum()))
                    run = 0
                    chatter = False
                    for f in flips:
                        run = run + 1 if f else 0
                        if run >= CHATTER_STEPS:
                            chatter = True
                            break
                    if status == 2:
                        tally["failed"] += 1
                    elif status in (1, 3):
                        tally["stalled"] += 1
                    else:
                        tally["completed"] += 1
                    if chatter:
                        tally["chatter"] += 1
                    if (chatter or status == 2) and len(examples) < 5:
                        examples.append({"mass": mass, "grade": grade, "status": status,
                                         **about})
    finally:
        shutil.rmtree(work, ignore_errors=True)
    tally["events_max"] = int(max(events))
    tally["events_median"] = float(np.median(events))
    emit({"benchmark": "rt_fuzz", "step_s": args.step, "seed": args.seed,
          "masses_kg": MASSES, "grades_pct": GRADES, "chatter_steps": CHATTER_STEPS,
          **tally, "examples": examples, "wall_s": time.perf_counter() - t_start})
    return 0


if __name__ == "__main__":
    sys.exit(main())
