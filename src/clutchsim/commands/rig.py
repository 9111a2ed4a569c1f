"""``clutchsim rig``: run the friction test rig with a force or velocity input."""

from __future__ import annotations

import contextlib
import logging
import math

from ._common import (
    SimulationFailed,
    UserError,
    add_limit_flags,
    add_option_flag,
    command_parser,
    emit_json,
    solver_option_items,
)

log = logging.getLogger("clutchsim")

HELP = """\
examples:
  clutchsim rig --model lugre --force "0.5 + sine(0.4, 1)" --t-end 20 --out d1.csv
  clutchsim rig --model lugre --force 0 --spring 2 --pull-speed 0.1 --t-end 30 --json
  clutchsim rig --model mykhailevych2020 --set reset=zero --velocity "ramp(0, 1, 0.01)" \\
                --t-end 2 --out ramp.csv
  # a torque table (time [s], torque [N·m]): the clutch sticks until it passes T_stat = 240
  clutchsim rig --model mykhailevych2020 --params mykhailevych2020_clutch \\
                --domain rotational --mass 0.2 --force examples/rig_torque.csv --t-end 5 \\
                --out breakaway.csv

--scale multiplies the friction capacity (normal-load ratio N(t)/N_ref [-], >= 0;
same syntax as --force).  --v0 starts the force-driven body moving: the friction
state then starts in steady sliding at v0 (a switching model in its sliding mode).

signals (--force/--velocity/--scale): a CSV file (header row, then time [s], value; linear
interpolation, held after the last row) or a formula of numbers, pi, + - and * by a
number, and const(v), step(t, height[, offset]), ramp(start, duration, height[, offset]),
sine(amplitude, freq[, phase, offset, start]), pulse(amplitude, width_percent, period[,
offset, start]); keyword arguments allowed, e.g. sine(amplitude=0.4, freq=1, offset=0.5).

outputs: --out FILE.csv holds time, x, v, F (theta, omega, T with --domain rotational),
then every other signal of the run (the friction states, the applied force, F_ext,
F_spring, the friction power), units in the column names; --json prints {"status",
"outcome", "event", "warnings", "message", "model", "domain", "stats", "final", "out"}.
Every accepted step is stored, at most --max-output-rows rows (then the result warns).
exit status: 0 completed, 1 the run did not complete (the CSV and JSON are still written),
2 bad input.
"""


def register(sub, common):
    p = command_parser(sub, common, "rig", help="simulate the friction test rig",
                       description="Simulate a mass (or inertia) on a friction contact, "
                       "driven by a force/torque or an imposed velocity.", epilog=HELP)
    p.add_argument("--model", required=True, help="friction model (see 'clutchsim models')")
    p.add_argument("--params", metavar="SET", help="parameter set (default: the model's own)")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="override one model parameter (repeatable)")
    drive = p.add_mutually_exclusive_group(required=True)
    drive.add_argument("--force", metavar="CSV_OR_EXPR",
                       help="applied force [N] (torque [N·m] with --domain rotational)")
    drive.add_argument("--velocity", metavar="CSV_OR_EXPR",
                       help="imposed velocity [m/s] (rad/s with --domain rotational)")
    p.add_argument("--scale", metavar="CSV_OR_EXPR", default=None,
                   help="capacity multiplier [-] (normal-load proxy, e.g. N(t)/N_ref), a "
                   "formula or CSV like --force; must stay >= 0 (default 1)")
    p.add_argument("--v0", type=float, default=0.0,
                   help="initial velocity [m/s or rad/s] (force drive only; the friction "
                   "state starts in steady sliding at v0; default 0: at rest)")
    p.add_argument("--mass", type=float, default=1.0,
                   help="mass [kg] or inertia [kg·m²] (default 1)")
    p.add_argument("--spring", type=float, default=0.0,
                   help="stiffness of a spring to a moving point [N/m or N·m/rad]")
    p.add_argument("--pull-speed", type=float, default=0.0,
                   help="speed of the spring's free end [m/s or rad/s]")
    p.add_argument("--domain", choices=("translational", "rotational"),
                   default="translational")
    p.add_argument("--t-end", type=float, required=True, help="end time [s]")
    p.add_argument("--solver", default=None,
                   help="integrator (default: the core's, rodas4; 'clutchsim models' and "
                        "docs/core.md list them)")
    add_option_flag(p, what="the run")
    p.add_argument("--out", metavar="FILE.csv", help="write the traces as CSV")
    p.add_argument("--json", action="store_true", help="print one JSON document")
    add_limit_flags(p)


def _value(text: str):
    try:
        return float(text)
    except ValueError:
        return text


def build_model(name: str, params: str | None, sets: list[str]):
    """The friction model from ``--model``, ``--params`` and ``--set`` (ValueError if bad)."""
    from ..friction import get_model_class, make_model
    cls = get_model_class(name)
    overrides = {}
    for item in sets:
        key, eq, text = item.partition("=")
        if not eq or not key.strip():
            raise UserError(f"--set {item!r}: expected KEY=VALUE")
        key = key.strip()
        if key not in cls.parameter_info:
            raise UserError(f"--set {item!r}: {cls.name} has no parameter {key!r}; "
                            f"parameters: {', '.join(cls.parameter_info)}")
        overrides[key] = _value(text.strip())
    try:
        return make_model(name, params, **overrides)
    except TypeError as exc:
        raise UserError(f"--set: {exc}") from None


def _finite(flag: str, value: float, *, positive: bool = False, unit: str = "") -> None:
    if not math.isfinite(value) or (positive and value <= 0):
        rule = "a finite number > 0" if positive else "a finite number"
        raise UserError(f"{flag} {value!r}: must be {rule}{' ' + unit if unit else ''}")


def _solver_options(items: list[str], **defaults):
    """``SolverOptions`` from ``--option KEY=VALUE`` items over ``defaults``;
    SolverOptions.from_mapping reads and checks them, as it does a scenario's [solver]
    table."""
    from ..core import SolverOptions
    try:
        return SolverOptions.from_mapping(solver_option_items(items), **defaults)
    except (TypeError, ValueError) as exc:
        raise UserError(f"--option: {exc}") from None


def run(args) -> int:
    from .._util import check_output_file, check_run_size, estimate_run
    from ..core.options import DEFAULT_METHOD
    from ..progress import progress_for
    from ..rig import run_rig
    from ..signal_expr import parse_signal
    _finite("--t-end", args.t_end, positive=True, unit="s")
    for flag, value in (("--mass", args.mass), ("--spring", args.spring),
                        ("--pull-speed", args.pull_speed), ("--v0", args.v0)):
        _finite(flag, value, positive=flag == "--mass")
    if args.v0 != 0.0 and args.velocity is not None:
        raise UserError(f"--v0 {args.v0!r}: the initial velocity is only for the force drive "
                        "(with --velocity the imposed velocity sets it)")
    if args.out:
        if not args.out.lower().endswith(".csv"):
            raise UserError(f"--out {args.out!r}: the trace file must end in .csv")
        check_output_file(args.out)
    model = build_model(args.model, args.params, args.set)
    flag = "--force" if args.force is not None else "--velocity"
    try:
        signal = parse_signal(args.force if args.force is not None else args.velocity)
    except ValueError as exc:
        raise UserError(f"{flag}: {exc}") from None
    drive = {"force": signal} if args.force is not None else {"velocity": signal}
    scale = 1.0
    if args.scale is not None:
        try:
            scale = parse_signal(args.scale)
        except ValueError as exc:
            raise UserError(f"--scale: {exc}") from None
        _check_scale(scale, args.t_end)
    options = _solver_options(args.option, h_max=args.t_end / 100.0)
    options = check_run_size(estimate_run(args.t_end, options, 0), options,
                             what="rig", max_rows=args.max_output_rows)
    log.info("rig: %s, %s, 0-%g s", model.name, args.domain, args.t_end)
    with progress_for(args, "run", tick=1.0) or contextlib.nullcontext() as bar:
        if bar is not None:
            bar(0, 1)
        res = run_rig(model, args.t_end, domain=args.domain, mass=args.mass,
                      spring=args.spring, pull_speed=args.pull_speed, solver=args.solver or DEFAULT_METHOD,
                      options=options, scale=scale, v0=args.v0, **drive)
        if bar is not None:
            bar(1, 1)
    if args.out:
        frame = _frame(res, args.domain)
        from .._util import atomic_write
        atomic_write(args.out, lambda p: frame.to_csv(p, index=False, float_format="%.17g"))
        log.info("wrote %s", args.out)
    if args.json:
        finals = {f"{n} [{res.unit(n)}]": res.final(n) for n in res.signals}
        emit_json({"status": res.status, "outcome": str(res.outcome), "event": res.event,
                   "warnings": list(res.warnings), "message": res.message,
                   "model": model.name, "domain": args.domain, "stats": res.stats.as_dict(),
                   "final": finals, "out": args.out})
    elif not args.out:
        print(res.message)
    for w in res.warnings:
        log.warning("warning: %s", w)
    if res.status == "failed":
        raise SimulationFailed(res.message)
    return 0


def _check_scale(scale, t_end: float) -> None:
    """A capacity multiplier must be >= 0 (a negative one would reverse the friction)."""
    import numpy as np
    t = np.linspace(0.0, t_end, 2001)
    bp = np.asarray(scale.breakpoints(), dtype=float)
    t = np.union1d(t, bp[(bp >= 0.0) & (bp <= t_end)])
    values = scale(t)
    bad = np.flatnonzero(~np.isfinite(values) | (values < 0))
    if bad.size:
        i = bad[0]
        raise UserError(f"--scale: the capacity multiplier is {values[i]:g} at t = {t[i]:g} s; "
                        "it must be finite and >= 0 (a normal-load ratio)")


def _frame(res, domain: str):
    """Columns time, position, velocity, friction force, then every other signal of the
    result in its order (friction states, applied force, F_ext, F_spring, power...)."""
    x, v, f = ("x", "v", "F") if domain == "translational" else ("theta", "omega", "T")
    frame = res.to_frame()
    first = ["time [s]"] + [f"{n} [{res.unit(n)}]" for n in (x, v, f)]
    return frame[first + [c for c in frame.columns if c not in first]]
