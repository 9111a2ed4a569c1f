"""``clutchsim judder``: the modes of a scenario's driveline at an operating time."""

from __future__ import annotations

import logging

from ._common import (
    SimulationFailed,
    UserError,
    add_force_flag,
    add_option_flag,
    command_parser,
    emit_json,
    scenario_with_options,
)

log = logging.getLogger("clutchsim")

HELP = """\
examples:
  clutchsim judder                                     # the default launch at t = 0
  clutchsim judder examples/launch.toml --at 0.9 --json
  clutchsim judder --model coulomb-robust --at 3 --out modes/
  clutchsim judder --at 0.9 --set "coupling[0].friction.overrides.k_din=0.8" \
      --element clutch
  clutchsim judder --at 3 --frf throttle:a_vehicle --f-min 0.5 --f-max 100 --json

The scenario is simulated from 0 to --at (default 0), its inputs frozen there, and the
driveline linearised: locked elements are merged (their constraint holds), slipping ones
enter through their friction slope dT/d(slip).  Every mode is listed by frequency (rigid-body
and first-order modes with frequency 0): natural frequency [Hz], damping ratio [-], growth
rate [1/s], stable, the states that dominate it.

--map KEY=LO:HI:N --map KEY=LO:HI:N: the judder margin (smallest damping ratio of the
oscillatory modes) at --at over that grid of scenario variants; --out writes judder_map.csv
and judder_map.png; --json prints {"kind": "judder_map", "model", "t_s", "x": {"key",
"values"}, "y": {...}, "points": [{KEY_X, KEY_Y, "damping_ratio", "growth_rate_1_s",
"frequency_hz", "friction_slope_Nms", "stable"}]}.

--frf INPUT:OUTPUT: the frequency response H = output/input of the linearised driveline at
--at, from an input channel of the scenario (a load torque [N·m], a clutch command [-], the
throttle [-]) to an output or state (a_vehicle, T_clutch, omega_wheels, ...), over --points
frequencies log-spaced from --f-min to --f-max [Hz] (default 0.1 to 1000, 400 points).
--json prints {"kind": "frf", "model", "t_s", "input", "output", "unit", "input_unit",
"output_unit", "frequency_hz": [...], "magnitude": [...], "phase_deg": [...], "peaks":
[{"frequency_hz", "magnitude"}], "warnings": [...], "parameters"}; --out writes frf.csv,
frf.json and frf.png.

--json prints {"kind": "judder", "model", "operating_point": {"t_s", "elements": {NAME:
{"slip_rad_s", "friction_slope_Nms", "state"}}}, "modes": [{"frequency_hz",
"damping_ratio", "growth_rate_1_s", "stable", "dominant_states"}], "stable",
"parameters"}; "parameters" is every value of the linearised network with its unit
(COMPONENT: {PARAMETER: {"value", "unit", "description"}}, as a run's summary.json), also
in the FRF's document.  --out DIR
writes judder.json and judder.png (atomically: DIR.partial put in place when complete; an
existing DIR only if empty or an earlier `clutchsim judder` output, --force: beside other
files, which are kept).

exit status: 0 done (whether or not the point is stable: see "stable"), 1 the run to --at
did not complete, 2 bad input (--at past t_end, an unknown element, a bad scenario, an
unknown --frf input or output: the valid names are listed, --f-min >= --f-max, --points < 2).
"""


def register(sub, common):
    p = command_parser(sub, common, "judder",
                       help="modes and friction slopes of a driveline at an operating time",
                       description="Linearise a driveline scenario at an operating time and "
                       "report its modes (judder analysis), or with --frf the frequency "
                       "response from an input to an output.", epilog=HELP, scenario=True)
    p.add_argument("--model", default=None, help="friction model of the clutch element")
    p.add_argument("--at", type=float, default=0.0, metavar="T",
                   help="operating time [s], 0 <= T <= t_end (default 0)")
    p.add_argument("--set", action="append", default=[], metavar="PATH=VALUE",
                   help="override a scenario key, e.g. vehicle.grade=12")
    add_option_flag(p, what="the run to the operating time")
    p.add_argument("--element", action="append", default=None, metavar="NAME",
                   help="report only this switching element (repeatable)")
    p.add_argument("--out", default=None, metavar="DIR",
                   help="write judder.json and judder.png to DIR (--map: judder_map.*, --frf: "
                   "frf.csv, frf.json, frf.png)")
    add_force_flag(p)
    p.add_argument("--map", action="append", default=None, metavar="KEY=LO:HI:N",
                   help="stability map: give twice (x, then y axis), N values from LO to HI "
                   "of a scenario key")
    p.add_argument("--classic", choices=("x", "y"), default=None,
                   help="with --map: that axis is a driveline damping c [N·m·s/rad]; draw the "
                   "classic boundary c + dT/dω = 0")
    p.add_argument("--frf", default=None, metavar="INPUT:OUTPUT",
                   help="frequency response from a scenario input to an output or state, "
                   "e.g. throttle:a_vehicle")
    p.add_argument("--f-min", type=float, default=None, metavar="HZ",
                   help="with --frf: lowest frequency [Hz] (default 0.1)")
    p.add_argument("--f-max", type=float, default=None, metavar="HZ",
                   help="with --frf: highest frequency [Hz] (default 1000)")
    p.add_argument("--points", type=int, default=None, metavar="N",
                   help="with --frf: number of frequencies, log-spaced (default 400)")
    p.add_argument("--json", action="store_true", help="print the result as JSON on stdout")


def _table(result) -> str:
    head = (f"judder analysis of {result.model!r} at t = {result.point.t_s:g} s "
            f"({result.linear.n} states, {result.linear.method} Jacobian)")
    lines = [head]
    for e in result.point.elements:
        slope = "-" if e.friction_slope_Nms is None else f"{e.friction_slope_Nms:.4g} N·m·s/rad"
        lines.append(f"  element {e.name}: {e.state}, slip {e.slip_rad_s:.4g} rad/s, "
                     f"friction slope {slope}")
    lines.append(f"  {'f [Hz]':>10} {'zeta [-]':>10} {'growth [1/s]':>13} stable  dominant")
    for m in result.modes:
        flag = "yes" if m.stable else "NO"
        lines.append(f"  {m.frequency_hz:10.4g} {m.damping_ratio:10.4g} "
                     f"{m.growth_rate_1_s:13.4g} {flag:6}  {', '.join(m.dominant_states)}")
    lines.append("stable" if result.stable else "UNSTABLE: a mode grows")
    return "\n".join(lines)


def run(args) -> int:
    import math

    if not math.isfinite(args.at):
        raise UserError(f"--at {args.at!r}: the operating time must be a finite number of "
                        "seconds")
    if args.out is None:
        return _dispatch(args, None)
    from .._util import claim_output_dir
    with claim_output_dir(args.out, "judder", force=args.force) as out:
        return _dispatch(args, out)


def _dispatch(args, out) -> int:
    import sys

    from ..analysis import OperatingPointError
    from ..scenario import load_scenario
    from ..studies.judder import judder_analysis
    if args.frf is not None:
        return _run_frf(args, out)
    for flag in ("f_min", "f_max", "points"):
        if getattr(args, flag) is not None:
            raise UserError(f"--{flag.replace('_', '-')} needs --frf")
    if args.map is not None:
        return _run_map(args, out)
    if args.classic is not None:
        raise UserError("--classic needs --map")
    sc = scenario_with_options(load_scenario(args.scenario, overrides=args.set), args.option)
    try:
        result = judder_analysis(sc, args.model, args.at, elements=args.element)
    except OperatingPointError as exc:
        raise SimulationFailed(str(exc)) from None
    doc = {**result.as_dict(), "parameters": sc.network(args.model).parameter_values()}
    if out is not None:
        from ..plot.judder import plot_modes
        _write_out(out, "judder", doc, lambda p: plot_modes(result, p))
    if args.json:
        emit_json(doc)
    else:
        print(_table(result), file=sys.stdout)
    return 0


def _write_out(out, stem: str, doc: dict, plot, rows=None) -> None:
    """``STEM.json``, ``STEM.png`` (``plot(path)``) and, with ``rows``, ``STEM.csv`` in the
    claimed directory ``out`` (:class:`clutchsim._util.OutputDir`), atomically."""
    import csv
    import json

    from .._util import atomic_write

    def write_csv(path):
        with open(path, "w", newline="", encoding="utf-8") as fh:
            w = csv.DictWriter(fh, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)
    with out.build() as part:
        if rows:
            atomic_write(part / f"{stem}.csv", write_csv)
        atomic_write(part / f"{stem}.json", lambda p: p.write_text(
            json.dumps(doc, indent=2, allow_nan=False)))
        plot(part / f"{stem}.png")
    log.info("wrote %s", out.shown)


def _axis(text: str):
    import numpy as np
    key, sep, rng = text.partition("=")
    parts = rng.split(":")
    if not sep or not key or len(parts) != 3:
        raise UserError(f"--map {text!r}: expected KEY=LO:HI:N, e.g. "
                        "coupling[1].d=0.1:5:8")
    try:
        lo, hi, n = float(parts[0]), float(parts[1]), int(parts[2])
    except ValueError:
        raise UserError(f"--map {text!r}: LO and HI must be numbers and N an integer") \
            from None
    if not (np.isfinite(lo) and np.isfinite(hi)) or not 1 <= n <= 200:
        raise UserError(f"--map {text!r}: LO and HI must be finite and N in 1..200")
    return key, np.linspace(lo, hi, n)


def _run_map(args, out) -> int:

    from ..analysis import OperatingPointError
    from ..studies.judder import judder_map
    if len(args.map) != 2:
        raise UserError(f"--map: give it exactly twice (x and y axes), got {len(args.map)}")
    if args.element:
        raise UserError("--element does not apply to --map")
    x, y = _axis(args.map[0]), _axis(args.map[1])
    if x[0] == y[0]:
        raise UserError(f"--map: both axes are {x[0]!r}")
    try:
        # an --option is the [solver] key of the same name, set on every point's scenario
        jm = judder_map(args.scenario, args.model, x=x, y=y, at=args.at,
                        overrides=[*args.set, *(f"solver.{o.strip()}" for o in args.option)],
                        classic=args.classic)
    except OperatingPointError as exc:
        raise SimulationFailed(str(exc)) from None
    doc = jm.as_dict()
    if out is not None:
        from ..plot.judder import plot_map
        _write_out(out, "judder_map", doc, lambda p: plot_map(jm, p), jm.rows())
    if args.json:
        emit_json(doc)
    else:
        n_bad = sum(not r["stable"] for r in doc["points"])
        print(f"judder map of {jm.model!r} at t = {jm.t_s:g} s: {len(doc['points'])} points, "
              f"{n_bad} unstable")
    return 0


def _run_frf(args, out) -> int:
    import sys

    from ..analysis import OperatingPointError, frequency_grid
    from ..analysis.frf import DEFAULT_BAND_HZ, DEFAULT_POINTS
    from ..scenario import load_scenario
    from ..studies.frf import frf_analysis
    for flag, bad in (("--map", args.map is not None), ("--element", bool(args.element)),
                      ("--classic", args.classic is not None)):
        if bad:
            raise UserError(f"{flag} does not apply to --frf")
    parts = args.frf.split(":")
    if len(parts) != 2 or not all(p.strip() for p in parts):
        raise UserError(f"--frf {args.frf!r}: expected INPUT:OUTPUT, e.g. throttle:a_vehicle")
    inp, outp = (p.strip() for p in parts)
    f_min = DEFAULT_BAND_HZ[0] if args.f_min is None else args.f_min
    f_max = DEFAULT_BAND_HZ[1] if args.f_max is None else args.f_max
    points = DEFAULT_POINTS if args.points is None else args.points
    try:
        freqs = frequency_grid(f_min, f_max, points)
    except ValueError as exc:
        raise UserError(f"--f-min {f_min:g} --f-max {f_max:g} --points {points}: {exc}") \
            from None
    sc = scenario_with_options(load_scenario(args.scenario, overrides=args.set), args.option)
    try:
        fr = frf_analysis(sc, args.model, args.at, input=inp, output=outp, freqs_hz=freqs)
    except OperatingPointError as exc:
        raise SimulationFailed(str(exc)) from None
    for w in fr.warnings:
        log.warning("frf: %s", w)
    doc = {**fr.as_dict(), "parameters": sc.network(args.model).parameter_values()}
    if out is not None:
        from ..plot.judder import plot_frf
        _write_out(out, "frf", doc, lambda p: plot_frf(fr, p), fr.rows())
    if args.json:
        emit_json(doc)
    else:
        head = (f"frequency response {fr.output}/{fr.input} [{fr.unit}] of {fr.model!r} at "
                f"t = {fr.t_s:g} s, {fr.frequency_hz[0]:g} to {fr.frequency_hz[-1]:g} Hz "
                f"({fr.frequency_hz.size} points; {fr.method})")
        lines = [head]
        if fr.peaks:
            lines.append(f"  {'peak f [Hz]':>12} {'|H| [' + fr.unit + ']':>20}")
            lines += [f"  {p.frequency_hz:12.5g} {p.magnitude:20.5g}" for p in fr.peaks]
        else:
            lines.append("  no peak inside the grid")
        print("\n".join(lines), file=sys.stdout)
    return 0


__all__ = ["UserError", "register", "run"]
