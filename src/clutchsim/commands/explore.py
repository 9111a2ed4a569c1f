"""``clutchsim explore [SCENARIO]``: the launch explorer in the browser (a small Tornado server on
127.0.0.1 over :class:`clutchsim.explore.Session`)."""

from __future__ import annotations

import errno
import logging
import socket
import sys
from pathlib import Path

from ._common import UserError, add_scenario_flags, command_parser, emit_json

log = logging.getLogger("clutchsim")

HELP = """\
examples:
  clutchsim explore --list                         # the parameters it offers, default launch
  clutchsim explore examples/launch_actuated.toml --list --json

  clutchsim explore examples/launch.toml           # opens http://127.0.0.1:PORT/ (Ctrl-C ends)
  clutchsim explore --port 5006 --no-browser --out explored/

Sliders for the launch parameters the scenario has (the clutch's friction parameters, the
touch point of a release system, the engagement time of the clutch command's ramp, the
engine's full-load torque, vehicle mass and road grade, damper stiffness) and a field for
any numeric key path; every change re-runs the launch (a few ms: the compiled plant is
reused) and redraws the traces and launch metrics.  A refused value shows its message (the
one `clutchsim run --set` prints) beside the sliders; a run that does not complete shows
its outcome.  The server listens on 127.0.0.1 only.  With --out, the page can export the
traces, the --set items of its state and the scenario with them (explore_scenario.toml)
into that folder, and nowhere else.  See docs/explore.md.

exit status: 0 after --list, 130 when ended with Ctrl-C, 2 bad input (a scenario or value
error, a port in use, the extra clutchsim[explore] not installed).
"""


def register(sub, common):
    p = command_parser(sub, common, "explore", help="tune a launch live in the browser",
                       description="Start the launch explorer: a local web page with sliders "
                       "for the launch parameters, re-simulating on every change.",
                       epilog=HELP, scenario=True)
    add_scenario_flags(p, set_help="override a scenario key before exploring, e.g. "
                       "vehicle.grade=12")
    p.add_argument("--port", type=int, default=0, metavar="N",
                   help="TCP port on 127.0.0.1 (default: a free one)")
    p.add_argument("--no-browser", action="store_true", help="print the URL, open no browser")
    p.add_argument("--out", metavar="DIR", help="folder the page may export traces into")
    p.add_argument("--list", action="store_true",
                   help="print the parameters the explorer offers and exit")
    p.add_argument("--json", action="store_true", help="with --list: one JSON document")


def _check_port(port: int) -> None:
    if not 0 <= port <= 65535:
        raise UserError(f"--port {port}: must be 0 (a free port) or 1-65535")
    if port == 0:
        return
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        try:
            s.bind(("127.0.0.1", port))
        except OSError as exc:
            why = "is in use" if exc.errno == errno.EADDRINUSE else f"cannot be used " \
                f"({exc.strerror})"
            raise UserError(f"--port {port}: the port {why} on 127.0.0.1 (choose another, "
                            "or leave --port out for a free one)") from None


def run(args) -> int:
    from ..explore import Session
    from ..scenario import resolve_scenario
    session = Session(resolve_scenario(args.scenario, args.set or None), args.model)
    if args.list:
        rows = [{"key": p.key, "label": p.label, "unit": p.unit, "value": p.value,
                 "low": p.low, "high": p.high, "doc": p.doc} for p in session.parameters]
        if args.json:
            emit_json({"scenario": session.scenario.name, "model": session.model,
                       "models": list(session.models), "parameters": rows})
        else:
            print(f"{session.scenario.name} ({session.model or 'its own model'}):")
            for r in rows:
                print(f"  {r['key']:<52} {r['value']:>10.4g} {r['unit']:<8} "
                      f"[{r['low']:.4g}, {r['high']:.4g}]  {r['label']}")
        return 0
    if args.json:
        raise UserError("--json goes with --list (the explorer itself prints its URL)")
    _check_port(args.port)
    out = None
    if args.out:
        out = Path(args.out)
        if out.exists() and not out.is_dir():
            raise UserError(f"--out {args.out!r} is a file, not a folder")
    try:
        from ..explore.app import require_server, serve
        require_server()
    except ModuleNotFoundError as exc:
        raise UserError(str(exc)) from None

    def started(url):
        print(url, flush=True)
        log.info("clutchsim explore: %s on %s (Ctrl-C ends)", session.scenario.name, url)
    try:
        serve(session, port=args.port, open_browser=not args.no_browser, out_dir=out,
              on_start=started)
    except OSError as exc:
        if exc.errno == errno.EADDRINUSE:
            raise UserError(f"--port {args.port}: the port is in use on 127.0.0.1 (choose "
                            "another, or leave --port out for a free one)") from None
        raise
    sys.stdout.flush()
    return 0


__all__ = ["register", "run"]
