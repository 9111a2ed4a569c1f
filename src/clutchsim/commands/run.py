"""``clutchsim run``: simulate a driveline scenario with one or several friction models."""

from __future__ import annotations

import logging

from ._common import (
    SimulationFailed,
    UserError,
    add_limit_flags,
    add_option_flag,
    add_output_flags,
    checked_scenario,
    command_parser,
    emit_json,
    scenario_with_options,
    write_command,
)

log = logging.getLogger("clutchsim")

HELP = """\
examples:
  clutchsim run --out launch/                          # the default passenger-car launch
  clutchsim run examples/hill_start.toml --out hill/ --json
  # exit 1: chatter detection stops the naive model at lock-up (cmp/ holds both runs)
  clutchsim run examples/launch.toml --model coulomb-robust --model coulomb-naive --out cmp/
  clutchsim run examples/launch.toml --set vehicle.grade=12 \
      --set 'inputs.throttle="0.1 + ramp(0.3, 0.5, 0.5)"' --out steep/   # 12 %: more throttle
  clutchsim run examples/launch.toml --option rtol=1e-8 --option wall_time=30 --out tight/
  clutchsim run examples/one_way_clutch.toml --out owc/ --json   # not a launch: its summary

outputs in DIR: timeseries.csv and timeseries.parquet (first model; one file per model with
several), summary.json, the figures, command.txt and report.html, and
.clutchsim-output.json (the manifest: kind and files).  A launch (the scenario's clutch
element is a friction clutch, and the network has a vehicle or an engine) gets
summary.json {"models": {MODEL: {"outcome", "warnings", metric: value}}, "failed":
[MODEL, ...]}, launch_<model>.png and, with several models, comparison.png.  A
scenario with faults adds "faults": [{"component", "kind", "fault", "time_s"}, ...] (what
fails, when it struck in the first model's run: null for a temperature-triggered fault
that never did; docs/components.md, faults).  Any other
network gets summary.json {"runs": {LABEL: {"outcome", "warnings", "speeds",
"energies", "friction_elements", "temperatures", "located_events", ...}}, "failed": [LABEL,
...]} and network_<label>.png; LABEL is the scenario's name, or the model's where several
models are compared (docs/outputs.md lists every key).  DIR is written
as DIR.partial and put in place when complete; Ctrl-C or SIGTERM removes DIR.partial.
An existing DIR is replaced only when it is empty or holds an earlier `clutchsim run`
output; clutchsim never deletes a file it did not write (--force: write beside them).

Every model is checked (its parameters, and the output size against --max-output-rows)
before the first one runs.  exit status: 0 every model completed, 1 any did not (the JSON
says which: "failed", and each model's "outcome"), 2 bad input.
"""


def register(sub, common):
    p = command_parser(sub, common, "run", help="simulate a driveline scenario",
                       description="Simulate a driveline scenario (TOML) and write time "
                       "series, metrics and figures.", epilog=HELP, scenario=True)
    p.add_argument("--model", action="append", default=None,
                   help="friction model of the clutch element (repeatable)")
    p.add_argument("--set", action="append", default=[], metavar="PATH=VALUE",
                   help="override a scenario key, e.g. vehicle.grade=12")
    add_option_flag(p, what="every model's run")
    add_output_flags(p, json_help="print summary.json on stdout")
    add_limit_flags(p)


def run(args) -> int:
    from .._util import claim_output_dir
    with claim_output_dir(args.out, "run", force=args.force) as out:
        return _run(args, out)


def _run(args, out) -> int:
    import json

    from .._util import atomic_write
    from ..progress import progress_for
    from ..report import build_report
    from ..scenario import load_scenario
    from ..scenario.outputs import write_runs
    sc = scenario_with_options(load_scenario(args.scenario, overrides=args.set), args.option)
    models = args.model or list(sc.models) or [None]
    if len(set(models)) != len(models):
        raise UserError(f"--model: listed twice: {', '.join(str(m) for m in models)}")
    for m in models:   # every model is checked before any runs
        sc = checked_scenario(sc, m, args.max_output_rows)
    bar = progress_for(args, "models", tick=1.0)
    try:
        with out.build() as part:
            summary = write_runs(sc, models, part, plots=not args.no_plots, progress=bar)
            summary["failed"] = [n for n, m in _runs(summary).items() if not m["completed"]]
            atomic_write(part / "summary.json", lambda p: p.write_text(
                json.dumps(summary, indent=2, allow_nan=False, default=float)))
            write_command(part, args.argv)
            build_report(part)
    finally:
        if bar is not None:
            bar.close()
    if args.json:
        emit_json(summary)
    failed = summary["failed"]
    if failed:
        m = _runs(summary)
        if len(models) == 1:
            raise SimulationFailed(m[failed[0]]["message"])
        raise SimulationFailed(f"{len(failed)} of {len(models)} models did not complete: "
                               + "; ".join(f"{n} ({m[n]['outcome']}): {m[n]['message']}"
                                           for n in failed))
    return 0


def _runs(summary: dict) -> dict:
    """The runs of a summary: a launch's ``models``, any other network's ``runs``."""
    return summary["models"] if "models" in summary else summary["runs"]


__all__ = ["UserError", "register", "run"]
