"""The ``clutchsim`` command line: a thin layer over the public functions.

Every subcommand lives in :mod:`clutchsim.commands` as a module with ``register(sub)``
(adds its argparse subparser) and ``run(args) -> int``.  Conventions, shared by all:

* exit status 0 success, 1 a simulation that did not complete (its message is printed),
  2 bad input (a one-line message naming the argument/file/key, and a hint);
* ``--json`` prints exactly one JSON document on stdout; progress and logs go to stderr;
* ``--quiet`` silences progress and info logs, ``--verbose`` adds detail, ``--debug``
  shows tracebacks instead of one-line messages.
"""

from __future__ import annotations

import argparse
import importlib
import json
import logging
import sys

from ._version import __version__

__all__ = ["SimulationFailed", "UserError", "emit_json", "main"]

#: subcommand modules, in the order ``--help`` lists them
COMMANDS = ("models", "rig", "bench", "run", "demo", "sweep", "fit", "report")

EPILOG = """\
examples:
  clutchsim demo                                  # default launch + drift test, HTML report
  clutchsim models                                # the friction models, states and parameters
  clutchsim rig --model lugre --spring 2 --pull-speed 0.1 --t-end 30 --out rig.csv
  clutchsim bench drift --model lugre --model elastoplastic --out drift/ --json
  clutchsim run examples/launch.toml --model mykhailevych2020 --out launch/

exit status: 0 success, 1 a simulation did not complete, 2 bad input.
"""

log = logging.getLogger("clutchsim")


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


def _available():
    mods = {}
    for name in COMMANDS:
        try:
            mods[name] = importlib.import_module(f".commands.{name}", __package__)
        except ModuleNotFoundError as exc:
            if exc.name != f"{__package__}.commands.{name}":
                raise
    return mods


def build_parser(mods=None) -> argparse.ArgumentParser:
    mods = mods if mods is not None else _available()
    parser = argparse.ArgumentParser(
        prog="clutchsim", formatter_class=argparse.RawDescriptionHelpFormatter,
        description="Dry friction clutch and driveline simulation.", epilog=EPILOG)
    parser.add_argument("--version", action="version", version=f"clutchsim {__version__}")
    # the output flags work before the subcommand too (own dests: a subparser's defaults
    # would otherwise overwrite them)
    parser.add_argument("-q", "--quiet", dest="g_quiet", action="store_true",
                        help=argparse.SUPPRESS)
    parser.add_argument("-v", "--verbose", dest="g_verbose", action="store_true",
                        help=argparse.SUPPRESS)
    parser.add_argument("--debug", dest="g_debug", action="store_true", help=argparse.SUPPRESS)
    common = argparse.ArgumentParser(add_help=False)
    g = common.add_argument_group("output")
    g.add_argument("-q", "--quiet", action="store_true", help="no progress, warnings only")
    g.add_argument("-v", "--verbose", action="store_true", help="more detail on stderr")
    g.add_argument("--debug", action="store_true", help="show tracebacks for errors")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for mod in mods.values():
        mod.register(sub, common)
    return parser


def main(argv=None) -> int:
    mods = _available()
    parser = build_parser(mods)
    args = parser.parse_args(argv)
    if not args.command:
        parser.print_help(sys.stderr)
        return 2
    for flag in ("quiet", "verbose", "debug"):
        setattr(args, flag, getattr(args, flag, False) or getattr(args, f"g_{flag}", False))
    level = logging.WARNING if args.quiet else (logging.DEBUG if args.verbose else logging.INFO)
    logging.basicConfig(level=level, format="%(message)s", stream=sys.stderr, force=True)
    try:
        return int(mods[args.command].run(args) or 0)
    except (UserError, ValueError, TypeError, KeyError, FileNotFoundError) as exc:
        if getattr(args, "debug", False):
            raise
        msg = exc.args[0] if isinstance(exc, KeyError) and exc.args else exc
        print(f"clutchsim {args.command}: error: {msg}", file=sys.stderr)
        return 2
    except SimulationFailed as exc:
        if getattr(args, "debug", False):
            raise
        print(f"clutchsim {args.command}: simulation did not complete: {exc}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
