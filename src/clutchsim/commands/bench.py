"""``clutchsim bench``: run a friction benchmark, write its figure, traces and metrics."""

from __future__ import annotations

import json
import logging

from ._common import (
    SimulationFailed,
    UserError,
    add_force_flag,
    command_parser,
    emit_json,
    write_command,
)

log = logging.getLogger("clutchsim")

HELP = """\
examples:
  clutchsim bench drift --json                       # default models, metrics on stdout
  clutchsim bench drift --model lugre --model elastoplastic --out drift/
  clutchsim bench stick-slip --model lugre --out ss/ --json
  clutchsim bench drift --model "mykhailevych2020,reset=zero"

benchmarks: curves, drift, hysteresis, presliding, lag, breakaway, stick-slip,
coulomb-analytic.  A model is NAME[:PARAMETER_SET][,key=value...].
--out DIR receives <name>.png, <name>_traces.csv and bench.json; the directory is
built as DIR.partial and put in place when complete.  An existing DIR is replaced only when
it is empty or holds an earlier `clutchsim bench` output (--force: write beside other files,
which are kept).
"""


def register(sub, common):
    p = command_parser(sub, common, "bench", help="run a friction benchmark",
                       description="Run a friction benchmark protocol on one or more "
                       "models and report its metrics.", epilog=HELP)
    p.add_argument("name", help="benchmark name")
    p.add_argument("--model", action="append", metavar="M",
                   help="model (repeatable; default: every applicable model)")
    p.add_argument("--out", metavar="DIR", help="write PNG, CSV traces and bench.json")
    add_force_flag(p)
    p.add_argument("--json", action="store_true", help="print one JSON document")


def run(args) -> int:
    from ..benchmarks import get_benchmark
    bench = get_benchmark(args.name)
    if args.out is None:
        return _run(args, bench, None)
    from .._util import claim_output_dir
    with claim_output_dir(args.out, "bench", force=args.force) as out:
        return _run(args, bench, out)


def _run(args, bench, out) -> int:
    try:
        from ..benchmarks import resolve_models
        entries = resolve_models(args.model, bench.default_models, bench.applicable)
    except ValueError as exc:
        raise UserError(f"--model: {exc}") from None
    log.info("bench %s: %s", bench.name, ", ".join(e.label for e in entries))
    result = bench.run(args.model)
    if out is not None:
        from ..benchmarks import write_outputs
        from ..report import build_report
        with out.build() as part:
            write_outputs(result, part)
            write_command(part, args.argv)
            build_report(part)
        log.info("wrote %s", args.out)
    if args.json:
        emit_json(result.metrics_json())
    else:
        for label in result.metrics:
            print(f"{label}: {json.dumps(result.metrics_json()['results'][label])}")
    failed = [label for label, m in result.metrics.items() if m.get("status") == "failed"]
    if failed:
        raise SimulationFailed("; ".join(f"{label}: {result.metrics[label]['message']}"
                                         for label in failed))
    return 0
