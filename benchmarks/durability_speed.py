"""Time the 1,000-cycle accelerated durability study (issue 21: <= 60 s on this machine).

examples/durability/passenger_car.toml (ten launches per cycle), 1,000 cycles,
accelerated: the median wall time of 5 runs after a warm-up (the compile), and the number of cycles it
simulated.  Baseline in the same run: the full cycle-by-cycle mode on the first 50 cycles
(median of 3), scaled to 1,000 cycles (its cost per cycle is constant), and the wear both
give after 50 cycles.  Prints one JSON object on the last line of stdout.

Run from the repository root: ``.venv/bin/python benchmarks/durability_speed.py``.
"""

from __future__ import annotations

import json
import statistics
import time
from pathlib import Path

from clutchsim.studies.durability import load_duty, run_durability

DUTY = Path(__file__).resolve().parents[1] / "examples" / "durability" / "passenger_car.toml"


def _time(fn, n):
    out, times = None, []
    for _ in range(n):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def main() -> None:
    duty = load_duty(DUTY)
    run_durability(duty, 3, accelerated=False)           # warm-up: compile and load
    t_acc, acc = _time(lambda: run_durability(duty, 1000, accelerated=True), 5)
    t_full50, full50 = _time(lambda: run_durability(duty, 50, accelerated=False), 3)
    acc50 = run_durability(duty, 50, accelerated=True)
    doc = {"benchmark": "durability_speed", "cycles": 1000, "accelerated_s": t_acc,
           "simulated_cycles": acc.simulated_cycles, "target_s": 60.0,
           "full_50_cycles_s": t_full50, "full_1000_cycles_estimate_s": t_full50 * 20,
           "ratio_vs_full_estimate": t_full50 * 20 / t_acc,
           "wear_mm_1000": acc.wear_m * 1e3,
           "wear_rel_diff_50_cycles": acc50.wear_m / full50.wear_m - 1.0}
    print(f"1,000 cycles accelerated: {t_acc:.2f} s, {acc.simulated_cycles} cycles simulated; "
          f"full mode {t_full50 / 50 * 1e3:.0f} ms per cycle")
    print(json.dumps(doc))


if __name__ == "__main__":
    main()
