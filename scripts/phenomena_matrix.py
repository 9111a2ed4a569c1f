#!/usr/bin/env python
"""Measure which friction phenomena every model shows and write the docs from the numbers.

    python scripts/phenomena_matrix.py                # measure all models, write the docs
    python scripts/phenomena_matrix.py --render-only  # re-render the docs from the JSON
    python scripts/phenomena_matrix.py --reclassify   # re-apply the rules to the JSON metrics
    python scripts/phenomena_matrix.py --check        # exit 1 if the docs differ from the JSON
    python scripts/phenomena_matrix.py --new          # measure only the models the JSON lacks

Measuring runs the benchmarks curves, drift, breakaway, presliding and lag on each
registered friction model with its default parameter set
(:func:`clutchsim.benchmarks.phenomena.measure_model`), classifies the metrics, and writes

* ``docs/phenomena.json``: the measured metrics, verdicts, thresholds, literature
  expectation, clutchsim version and date;
* ``docs/phenomena.md``: the matrix, the comparison with the literature and the rules;
* the ``## Phenomena`` section of every ``docs/models/<name>.md`` (between the generated
  markers; the rest of each page is left as it is).

The Markdown is a pure function of the JSON, so ``--render-only`` and the tests rebuild it
without simulating.  ``--reclassify`` keeps the measured metrics (and their version and
date) but rebuilds the verdicts, literature and notes with the current code, for a change
of the rules or of the texts that needs no new measurement.  ``--new`` measures only the
registered models the JSON does not have yet (a new model: docs/models/README.md) and adds
them, keeping the other models' measured metrics, version and date.  Every file is written atomically.  The first run compiles the rig
kernels (tens of seconds per model); later runs load them from numba's cache.
"""

from __future__ import annotations

import argparse
import datetime
import json
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

from clutchsim import __version__
from clutchsim._util import atomic_write
from clutchsim.benchmarks.phenomena import (
    build_report,
    measure_model,
    metrics_from_report,
    render_matrix,
    render_pages,
)
from clutchsim.friction import MODELS

DOCS = ROOT / "docs"


def measure_all(models, solver: str = "rodas4") -> list:
    """Metrics of every model in ``models``, with progress on stderr."""
    out = []
    for name in models:
        t0 = time.perf_counter()
        metrics = measure_model(name, solver=solver)
        status = ", ".join(f"{b}: {m.status}" for b, m in metrics.benchmarks.items())
        print(f"{name:20s} {time.perf_counter() - t0:6.1f} s  {status}", file=sys.stderr,
              flush=True)
        out.append(metrics)
    return out


def rendered(data: dict, docs: Path) -> dict[Path, str]:
    """Path -> text of every generated Markdown file (pure given the current pages)."""
    pages = {p.stem: p.read_text(encoding="utf-8") for p in sorted((docs / "models").glob("*.md"))}
    out = {docs / "phenomena.md": render_matrix(data)}
    out.update({docs / "models" / f"{name}.md": text
                for name, text in render_pages(data, pages).items()})
    return out


def write_text(path: Path, text: str) -> None:
    """Write ``text`` to ``path`` atomically (UTF-8, Unix newlines)."""
    atomic_write(path, lambda tmp: tmp.write_text(text, encoding="utf-8", newline="\n"))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    mode = ap.add_mutually_exclusive_group()
    mode.add_argument("--render-only", action="store_true",
                      help="re-render the Markdown from the existing JSON (no simulation)")
    mode.add_argument("--reclassify", action="store_true",
                      help="re-apply the current rules and texts to the metrics in the JSON "
                           "(no simulation), then write the JSON and the docs")
    mode.add_argument("--check", action="store_true",
                      help="exit 1 if a generated file differs from what the JSON gives")
    mode.add_argument("--new", action="store_true",
                      help="measure only the registered models the JSON lacks and add them")
    ap.add_argument("--docs", type=Path, default=DOCS, help="docs directory (default: %(default)s)")
    args = ap.parse_args(argv)
    json_path = args.docs / "phenomena.json"

    if args.render_only or args.check or args.reclassify or args.new:
        data = json.loads(json_path.read_text(encoding="utf-8"))
    if args.reclassify or args.new:
        metrics = [metrics_from_report(data, model) for model in data["models"]]
        if args.new:
            metrics += measure_all([m for m in MODELS if m not in data["models"]],
                                   solver=data["solver"])
        data = build_report(metrics, version=data["clutchsim_version"], date=data["date"],
                            solver=data["solver"])
    elif not (args.render_only or args.check):
        metrics = measure_all(MODELS)
        data = build_report(metrics, version=__version__,
                            date=datetime.datetime.now(datetime.UTC).date().isoformat())
    if not (args.render_only or args.check):
        write_text(json_path, json.dumps(data, indent=1, ensure_ascii=False, allow_nan=False)
                   + "\n")
        print(f"wrote {json_path}", file=sys.stderr)

    stale = []
    for path, text in rendered(data, args.docs).items():
        if path.exists() and path.read_text(encoding="utf-8") == text:
            continue
        if args.check:
            stale.append(path)
        else:
            write_text(path, text)
            print(f"wrote {path}", file=sys.stderr)
    if stale:
        print("out of date (run scripts/phenomena_matrix.py --render-only): "
              + ", ".join(str(p) for p in stale), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
