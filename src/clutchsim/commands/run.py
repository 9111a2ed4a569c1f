"""``clutchsim run``: simulate a driveline scenario with one or several friction models."""

from __future__ import annotations

import argparse
import logging
import sys

from ..cli import SimulationFailed, UserError, emit_json

log = logging.getLogger("clutchsim")

HELP = """\
examples:
  clutchsim run --out launch/                          # the default passenger-car launch
  clutchsim run examples/hill_start.toml --out hill/ --json
  clutchsim run examples/launch.toml --model coulomb-robust --model coulomb-naive --out cmp/
  clutchsim run examples/launch.toml --set vehicle.grade=12 --out steep/

outputs in DIR: timeseries.csv and timeseries.parquet (first model; one file per model with
several), summary.json {"models": {NAME: {metric: value}}}, launch_<model>.png and, with
several models, comparison.png.  DIR is written as DIR.partial and renamed when complete.
"""


def register(sub, common):
    p = sub.add_parser("run", parents=[common], help="simulate a driveline scenario",
                       description="Simulate a driveline scenario (TOML) and write time "
                       "series, metrics and figures.", epilog=HELP,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("scenario", nargs="?", help="scenario TOML (default: the packaged launch)")
    p.add_argument("--model", action="append", default=None,
                   help="friction model of the clutch element (repeatable)")
    p.add_argument("--set", action="append", default=[], metavar="PATH=VALUE",
                   help="override a scenario key, e.g. vehicle.grade=12")
    p.add_argument("--out", required=True, metavar="DIR", help="output directory")
    p.add_argument("--no-plots", action="store_true", help="skip the figures")
    p.add_argument("--json", action="store_true", help="print summary.json on stdout")


def run(args) -> int:
    from ..core.result import atomic_directory
    from ..driveline.outputs import write_runs
    from ..progress import progress_for
    from ..report import build_report
    from ..scenario import load_scenario
    sc = load_scenario(args.scenario, overrides=args.set)
    models = args.model or list(sc.models) or [None]
    with atomic_directory(args.out) as part:
        summary = write_runs(sc, models, part, plots=not args.no_plots,
                             progress=progress_for(args, "models"))
        (part / "command.txt").write_text(" ".join(["clutchsim", *sys.argv[1:]]) + "\n")
        build_report(part)
    if args.json:
        emit_json(summary)
    failed = [n for n, m in summary["models"].items() if not m["completed"]]
    if failed and len(models) == 1:
        raise SimulationFailed(summary["models"][failed[0]]["message"])
    return 0


__all__ = ["UserError", "register", "run"]
