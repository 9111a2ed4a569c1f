"""Run every example scenario through the public runner and store what it produced, or
compare two such stores bit for bit (a behaviour-preserving change must leave every array
identical).

    PYTHONPATH=<tree>/src python scripts/compare_examples.py run OUT
    python scripts/compare_examples.py diff OUT_A OUT_B

``run`` runs each scenario file under examples/ (and the packaged default launch) once per
model it lists (else with its own model) and writes, per run, ``<name>.npz`` (the output
times and every output array) and one ``runs.json`` (lock-up time, the located events and
the outcome of each run).  ``diff`` says which runs differ, and exits 1 if any does.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]


def scenario_files() -> list[Path | None]:
    """The packaged default (None) and every example file that is a scenario."""
    return [None, *sorted((REPO / "examples").rglob("*.toml"))]


def _run(out: Path) -> int:
    from clutchsim import run_scenario
    from clutchsim.scenario import ScenarioError, load_scenario
    out.mkdir(parents=True, exist_ok=True)
    runs = {}
    for path in scenario_files():
        label = "default" if path is None else str(path.relative_to(REPO / "examples"))
        try:
            sc = load_scenario(path)
        except ScenarioError as exc:
            print(f"skip {label}: {exc}", file=sys.stderr)
            continue
        for model in sc.models or (None,):
            key = f"{label}:{model or 'own'}"
            t0 = time.perf_counter()
            lr = run_scenario(sc, model)
            res = lr.result
            arrays = {"t": np.asarray(res.t)}
            arrays.update({f"s:{n}": np.asarray(res[n]) for n in res.data})
            name = key.replace("/", "__").replace(":", "__")
            np.savez(out / f"{name}.npz", **arrays)
            runs[key] = {"file": f"{name}.npz", "outcome": str(res.outcome),
                         "lockup_time_s": lr.metrics.get("lockup_time_s"),
                         "events": [[e.t, e.name, e.action, e.source] for e in res.events],
                         "signals": list(res.data)}
            print(f"{key}: {res.outcome}, {len(res.t)} rows, "
                  f"{time.perf_counter() - t0:.1f} s", file=sys.stderr)
    (out / "runs.json").write_text(json.dumps(runs, indent=1, default=str), encoding="utf-8")
    print(f"{len(runs)} runs stored in {out}")
    return 0


def _diff(a: Path, b: Path) -> int:
    ra = json.loads((a / "runs.json").read_text(encoding="utf-8"))
    rb = json.loads((b / "runs.json").read_text(encoding="utf-8"))
    same, bad = 0, []
    for key in sorted(set(ra) | set(rb)):
        if key not in ra or key not in rb:
            bad.append(f"{key}: only in {'A' if key in ra else 'B'}")
            continue
        x, y = ra[key], rb[key]
        problems = [f"{k} {x[k]!r} != {y[k]!r}" for k in ("outcome", "lockup_time_s",
                                                          "events", "signals")
                    if x[k] != y[k]]
        with np.load(a / x["file"]) as za, np.load(b / y["file"]) as zb:
            if set(za.files) != set(zb.files):
                problems.append("different arrays")
            for name in sorted(set(za.files) & set(zb.files)):
                if za[name].shape != zb[name].shape or \
                        za[name].tobytes() != zb[name].tobytes():
                    problems.append(f"{name} differs")
        if problems:
            bad.append(f"{key}: " + "; ".join(problems[:5]))
        else:
            same += 1
    for line in bad:
        print(line)
    print(f"{same} of {len(set(ra) | set(rb))} runs bit-identical")
    return 1 if bad else 0


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = p.add_subparsers(dest="cmd", required=True)
    sub.add_parser("run").add_argument("out", type=Path)
    d = sub.add_parser("diff")
    d.add_argument("a", type=Path)
    d.add_argument("b", type=Path)
    args = p.parse_args(argv)
    return _run(args.out) if args.cmd == "run" else _diff(args.a, args.b)


if __name__ == "__main__":
    sys.exit(main())
