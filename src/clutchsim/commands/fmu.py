"""``clutchsim fmu``: export a scenario's plant as an FMU (Model Exchange and co-simulation,
FMI 2.0 or 3.0)."""

from __future__ import annotations

import logging

from ._common import UserError, add_scenario_flags, command_parser, emit_json

log = logging.getLogger("clutchsim")

HELP = """\
examples:
  clutchsim fmu examples/launch.toml --model mykhailevych2020 --out launch.fmu
  clutchsim fmu examples/coupled_clutches.toml --out coupled.fmu --json
  clutchsim fmu examples/launch.toml --fmi 3 --out launch3.fmu
  clutchsim fmu examples/launch.toml --kind both --out launch_mecs.fmu
  clutchsim fmu examples/launch.toml --fmi 3 --kind cs --out launch3_cs.fmu

The FMU (FMI 2.0 or 3.0; Model Exchange, co-simulation with its own ROS2 solver, or both;
directional derivatives, exact to the states) holds the scenario's plant printed as C and
compiled with the system C compiler ($CC, cc, gcc or clang) for this platform, its C
sources, and modelDescription.xml: states, inputs (start = the signal at t = 0), outputs
with units, parameters.  It runs without Python.  Using it from FMPy and other tools: docs/fmu.md.
NAME.fmu appears only when complete.

--json prints {"path", "fmi", "kind", "model", "model_identifier", "guid", "platform",
"compiler", "states", "inputs", "outputs", "parameters", "constants",
"event_indicators", "size_bytes"}.

exit status: 0 written, 2 bad input (a scenario or option error, an --fmi other than 2 or
3, a --kind other than me, cs, both, no C compiler, a model or scenario that cannot be
exported).
"""


def register(sub, common):
    p = command_parser(sub, common, "fmu", help="export a scenario as an FMU",
                       description="Export a scenario's plant as a Functional Mock-up Unit "
                       "(FMI 2.0 or 3.0, Model Exchange or co-simulation) that any FMI tool "
                       "can run.", epilog=HELP, scenario=True)
    add_scenario_flags(p)
    p.add_argument("--fmi", default="2", help="FMI version: 2 (default) or 3")
    p.add_argument("--kind", default="me",
                   help="interface: me (Model Exchange, default), cs (co-simulation), both")
    p.add_argument("--out", required=True, metavar="NAME.fmu", help="the FMU file to write")
    p.add_argument("--json", action="store_true", help="print what was written as JSON")


def run(args) -> int:
    from .._util import check_output_file
    from ..fmu import NoCompilerError, export_fmu
    check_output_file(args.out)
    try:
        info = export_fmu(args.scenario, args.out, args.model, fmi=args.fmi, kind=args.kind,
                          overrides=args.set)
    except NoCompilerError as exc:
        raise UserError(str(exc)) from exc
    if args.json:
        emit_json(info.to_dict())
    else:
        log.info("%s: FMI %s (%s), %d states, %d inputs, %d outputs, %d "
                 "parameters, %d event indicators (%s), %s", info.path, info.fmi, info.kind,
                 len(info.states), len(info.inputs), len(info.outputs), len(info.parameters),
                 len(info.event_indicators), ", ".join(info.event_indicators) or "none",
                 info.platform)
    return 0


__all__ = ["register", "run"]
