"""``clutchsim calibrate``: fit a launch scenario to vehicle logs (no torque sensor)."""

from __future__ import annotations

import logging
from pathlib import Path

from ._common import (
    UserError,
    add_output_flags,
    command_parser,
    emit_json,
    write_command,
)

log = logging.getLogger("clutchsim")

HELP = """\
examples:
  clutchsim calibrate examples/calibration/launch_calibration.toml --out calib/
  clutchsim calibrate examples/calibration/launch_calibration.toml --log examples/calibration/launch_log.csv --validate examples/calibration/validate_log.csv --out calib/ --json

SPEC is a calibration spec (docs/calibration.md): the launch scenario whose network is fitted
(its engine driven by the measured torque, its clutch by the clamp map of the measured
travel), the channel map, the parameters to fit (the clamp map's, the engine torque's, and
any of the scenario's keys) with start values, bounds and optional priors, the ones held
fixed.
--log replaces the spec's logs, --validate its validation logs (each repeatable; CSV, MDF4,
or BLF/ASC decoded with the map's DBC).  The launches in each log are found (clutchsim log
launches) and fitted together; the launches of the validation logs are predicted.
Writes DIR/calibration.json, DIR/parameters.toml (values and intervals), DIR/traces.csv
(measured and simulated per launch and signal, at the measured stamps), DIR/report.md and
DIR/calibration.png (and report.html, one page of them).  --json prints one document:
{"parameters", "stderr", "intervals", "confidence", "units", "keys", "correlation",
"at_bound", "unidentified", "warnings", "launches", "validation", "sliding_capacity",
"sigma", "notes", "evaluations", "wall_time_s"}.
"""


def register(sub, common):
    p = command_parser(sub, common, "calibrate",
                       help="calibrate clutch and driveline from vehicle logs",
                       description="Fit clutch capacity, touch point, driveline stiffness "
                       "and damping and the engine-torque scale to the launches of vehicle "
                       "logs, from measured speeds only.", epilog=HELP)
    p.add_argument("spec", metavar="SPEC", help="calibration spec (TOML)")
    p.add_argument("--log", action="extend", nargs="+", default=[], metavar="FILE",
                   help="log(s) to fit (several files, repeatable; replaces the spec's logs)")
    p.add_argument("--validate", action="extend", nargs="+", default=[], metavar="FILE",
                   help="log(s) whose launches are predicted (several files, repeatable)")
    add_output_flags(p, figures="the figure")


def run(args) -> int:
    from .._util import claim_output_dir
    from ..identify.calibrate import load_calibration
    spec = load_calibration(args.spec)
    for f in args.log + args.validate:
        if not Path(f).is_file():
            raise UserError(f"{f}: no such log file")
    with claim_output_dir(args.out, "calibrate", force=args.force) as out:
        return _run(args, spec, out)


def _run(args, spec, out) -> int:
    from ..identify.calibrate import calibrate
    from ..identify.calibration_outputs import write_calibration_outputs
    from ..progress import progress_for
    result = calibrate(spec, args.log or None, args.validate or None,
                       progress=progress_for(args, "passes"))
    with out.build() as part:
        write_calibration_outputs(result, Path(part), plots=not args.no_plots)
        write_command(part, args.argv)
        from ..report import build_report
        build_report(part)
    log.info("calibrated %d launch(es) in %.1f s; wrote %s", len(result.launches),
             result.wall_time, args.out)
    if args.json:
        emit_json(result.summary())
        return 0
    pct = f"{100 * result.confidence:g} %"
    units = result.summary()["units"]
    for n in result.names:
        iv = result.intervals[n]
        u = f" {units[n]}" if units.get(n) not in (None, "", "-", "1") else ""
        shown = "no interval" if iv is None else f"{pct} [{iv[0]:.5g}, {iv[1]:.5g}]{u}"
        flag = " (at its bound)" if n in result.at_bound else ""
        flag += " (cannot be identified)" if n in result.unidentified else ""
        key = f" ({result.keys[n]})" if n in result.keys else ""
        print(f"{n:>16} = {result.parameters[n]:.6g}{u}  {shown}{flag}{key}")
    sc = result.sliding_capacity
    if sc is not None:
        iv = sc["interval"]
        print(f"{'sliding capacity':>16} = {sc['value']:.6g} N·m at {sc['speed']:g} rad/s of "
              "slip" + ("" if iv is None else f"  {pct} [{iv[0]:.5g}, {iv[1]:.5g}] N·m"))
    for tr in list(result.launches) + list(result.validation):
        m = tr.metrics
        slip = m.get("slip_end_error_ms")
        print(f"{tr.role:>8} {tr.name}: engine RMS {m['engine_rms_rpm']:.3g} rpm, slip end "
              + ("–" if slip is None else f"{slip:+.3g} ms"))
    for w in result.warnings:
        log.warning("warning: %s", w)
    return 0
