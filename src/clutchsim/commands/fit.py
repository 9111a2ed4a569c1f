"""``clutchsim fit``: identify friction parameters from measured data (or a TOML fit spec)."""

from __future__ import annotations

import logging
import math
from pathlib import Path

from ._common import (
    SimulationFailed,
    UserError,
    add_option_flag,
    add_output_flags,
    command_parser,
    emit_json,
    solver_option_items,
    write_command,
)

log = logging.getLogger("clutchsim")

HELP = """\
examples:
  clutchsim fit examples/fit_emps.toml --model lugre --out emps_lugre/ --json
  clutchsim fit examples/fit_emps.toml --model tanh --params F_c,sigma2,M,offset --out cv/
  clutchsim fit examples/fit_emps.toml --model tanh --option rtol=1e-9 --option wall_time=60 \\
      --out tight/
  clutchsim fit examples/fit_brfd_loads.toml --model dahl --out loads/ --json
  # a CSV record (here two written by the rig), fitted, then validated on the other one
  clutchsim rig --model tanh --velocity "sine(0.05, 0.5)" --t-end 8 --out rec.csv
  clutchsim rig --model tanh --velocity "sine(0.08, 0.3)" --t-end 8 --out other.csv
  clutchsim fit rec.csv --model tanh --plant rig-velocity --input v --output F \\
      --time "time [s]" --column "v=v [m/s]" --column "F=F [N]" --params F_c,sigma2 \\
      --bounds sigma2=0:10 --validate other.csv --out rec_fit/

DATA is a CSV/TXT, NPZ or MAT file, or a TOML fit specification (see
docs/identification.md); command-line options override the specification.  A
specification may fit several records at once ([[records]]), declare measured inputs
([inputs.COLUMN]), derive columns ([data] derived) and choose how validation records
start ([validate] initial, warmup).  Solver options (--option, a spec's [solver] table)
default to clutchsim.identify.FIT_SOLVER_DEFAULTS, with atol from the output scale unless
it is given; --option overrides the spec.
Writes DIR/fit.json, DIR/fit.png (measured vs simulated), DIR/residuals.png,
DIR/traces.csv and DIR/report.md.  --json prints one document:
{"model", "parameters", "stderr", "nrmse_fit", "nrmse_validation", "nrmse_pooled",
"records", "validation", "at_bound", "unidentified", "warnings", "notes"} (records and
validation: {"source", "nrmse"} per record; notes: declared inputs a record lacks; at_bound: fitted values within 0.1 % of a bound;
unidentified: parameters the data cannot determine; warnings: why, for each).
"""


def register(sub, common):
    p = command_parser(sub, common, "fit", help="fit friction parameters to measured data",
                       description="Output-error fit of a friction model (and plant "
                       "parameters) to a measured record.", epilog=HELP)
    p.add_argument("data", metavar="DATA_OR_SPEC", help="data file or TOML fit specification")
    p.add_argument("--model", help="friction model (default: the spec's [fit] model)")
    p.add_argument("--input", help="measured input column")
    p.add_argument("--output", help="measured output column")
    p.add_argument("--params", help="parameters to fit, comma separated")
    p.add_argument("--bounds", action="append", default=[], metavar="NAME=LO:HI",
                   help="bounds of a fitted parameter (repeatable)")
    p.add_argument("--fixed", action="append", default=[], metavar="NAME=VALUE",
                   help="hold a parameter at a value (repeatable)")
    p.add_argument("--start", action="append", default=[], metavar="NAME=VALUE",
                   help="start value of a model or plant parameter (repeatable)")
    p.add_argument("--validate", action="extend", nargs="+", default=[], metavar="OTHER_DATA",
                   help="validation record(s), read with the same column mapping (several "
                   "files, repeatable); each is reported")
    p.add_argument("--plant", help="rig-force, rig-velocity or emps (default rig-force)")
    p.add_argument("--plant-option", action="append", default=[], metavar="KEY=VALUE",
                   help="plant option, e.g. mass=2 or scale=N (repeatable)")
    p.add_argument("--column", action="append", default=[], metavar="NAME=FILECOLUMN",
                   help="column mapping for a data file (repeatable; default: all columns)")
    p.add_argument("--time", default=None, help="time column of a data file (default t)")
    p.add_argument("--scale", action="append", default=[], metavar="NAME=FACTOR",
                   help="unit factor of a column (repeatable)")
    p.add_argument("--nan", choices=("error", "drop", "interpolate"), default=None,
                   help="NaN samples: error (default), drop the rows, or interpolate")
    p.add_argument("--window", metavar="T0:T1", help="time window of the fitting data [s]")
    p.add_argument("--starts", type=int, default=None, help="number of starts (default 1)")
    p.add_argument("--seed", type=int, default=None, help="seed of the random starts")
    p.add_argument("--solver", default=None,
                   help="integrator (default: the spec's [solver] method, else the core's, "
                        "rodas4)")
    add_option_flag(p, what="every simulation")
    add_output_flags(p, figures="the PNG figures")


def _pairs(items, what, convert=float):
    out = {}
    for item in items:
        if "=" not in item:
            raise UserError(f"--{what} {item!r}: expected NAME=VALUE")
        key, value = item.split("=", 1)
        try:
            out[key.strip()] = convert(value.strip())
        except ValueError:
            raise UserError(f"--{what} {item!r}: {value!r} is not a valid value") from None
    return out


def _bounds(items):
    out = {}
    for item in items:
        name, sep, rng = item.partition("=")
        lo, sep2, hi = rng.partition(":")
        if not sep or not sep2:
            raise UserError(f"--bounds {item!r}: expected NAME=LO:HI, e.g. sigma0=1e4:1e8")
        try:
            a, b = float(lo), float(hi)
        except ValueError:
            raise UserError(f"--bounds {item!r}: LO and HI must be numbers") from None
        if not (math.isfinite(a) and math.isfinite(b)):
            raise UserError(f"--bounds {item!r}: LO and HI must be finite")
        if a >= b:
            raise UserError(f"--bounds {item!r}: lo = {a:g} must be < hi = {b:g}")
        out[name.strip()] = (a, b)
    return out


def _auto(value: str):
    try:
        return float(value)
    except ValueError:
        if value.lower() in ("true", "false"):
            return value.lower() == "true"
        return value


def _window(text):
    if text is None:
        return None
    a, sep, b = text.partition(":")
    if not sep:
        raise UserError(f"--window {text!r}: expected T0:T1 (either may be empty)")
    try:
        t0, t1 = (float(a) if a else None, float(b) if b else None)
    except ValueError:
        raise UserError(f"--window {text!r}: T0 and T1 must be numbers") from None
    for name, t in (("T0", t0), ("T1", t1)):
        if t is not None and not math.isfinite(t):
            raise UserError(f"--window {text!r}: {name} = {t!r} must be a finite time [s]")
    if t0 is not None and t1 is not None and t0 >= t1:
        raise UserError(f"--window {text!r}: T0 = {t0:g} s > T1 = {t1:g} s; the window "
                        "must start before it ends (write T0:T1 with T0 < T1)"
                        if t0 > t1 else f"--window {text!r}: T0 = T1 = {t0:g} s is an "
                        "empty window (T0 must be < T1)")
    return t0, t1


def _check_numbers(args) -> None:
    """The numeric options, before any file is read."""
    if args.starts is not None and args.starts < 1:
        raise UserError(f"--starts {args.starts}: the number of starts must be >= 1")
    if args.seed is not None and args.seed < 0:
        raise UserError(f"--seed {args.seed}: must be >= 0")


def _from_spec(args):
    from ..identify import load_spec
    spec = load_spec(args.data)
    model, entry = spec.model_entry(args.model)
    records = spec.fit_data(window=_window(args.window))
    data = records if len(records) > 1 else records[0]
    validate = spec.validation_data() + [spec.read(f) for f in args.validate]
    spec.check_inputs(records, validate)
    f = spec.fit
    params = args.params.split(",") if args.params else list(entry.get("params", []))
    if not params:
        raise UserError(f"{spec.path}: no parameters to fit for {model.name}: give --params "
                        f"or [models.{model.name}] params")
    bounds = {k: tuple(v) for k, v in entry.get("bounds", {}).items() if k in params}
    bounds.update(_bounds(args.bounds))
    fixed = {k: v for k, v in entry.get("fixed", {}).items() if k not in params}
    fixed.update(_pairs(args.fixed, "fixed"))
    options = dict(spec.plant.options)
    options.update({k: v for k, v in entry["plant_start"].items()})
    starts = _pairs(args.start, "start")
    model_starts = {k: v for k, v in starts.items() if k in type(model).parameter_info}
    model = model.with_(**model_starts) if model_starts else model
    options.update({k: v for k, v in starts.items() if k not in model_starts})
    options.update(_pairs(args.plant_option, "plant-option", _auto))
    from ..identify import FitOptions, FitProblem
    problem = FitProblem(input=args.input or f["input"], output=args.output or f["output"],
                         params=params, bounds=bounds, fixed=fixed,
                         plant=args.plant or spec.plant.kind, plant_options=options,
                         signal=f.get("signal"), inputs=spec.inputs,
                         per_record=f.get("per_record", []), weights=spec.weights())
    search = {key: f[key] for key in ("max_nfev", "diff_step", "tol") if key in f}
    if args.solver or "method" in spec.solver:      # else fit()'s default, the core's
        search["solver"] = args.solver or spec.solver["method"]
    fit_options = FitOptions(
        starts=args.starts or int(f.get("starts", 1)),
        seed=args.seed if args.seed is not None else int(f.get("seed", 0)),
        solver_options={k: v for k, v in spec.solver.items() if k != "method"}
        | solver_option_items(args.option), **search)
    validation = {"validate_initial": spec.validation_initial(model),
                  "validate_warmup": float(spec.validate.get("warmup", 0.0))}
    return model, data, validate, problem, fit_options, validation


def _from_data(args):
    from ..data import read_measurements
    from ..friction import make_model
    if not args.model:
        raise UserError("--model is required with a data file")
    missing = [o for o, v in (("--input", args.input), ("--output", args.output),
                              ("--params", args.params)) if not v]
    if missing:
        raise UserError(f"{', '.join(missing)} required with a data file (or use a TOML spec)")
    columns = _pairs(args.column, "column", str) or None
    scale = _pairs(args.scale, "scale")
    # a file column named "F [N]" gives F its unit (not when --scale converts it)
    from ..plot.interactive import split_label
    units = {k: u for k, v in (columns or {}).items()
             if k not in scale and (u := split_label(v)[1])}
    read = {"time": args.time or "t", "columns": columns, "scale": scale,
            "units": units, "nan": args.nan or "error"}
    data = read_measurements(args.data, **read)
    window = _window(args.window)
    if window:
        data = data.window(*window)
    validate = [read_measurements(f, **read) for f in args.validate]
    starts = _pairs(args.start, "start")
    from ..friction import get_model_class
    cls = get_model_class(args.model)
    model = make_model(args.model, **{k: v for k, v in starts.items()
                                      if k in cls.parameter_info})
    options = {k: v for k, v in starts.items() if k not in cls.parameter_info}
    options.update(_pairs(args.plant_option, "plant-option", _auto))
    from ..identify import FitOptions, FitProblem
    problem = FitProblem(input=args.input, output=args.output, params=args.params.split(","),
                         bounds=_bounds(args.bounds), fixed=_pairs(args.fixed, "fixed"),
                         plant=args.plant or "rig-force", plant_options=options)
    fit_options = FitOptions(starts=args.starts or 1, seed=args.seed or 0,
                             solver_options=solver_option_items(args.option),
                             **({"solver": args.solver} if args.solver else {}))
    return model, data, validate, problem, fit_options, {}


def run(args) -> int:
    from .._util import claim_output_dir
    _check_numbers(args)
    _window(args.window)
    with claim_output_dir(args.out, "fit", force=args.force) as out:
        return _run(args, out)


def _run(args, out) -> int:
    from ..identify import fit
    path = Path(args.data)
    read = _from_spec if path.suffix.lower() == ".toml" else _from_data
    model, data, validate, problem, fit_options, validation = read(args)
    sources = [d.source for d in (data if isinstance(data, list) else [data])]
    log.info("fitting %s (%s) to %s: %s", model.name, problem.plant, ", ".join(sources),
             ", ".join(problem.params))
    try:
        from ..progress import progress_for
        result = fit(model, data, problem, fit_options, validate=validate or None,
                     progress=progress_for(args, "simulations"), **validation)
    except RuntimeError as exc:
        raise SimulationFailed(str(exc)) from None
    from ..identify.outputs import write_outputs
    from ..report import build_report
    with out.build() as part:
        files = write_outputs(result, part, plots=not args.no_plots,
                              unit=(data[0] if isinstance(data, list) else data).units.get(
                                  problem.output, ""))
        write_command(part, args.argv)
        build_report(part)
    files = {name: Path(args.out) / path.name for name, path in files.items()}
    log.info("NRMSE fit %.4g%s; wall time %.1f s; wrote %s", result.nrmse_fit,
             "" if result.nrmse_validation is None
             else f", validation {result.nrmse_validation:.4g}", result.wall_time,
             ", ".join(str(p) for p in files.values()))
    if args.json:
        emit_json(result.summary())
    else:
        for name, value in result.parameters.items():
            se = result.stderr.get(name)
            flag = " (at its bound)" if name in result.at_bound else ""
            flag += " (cannot be identified)" if name in result.unidentified else ""
            print(f"{name:>10} = {value:.6g} ± " + ("undetermined" if se is None else f"{se:.2g}")
                  + flag)
        for w in result.warnings:
            log.warning("warning: %s", w)
        for note in result.notes:
            log.info("note: %s", note)
        if len(result.records) > 1:
            for tr in result.records:
                print(f"NRMSE fit {Path(tr.source).name} = {tr.nrmse:.4g}")
            print(f"NRMSE pooled = {result.nrmse_pooled:.4g}")
        else:
            print(f"NRMSE fit = {result.nrmse_fit:.4g}")
        for tr in result.validation:
            print(f"NRMSE validation {Path(tr.source).name} = {tr.nrmse:.4g}")
    return 0
