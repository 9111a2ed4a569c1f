"""``clutchsim durability``: lining wear over a duty cycle (clutchsim.durability)."""

from __future__ import annotations

import argparse

from ..cli import SimulationFailed, UserError, emit_json
from ._common import add_force_flag, write_command

HELP = """\
examples:
  clutchsim durability examples/durability/passenger_car.toml --out dur/ --json
  clutchsim durability examples/durability/hot_climate.toml --cycles 200 --full --out hot/

outputs in DIR: durability.csv (per recorded cycle: wear, clamp force, capacity, peak
temperature, friction work, simulated or extrapolated), summary.json {"kind":
"durability", "cycles", "simulated_cycles", "wear_mm", "clamp_force_end_N",
"capacity_end_Nm", "life_cycles" (null when the reserve is not used up), "wall_s", ...},
durability.png, command.txt.  DIR is written as DIR.partial and put in place when
complete; an existing DIR is replaced only when it is empty or holds an earlier
`clutchsim durability` output (--force: write beside other files, which are kept).

exit status: 0 done (a worn-out clutch is a result: life_cycles), 1 a manoeuvre did not
complete, 2 bad input.
"""


def register(sub, common):
    p = sub.add_parser("durability", parents=[common], help="lining wear over a duty cycle",
                       description="Run a duty cycle of manoeuvres cycle by cycle (wear and "
                       "temperatures carried over) and predict the clutch's life.",
                       epilog=HELP, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("duty", help="duty-cycle TOML")
    p.add_argument("--cycles", type=int, default=None, metavar="N",
                   help="number of cycles (default: the duty file's)")
    mode = p.add_mutually_exclusive_group()
    mode.add_argument("--accelerated", dest="accelerated", action="store_true", default=True,
                      help="simulate representative cycles and extrapolate (default)")
    mode.add_argument("--full", dest="accelerated", action="store_false",
                      help="simulate every cycle")
    p.add_argument("--out", required=True, metavar="DIR", help="output directory")
    add_force_flag(p)
    p.add_argument("--no-plots", action="store_true", help="skip the figure")
    p.add_argument("--json", action="store_true", help="print summary.json on stdout")


def run(args) -> int:
    from .._util import claim_output_dir
    if args.cycles is not None and args.cycles < 1:
        raise UserError(f"--cycles {args.cycles}: must be >= 1")
    with claim_output_dir(args.out, "durability", force=args.force) as out:
        return _run(args, out)


def _run(args, out) -> int:
    import json

    from .._util import atomic_write
    from ..durability import DurabilityFailed, load_duty, run_durability, write_durability
    duty = load_duty(args.duty)
    try:
        res = run_durability(duty, args.cycles, accelerated=args.accelerated)
    except DurabilityFailed as exc:
        raise SimulationFailed(str(exc)) from None
    summary = res.summary()
    with out.build() as part:
        write_durability(res, part, plots=not args.no_plots)
        atomic_write(part / "summary.json", lambda p: p.write_text(
            json.dumps(summary, indent=2, allow_nan=False)))
        write_command(part, args.argv)
    if args.json:
        emit_json(summary)
    return 0
