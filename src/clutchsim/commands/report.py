"""``clutchsim report DIR``: (re)build the self-contained HTML report of an output directory."""

from __future__ import annotations

from pathlib import Path

from ._common import UserError, command_parser, emit_json

HELP = """\
examples:
  clutchsim bench drift --model lugre --out drift/   # any output directory of clutchsim
  clutchsim report drift/                      # rebuild drift/report.html, print its path
  clutchsim report drift/ --title "Drift, LuGre" --json    # {"report": "drift/report.html"}
  clutchsim run examples/launch.toml --out launch/
  clutchsim report launch/ --interactive       # zoom, hover, linked time axes (Bokeh)
  clutchsim sweep examples/launch.toml --vary vehicle.mass=1100:1700:3 \\
      --vary vehicle.grade=0:6:3 --out mass_grade/
  clutchsim report mass_grade/ --interactive   # a sweep: linked scatter panels, heat maps

The report is one HTML file (figures embedded, no network access, opens from disk) with the
status and warnings, metrics, parameters, scenario, solver statistics, figures and a list
of the data files of DIR.  With --interactive its figures become interactive (zoom, pan,
hover values with units, series toggled from the legend), drawn from the data files of
DIR (nothing is simulated again): for a run, the time series (linked time axes, a lock-up
zoom panel, the models overlaid); a sweep, every metric against every swept parameter
(a box or lasso selection shared by all panels), histograms with their CDF and, for a 2-D
grid, heat maps; a UQ study, distributions with p05/p50/p95, Sobol' or Morris indices with
their intervals, convergence; a durability study, temperature, work, wear, clamp force
and capacity per start; a judder analysis, the modes, the stability map and the frequency
response; a fit, measured, simulated and residual against time.  Bokeh is inlined: still
one file that opens offline (~2.1 MB for a default run); needs the extra
clutchsim[explore].  Other directories get the static report.  See docs/report.md and
docs/explore.md.
"""


def register(sub, common):
    p = command_parser(sub, common, "report", help="rebuild the HTML report of a directory",
                       description="Write DIR/report.html from the JSON, TOML, PNG and data "
                       "files in an output directory.", epilog=HELP)
    p.add_argument("dir", metavar="DIR", help="output directory of run/bench/sweep/fit")
    p.add_argument("--title", help="page title (default: from the directory kind)")
    p.add_argument("--interactive", action="store_true",
                   help="interactive figures (Bokeh, inlined): a run's time series, a "
                   "sweep, UQ, durability, judder or fit study's figures")
    p.add_argument("--json", action="store_true", help='print {"report": PATH}')


def run(args) -> int:
    from .._util import add_to_manifest
    from ..report import build_report
    from ..report.gather import REPORT_NAME, check_output, report_inputs
    d = Path(args.dir)
    if not d.exists():
        raise UserError(f"DIR {args.dir!r} does not exist (give an output directory of "
                        "clutchsim run/bench/sweep/fit)")
    if not d.is_dir():
        raise UserError(f"DIR {args.dir!r} is a file, not an output directory")
    if not report_inputs(d):
        raise UserError(f"DIR {args.dir!r} is empty: nothing to report (run clutchsim "
                        "run/bench/fit with --out first)")
    try:
        check_output(d)
    except ValueError as exc:
        raise UserError(f"DIR {exc}") from None
    if args.interactive:
        try:
            from ..plot.interactive import require_bokeh
            require_bokeh()
        except ModuleNotFoundError as exc:
            raise UserError(str(exc)) from None
        from ..report.interactive import build_interactive_report
        path = build_interactive_report(d, title=args.title)
    else:
        path = build_report(d, title=args.title)
    add_to_manifest(d, [REPORT_NAME])
    if args.json:
        emit_json({"report": str(path)})
    else:
        print(path)
    return 0
