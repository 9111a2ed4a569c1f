"""``clutchsim demo``: the default launch with three clutch models and the drift test."""

from __future__ import annotations

from ._common import add_force_flag, command_parser, emit_json

HELP = """\
examples:
  clutchsim demo                          # writes clutchsim-out/demo and its report.html
  # chatter detection stops the naive model (outcome "chatter"); the other two lock up
  clutchsim demo --out demo/ --json       # the summary as one JSON document

The launch compares the seed paper's model (6) (mykhailevych2020, clamp reset) with the
robust stick/slip switching model and the naive switching model, which chatter detection
stops at lock-up; the drift test runs on every applicable friction model.
"""


def register(sub, common):
    p = command_parser(sub, common, "demo", help="run the demo (what make demo runs)",
                       description="Default passenger-car launch with model (6), the robust "
                       "and the naive switching model, plus the drift test; HTML report.",
                       epilog=HELP)
    p.add_argument("--out", default="clutchsim-out/demo", metavar="DIR",
                   help="output directory (default: clutchsim-out/demo)")
    add_force_flag(p)
    p.add_argument("--json", action="store_true", help="print the summary as JSON")


def run(args) -> int:
    from ..demo import format_summary, run_demo
    summary = run_demo(args.out, force=args.force)
    if args.json:
        emit_json(summary)
    else:
        print(format_summary(summary))
    return 0
