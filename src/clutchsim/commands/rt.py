"""``clutchsim rt``: a scenario's driveline as a fixed-step C library for hardware in the
loop (:func:`clutchsim.fmu.realtime.export_realtime`)."""

from __future__ import annotations

import logging

from ._common import UserError, command_parser, emit_json

log = logging.getLogger("clutchsim")

HELP = """\
examples:
  clutchsim rt examples/launch.toml --step 1e-3 --out rt/
  clutchsim rt --step 5e-4 --out rt_2khz/ --json

The directory holds C99 sources (plant.c, model.h, clutchsim_rt.h, rt_kernel.c, ros2.c):
cs_rt_step takes one fixed ROS2 step (one Jacobian, one LU factorisation, two right-hand
sides, two solves; no allocation, no I/O, no recursion) and applies the plant's events at
the step's end.  Also a shared library built from them (libclutchsim_rt.so), rt.json (the
layout, the step check and the kernel's launch against the variable-step run) and a README.
docs/realtime.md explains the step limit and the measured accuracy and timing.

A step longer than the plant allows is refused: every oscillatory mode up to --follow Hz
(linearised at the start and after lock-up) must have omega*h <= 0.5.

--json prints {"out", "library", "step_s", "model", "states", "inputs", "outputs",
"events", "step_max_s", "omega_h_max", "modes", "check"}.

exit status: 0 written, 2 bad input (a scenario or option error, a step beyond the limit,
no C compiler).
"""


def register(sub, common):
    p = command_parser(sub, common, "rt", help="export a fixed-step real-time C library",
                       description="Write a scenario's driveline as a fixed-step C99 library "
                       "for hardware-in-the-loop rigs, checked against the variable-step run.",
                       epilog=HELP, scenario=True)
    p.add_argument("--model", default=None,
                   help="friction model of the clutch element (default: the scenario's; "
                   "model (6) when it lists it)")
    p.add_argument("--reset", default=None,
                   help="model (6)'s reset policy on the clutch (default: the scenario's)")
    p.add_argument("--set", action="append", default=[], metavar="PATH=VALUE",
                   help="override a scenario key, e.g. vehicle.grade=12")
    p.add_argument("--step", type=float, default=1e-3, metavar="SECONDS",
                   help="the fixed step [s] (default 1e-3: 1 kHz)")
    p.add_argument("--follow", type=float, default=200.0, metavar="HZ",
                   help="modes up to this frequency must be followed (default 200 Hz)")
    p.add_argument("--out", required=True, metavar="DIR", help="the directory to write")
    p.add_argument("--force", action="store_true",
                   help="write into a directory that holds other files (they are kept)")
    p.add_argument("--json", action="store_true", help="print what was written as JSON")


def run(args) -> int:
    from ..fmu import NoCompilerError
    from ..fmu.realtime import export_realtime
    try:
        info = export_realtime(args.scenario, args.out, args.model, step=args.step,
                               overrides=args.set, follow_hz=args.follow, reset=args.reset,
                               force=args.force)
    except NoCompilerError as exc:
        raise UserError(str(exc)) from exc
    for w in info.check.get("warnings", ()):
        log.warning("warning: %s", w)
    if args.json:
        emit_json(info.to_dict())
        return 0
    c = info.check
    log.info("%s: %d states, %d inputs, %d outputs, %d events; step %g s (largest %.3g s); "
             "clutch law %s", info.out, len(info.states), len(info.inputs),
             len(info.outputs), len(info.events), info.step, info.step_max, info.model)
    for key, label in (("lockup_time_s", "lock-up"), ("jerk_peak_mps3", "peak jerk")):
        v = c.get(key) or {}
        if v.get("relative_error") is not None:
            log.info("  %s: %.6g (variable step %.6g), relative error %.2g", label,
                     v["realtime"], v["reference"], v["relative_error"])
    if c.get("engine_speed_max_error_rpm") is not None:
        log.info("  engine speed: largest error %.3g rpm", c["engine_speed_max_error_rpm"])
    return 0


__all__ = ["register", "run"]
