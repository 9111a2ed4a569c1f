"""The ``clutchsim`` command line: a thin layer over the public functions.

Every subcommand lives in :mod:`clutchsim.commands` as a module with ``register(sub)``
(adds its argparse subparser) and ``run(args) -> int``.  Conventions, shared by all:

* exit status 0 success, 1 a simulation that did not complete (its message is printed),
  2 bad input (a one-line message naming the argument/file/key, and a hint; also an
  output path that cannot be written and a run or sweep above its size limits), 130 / 143
  interrupted by SIGINT / SIGTERM (partial outputs are removed; a sweep keeps its finished
  chunks to resume);
* ``--out DIR`` never deletes a file clutchsim did not write: DIR is replaced only when it
  is empty or an earlier output of the same command, else refused up front (``--force``:
  written beside the other files, which are kept); see :mod:`clutchsim._util`;
* ``--json`` prints exactly one JSON document on stdout; progress and logs go to stderr;
* ``--quiet`` silences progress and info logs, ``--verbose`` adds detail, ``--debug``
  shows tracebacks instead of one-line messages.
"""

from __future__ import annotations

import argparse
import importlib
import logging
import os
import signal
import sys

from ._version import __version__
from .commands._common import SimulationFailed, UserError, emit_json

__all__ = ["SimulationFailed", "Terminated", "UserError", "emit_json", "main"]

#: subcommand modules, in the order ``--help`` lists them
COMMANDS = ("models", "rig", "bench", "run", "judder", "demo", "sweep", "fit", "report",
            "fmu", "rt", "durability", "uq", "log", "calibrate", "explore")

EPILOG = """\
examples:
  clutchsim demo                                  # default launch + drift test, HTML report
  clutchsim models                                # the friction models, states and parameters
  clutchsim rig --model lugre --force 0 --spring 2 --pull-speed 0.1 --t-end 30 --out rig.csv
  clutchsim bench drift --model lugre --model elastoplastic --out drift/ --json
  clutchsim run examples/launch.toml --model mykhailevych2020 --out launch/
  clutchsim fmu examples/launch.toml --model mykhailevych2020 --out launch.fmu
  clutchsim rt examples/launch.toml --step 1e-3 --out rt/
  clutchsim log launches examples/calibration/launch_log.csv --channels examples/calibration/channels.toml
  clutchsim calibrate examples/calibration/launch_calibration.toml --out calib/
  clutchsim explore --list                        # the launch explorer's parameters

exit status: 0 success, 1 a simulation did not complete, 2 bad input.
"""

log = logging.getLogger("clutchsim")


class Terminated(BaseException):
    """SIGTERM, raised in the main thread so that partial outputs are cleaned up as for
    Ctrl-C (a ``BaseException``: no ``except Exception`` swallows it)."""


#: longest error message printed (a message quoting a 200 KB input is cut)
MAX_MESSAGE = 2000


def _on_sigterm(signum, frame):
    raise Terminated()


#: it stops the program: a run of the compiled loop is cut short when it arrives
#: (:func:`clutchsim.core.simulate.interrupts_deferred`)
_on_sigterm.interrupts = True


def _one_line(exc: BaseException) -> str:
    """The message of ``exc`` as the one line the command prints."""
    if isinstance(exc, KeyError) and exc.args:
        msg = str(exc.args[0])
    elif isinstance(exc, OSError) and exc.filename is not None and exc.strerror:
        msg = f"{exc.filename}: {exc.strerror}"
    elif isinstance(exc, RecursionError):
        msg = ("an input is nested too deeply to read (Python's recursion limit); "
               "flatten the expression or file")
    elif isinstance(exc, MemoryError):
        msg = "out of memory: the input asks for more than this machine has"
    else:
        msg = str(exc) or type(exc).__name__
    if len(msg) > MAX_MESSAGE:
        msg = msg[:MAX_MESSAGE] + f"... ({len(msg):,} characters)"
    return msg


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
    argv = sys.argv[1:] if argv is None else list(argv)
    args = parser.parse_args(argv)
    args.argv = argv     # the command line as given, for command.txt
    if not args.command:
        parser.print_help(sys.stderr)
        return 2
    for flag in ("quiet", "verbose", "debug"):
        setattr(args, flag, getattr(args, flag, False) or getattr(args, f"g_{flag}", False))
    level = logging.WARNING if args.quiet else (logging.DEBUG if args.verbose else logging.INFO)
    # clutchsim's own progress at that level; other libraries' at WARNING (INFO with
    # --verbose): pandas' NumExpr said "NumExpr defaulting to 2 threads." on every run
    logging.basicConfig(level=logging.INFO if args.verbose else logging.WARNING,
                        format="%(message)s", stream=sys.stderr, force=True)
    logging.getLogger("clutchsim").setLevel(level)
    previous = _install_sigterm()
    name = f"clutchsim {args.command}"
    try:
        return int(mods[args.command].run(args) or 0)
    except (UserError, ValueError, TypeError, KeyError, OSError, RecursionError,
            MemoryError) as exc:
        if isinstance(exc, BrokenPipeError):
            return _broken_pipe()
        if args.debug:
            raise
        print(f"{name}: error: {_one_line(exc)}", file=sys.stderr)
        return 2
    except SimulationFailed as exc:
        if args.debug:
            raise
        print(f"{name}: simulation did not complete: {_one_line(exc)}", file=sys.stderr)
        return 1
    except (KeyboardInterrupt, Terminated) as exc:
        what = "SIGTERM" if isinstance(exc, Terminated) else "SIGINT"
        print(f"{name}: interrupted ({what})", file=sys.stderr)
        return 143 if isinstance(exc, Terminated) else 130
    except Exception as exc:   # a bug must still end in one line, not a traceback
        if args.debug:
            raise
        print(f"{name}: internal error: {type(exc).__name__}: {_one_line(exc)} (this is a "
              "bug in clutchsim; --debug shows the traceback)", file=sys.stderr)
        return 1
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)


def _install_sigterm():
    """Turn SIGTERM into :class:`Terminated` in the main thread (the previous handler is
    returned, ``None`` when none was installed: not the main thread)."""
    try:
        return signal.signal(signal.SIGTERM, _on_sigterm)
    except ValueError:   # not the main thread of the interpreter
        return None


def _broken_pipe() -> int:
    """stdout was closed by the reader (``clutchsim ... --json | head``): stop quietly."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError):
        pass
    return 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
