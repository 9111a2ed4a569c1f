"""Calibration from logs against a known truth: recovery errors, interval coverage, time.

Each trial makes a synthetic log of ``--launches`` launches (``clutchsim.identify.synthetic``:
mixed rates 25/17/50 Hz, quantisation, noise, late stamps; seed = trial number), maps it with
``examples/calibration/channels.toml``, and calibrates it with
``examples/calibration/launch_calibration.toml`` (6 parameters).  Reported per parameter:
the median and largest relative error, the share of trials whose interval holds the truth
(coverage, target ≥ 90 % of the 95 % intervals), and the median interval half-width; and the
median and largest wall time per calibration.  ``--model-error MU_RISE`` makes the truth with
a friction coefficient that rises with slip (the fitted model is Coulomb).

    PYTHONPATH=src .venv/bin/python benchmarks/calibration_coverage.py --trials 50

Prints one JSON object on the last stdout line.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

from clutchsim.data.channels import load_channel_map, map_log
from clutchsim.identify.calibrate import calibrate, load_calibration
from clutchsim.identify.synthetic import synthetic_log

#: the issue's recovery targets: relative for capacity and stiffness, absolute [m] for the
#: touch point
TARGETS = {"capacity": ("rel", 0.05), "touch_point": ("abs", 0.0003),
           "stiffness": ("rel", 0.10)}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--trials", type=int, default=50)
    ap.add_argument("--launches", type=int, default=3)
    ap.add_argument("--model-error", type=float, default=0.0, metavar="MU_RISE")
    ap.add_argument("--first-seed", type=int, default=0)
    args = ap.parse_args()
    cmap = load_channel_map(ROOT / "examples/calibration/channels.toml")
    spec = load_calibration(ROOT / "examples/calibration/launch_calibration.toml")
    rows = []
    for seed in range(args.first_seed, args.first_seed + args.trials):
        log, truth = synthetic_log(launches=args.launches, seed=seed,
                                   truth={"mu_rise": args.model_error})
        t0 = time.perf_counter()
        res = calibrate(spec, [map_log(log, cmap)])
        wall = time.perf_counter() - t0
        rows.append((res, truth["parameters"], wall))
        print(f"seed {seed}: {wall:.2f} s " + " ".join(
            f"{n}={res.parameters[n]:.5g}" for n in res.names), file=sys.stderr)
    out = {"trials": args.trials, "launches": args.launches, "model_error": args.model_error,
           "parameters": {}}
    for n in rows[0][0].names:
        est = np.array([r.parameters[n] for r, _, _ in rows])
        true = np.array([t[n] for _, t, _ in rows])
        ivs = [r.intervals[n] for r, _, _ in rows]
        inside = [iv is not None and iv[0] <= tv <= iv[1] for iv, tv in zip(ivs, true)]
        err = est - true
        rel = np.abs(err / true)
        entry = {"median_rel_error": float(np.median(rel)), "max_rel_error": float(rel.max()),
                 "median_abs_error": float(np.median(np.abs(err))),
                 "max_abs_error": float(np.max(np.abs(err))),
                 "bias": float(np.mean(err)),
                 "coverage": float(np.mean(inside)),
                 "median_half_width": float(np.median([(iv[1] - iv[0]) / 2 for iv in ivs
                                                       if iv is not None]))}
        if n in TARGETS:
            kind, limit = TARGETS[n]
            within = (rel if kind == "rel" else np.abs(err)) <= limit
            entry["within_target"] = float(np.mean(within))
            entry["target"] = f"{limit:g}" + (" relative" if kind == "rel" else " m")
        out["parameters"][n] = entry
    walls = [w for _, _, w in rows]
    out["wall_s_median"] = float(np.median(walls))
    out["wall_s_max"] = float(np.max(walls))
    print(json.dumps(out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
