"""What several subcommands share: the errors that set the exit status, the one JSON
document, the size-limit flags, command.txt, the run check.  :mod:`clutchsim.cli` imports
from here, never the other way round."""

from __future__ import annotations

import argparse
import json
import sys
from contextlib import nullcontext
from dataclasses import replace
from pathlib import Path

from .._util import DEFAULT_MAX_OUTPUT_ROWS, DEFAULT_MAX_RUNS, check_run_size

__all__ = ["SimulationFailed", "UserError", "add_force_flag", "add_limit_flags",
           "add_output_flags", "add_study_flags", "add_sweep_flags", "check_sweep_flags",
           "checked_scenario", "command_parser", "emit_json", "metric_names", "run_study",
           "solver_option_items", "write_command"]


class UserError(Exception):
    """A mistake in the command line, a scenario file or input data (exit status 2)."""


class SimulationFailed(Exception):
    """A simulation that did not complete (exit status 1)."""


def emit_json(document) -> None:
    """Print exactly one JSON document on stdout."""
    sys.stdout.write(json.dumps(document, indent=2, default=_json_default, allow_nan=False))
    sys.stdout.write("\n")
    sys.stdout.flush()


def _json_default(obj):
    import numpy as np
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    raise TypeError(f"not JSON serialisable: {type(obj).__name__}")


def _positive_int(text: str) -> int:
    try:
        value = int(float(text)) if "e" in text.lower() else int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not an integer") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"{text!r} must be >= 1")
    return value


def add_limit_flags(p, *, runs: bool = False) -> None:
    """``--max-output-rows`` (and ``--max-runs`` for sweeps), documented in --help."""
    g = p.add_argument_group("size limits (checked before anything runs)")
    g.add_argument("--max-output-rows", type=_positive_int, default=DEFAULT_MAX_OUTPUT_ROWS,
                   metavar="N", help="most output rows of one run (default "
                   f"{DEFAULT_MAX_OUTPUT_ROWS:,}); a fixed output grid (dt_out) above it "
                   "is refused, a run storing every step stops storing at it")
    if runs:
        g.add_argument("--max-runs", type=_positive_int, default=DEFAULT_MAX_RUNS,
                       metavar="N", help=f"most runs of the sweep (default "
                       f"{DEFAULT_MAX_RUNS:,})")


def add_sweep_flags(p, flag: str) -> None:
    """Where the runs of a sweep run (sweep, uq): ``flag`` (``--dask`` or ``--address``,
    dest ``address``: a Dask LocalCluster or scheduler), ``--workers``,
    ``--connect-timeout`` and ``--chunk-size``; :func:`check_sweep_flags` checks them."""
    p.add_argument(flag, dest="address", metavar="local|tcp://HOST:PORT", help="run on "
                   "Dask: a LocalCluster or the scheduler at this address")
    p.add_argument("--workers", type=int, metavar="N", help="threads (in-process) or Dask "
                   "workers of a local cluster (default: all cores)")
    p.add_argument("--connect-timeout", type=float, default=10.0, metavar="S",
                   help="seconds to wait for a Dask scheduler (default 10)")
    p.add_argument("--chunk-size", type=int, metavar="N", help="runs per chunk")


def check_sweep_flags(args) -> None:
    """The flags of :func:`add_sweep_flags`: UserError (exit 2) for a bad value."""
    import math
    if args.workers is not None and args.workers < 1:
        raise UserError(f"--workers {args.workers}: must be >= 1")
    if args.chunk_size is not None and args.chunk_size < 1:
        raise UserError(f"--chunk-size {args.chunk_size}: must be >= 1")
    if not (math.isfinite(args.connect_timeout) and args.connect_timeout > 0):
        raise UserError(f"--connect-timeout {args.connect_timeout!r}: must be a finite "
                        "number of seconds > 0")


def command_parser(sub, common, name: str, *, help: str, description: str, epilog: str,
                   scenario: bool = False):
    """The subcommand ``name`` with the common flags (``common``): ``help`` its line in the
    command list, ``description`` the head of its --help, ``epilog`` the examples and exit
    statuses below it, laid out as written; ``scenario``: its first argument is an optional
    scenario TOML."""
    p = sub.add_parser(name, parents=[common], help=help, description=description,
                       epilog=epilog, formatter_class=argparse.RawDescriptionHelpFormatter)
    if scenario:
        p.add_argument("scenario", nargs="?", help="scenario TOML (default: the packaged launch)")
    return p


def add_output_flags(p, *, force: bool = True, figures: str = "the figures",
                     json_help: str = "print one JSON document") -> None:
    """``--out DIR`` (required), ``--force`` (``force``: not for a command that adds to an
    existing study in place), ``--no-plots`` (skips ``figures``) and ``--json``."""
    p.add_argument("--out", required=True, metavar="DIR", help="output directory")
    if force:
        add_force_flag(p)
    p.add_argument("--no-plots", action="store_true", help=f"skip {figures}")
    p.add_argument("--json", action="store_true", help=json_help)


def add_study_flags(p) -> None:
    """The flags of a study of many runs of one scenario (sweep, uq): ``--metrics``,
    ``--model``, ``--set`` and ``--option`` (read back by :func:`metric_names` and
    :func:`solver_option_items`)."""
    p.add_argument("--metrics", metavar="M1,M2", help="metric columns (default: all but "
                   "wall_s)")
    add_scenario_flags(p, model_help="friction model of the clutch (default: the scenario's "
                       "first)", set_help="override a key of the base scenario")
    add_option_flag(p, what="every run")


def add_scenario_flags(p, *, model_help: str = "friction model of the clutch element "
                       "(default: the scenario's first)",
                       set_help: str = "override a scenario key, e.g. vehicle.grade=12") -> None:
    """``--model`` (the clutch's friction model) and ``--set PATH=VALUE`` (repeatable) of a
    command on one scenario."""
    p.add_argument("--model", default=None, help=model_help)
    p.add_argument("--set", action="append", default=[], metavar="PATH=VALUE", help=set_help)


def metric_names(text: str | None) -> list[str] | None:
    """The metric columns of ``--metrics M1,M2`` (None: every one)."""
    return [m.strip() for m in text.split(",") if m.strip()] if text else None


def run_study(args, kind: str, body) -> int:
    """Run the study command ``kind`` (sweep, uq) into ``--out``, which it may add to in
    place (an earlier study of the same kind resumes): ``body(args, directory)``."""
    from .._util import claim_output_dir
    from ..scenario.warmup import metrics_compiled_beside
    check_sweep_flags(args)
    # runs on this machine share its numba cache (a remote scheduler's workers do not)
    local = args.address in (None, "", "local")
    with claim_output_dir(args.out, kind, in_place=True) as out, \
            metrics_compiled_beside(batch=True) if local else nullcontext():
        return body(args, out.path)


def add_force_flag(p) -> None:
    """``--force``: write into an --out directory that holds other files (one help text
    for every command that writes a directory; the rules: :mod:`clutchsim._util`)."""
    p.add_argument("--force", action="store_true",
                   help="write into DIR even if it holds files clutchsim did not write or "
                        "another command's output: clutchsim's own files there are "
                        "replaced, every other file is kept")


def checked_scenario(sc, model, max_rows: int):
    """``sc`` with its solver options fitted to the output limit, after refusing a run
    beyond it (:class:`clutchsim._util.ResourceError`)."""
    est = sc.estimate(model)
    options = check_run_size(est, sc.options, what=f"{sc.file}: {model or 'its own model'}",
                             max_rows=max_rows)
    return sc if options is sc.options else replace(sc, options=options)


def write_command(directory: Path, argv: list[str]) -> None:
    """``command.txt``: the command line that made an output directory (atomically).
    ``argv`` is what :func:`clutchsim.cli.main` parsed (not ``sys.argv``: main may be
    called with its own list)."""
    import shlex

    from .._util import atomic_write
    text = shlex.join(["clutchsim", *argv]) + "\n"
    atomic_write(Path(directory, "command.txt"), lambda p: Path(p).write_text(text))


def add_option_flag(p, *, what: str = "the run") -> None:
    """``--option KEY=VALUE`` (repeatable): a solver option of ``what``, the keys of a
    scenario's ``[solver]`` table (one help text for every command that simulates)."""
    p.add_argument("--option", action="append", default=[], metavar="KEY=VALUE",
                   help=f"a solver option of {what}, the same keys as a scenario's [solver] "
                        "table (rtol, atol, h_max, dt_out, max_steps, wall_time, "
                        "chatter_events, chatter_window, controller, ...); repeatable")


def scenario_with_options(sc, items: list[str]):
    """``sc`` with the ``--option`` items over its ``[solver]`` table (UserError names a bad
    key or value)."""
    if not items:
        return sc
    from ..scenario.loader import with_solver_options
    try:
        return with_solver_options(sc, solver_option_items(items))
    except (TypeError, ValueError) as exc:
        raise UserError(f"--option: {exc}") from None


def solver_option_items(items: list[str]) -> dict:
    """``--option KEY=VALUE`` items as a mapping for ``SolverOptions.from_mapping`` (values
    are numbers except ``controller``; from_mapping names unknown keys and bad values)."""
    from ..core import SolverOptions
    raw = {}
    for item in items:
        key, sep, text = item.partition("=")
        key = key.strip()
        if not sep or not key:
            raise UserError(f"--option {item!r}: expected KEY=VALUE")
        kind = SolverOptions.MAPPING_KEYS.get(key)
        if kind in (int, float):
            try:
                value = float(text)
            except ValueError:
                raise UserError(f"--option {item!r}: {text.strip()!r} is not a number") \
                    from None
            raw[key] = int(value) if kind is int and value == int(value) else value
        else:       # controller, or an unknown key that from_mapping names
            raw[key] = text.strip()
    return raw
