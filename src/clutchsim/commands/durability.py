"""``clutchsim durability``: lining wear over a duty cycle (clutchsim.studies.durability)."""

from __future__ import annotations

import logging

from ._common import (
    SimulationFailed,
    UserError,
    add_output_flags,
    command_parser,
    emit_json,
    write_command,
)

log = logging.getLogger("clutchsim")

HELP = """\
examples:
  clutchsim durability examples/durability/passenger_car.toml --out dur/ --json
  clutchsim durability examples/durability/hot_climate.toml --cycles 200 --full --out hot/
  # a facing that wears 20,000 times faster: the end of life in tens of cycles (exit 0)
  clutchsim durability examples/durability/accelerated_wear.toml --out worn/ --json

outputs in DIR: durability.csv (per recorded cycle: wear, clamp force, capacity, peak
temperature, friction work, simulated or extrapolated), summary.json {"kind":
"durability", "outcome" (completed, end_of_life, failed), "cycles", "cycles_done",
"simulated_cycles", "wear_mm", "clamp_force_end_N", "capacity_end_Nm", "life_cycles"
(null while the clutch lasts), "end_of_life" {"cycle", "criterion" (wear_reserve: the
reserve is used up; capacity or engagement: a manoeuvre fails with the worn lining and
completes with a new one, the capacity below the new clutch's or not), "wear_mm",
"clamp_force_N", "capacity_Nm", ...}, "failure", "wall_s", ...},
durability.png, command.txt.  DIR is written as DIR.partial and put in place when
complete; an existing DIR is replaced only when it is empty or holds an earlier
`clutchsim durability` output (--force: write beside other files, which are kept).  The
study so far is written in every case.

exit status: 0 done (the end of life is a result: outcome end_of_life, life_cycles), 1 a
manoeuvre failed with a new lining too (not wear: outcome failed; the finished cycles are
written), 2 bad input.
"""


def register(sub, common):
    p = command_parser(sub, common, "durability", help="lining wear over a duty cycle",
                       description="Run a duty cycle of manoeuvres cycle by cycle (wear and "
                       "temperatures carried over) and predict the clutch's life.",
                       epilog=HELP)
    p.add_argument("duty", help="duty-cycle TOML")
    p.add_argument("--cycles", type=int, default=None, metavar="N",
                   help="number of cycles (default: the duty file's)")
    mode = p.add_mutually_exclusive_group()
    mode.add_argument("--accelerated", dest="accelerated", action="store_true", default=True,
                      help="simulate representative cycles and extrapolate (default)")
    mode.add_argument("--full", dest="accelerated", action="store_false",
                      help="simulate every cycle")
    add_output_flags(p, figures="the figure", json_help="print summary.json on stdout")


def run(args) -> int:
    from .._util import claim_output_dir
    if args.cycles is not None and args.cycles < 1:
        raise UserError(f"--cycles {args.cycles}: must be >= 1")
    with claim_output_dir(args.out, "durability", force=args.force) as out:
        return _run(args, out)


def _run(args, out) -> int:
    import json

    from .._util import atomic_write
    from ..studies.durability import describe_end, load_duty, run_durability, write_durability
    duty = load_duty(args.duty)
    res = run_durability(duty, args.cycles, accelerated=args.accelerated)
    summary = res.summary()
    with out.build() as part:
        write_durability(res, part, plots=not args.no_plots)
        atomic_write(part / "summary.json", lambda p: p.write_text(
            json.dumps(summary, indent=2, allow_nan=False)))
        write_command(part, args.argv)
    if args.json:
        emit_json(summary)
    if res.outcome == "failed":
        raise SimulationFailed(f"{describe_end(res)} ({res.cycles_done} finished cycles "
                               f"written to {args.out})")
    if res.outcome == "end_of_life":
        log.warning("%s", describe_end(res))
    return 0
