"""``clutchsim log``: inspect a vehicle log (channels, rates, units) and find its launches."""

from __future__ import annotations

import logging
from pathlib import Path

from ._common import UserError, add_force_flag, command_parser, emit_json, write_command

log = logging.getLogger("clutchsim")

HELP = """\
examples:
  clutchsim log info examples/calibration/launch_log.csv
  clutchsim log info examples/calibration/launch_log.csv --channels examples/calibration/channels.toml --json
  clutchsim log launches examples/calibration/launch_log.csv --channels examples/calibration/channels.toml --out launches/

info lists every channel of the file (name, unit, group, samples, rate, time span, gaps);
with --channels also the mapped model signals in SI units.  launches finds the launch
events (standstill, clutch closing, lock-up; docs/calibration.md) and with --out writes
each as launch_NN.csv (mapped signals, each group with its own time column) and
launches.json.  A CAN log (.blf, .asc) is decoded with --dbc or the map's [log] dbc.
"""


def register(sub, common):
    p = command_parser(sub, common, "log", help="inspect a vehicle log and find launches",
                       description="Read a vehicle log (CSV, MDF4, CAN through a DBC): its "
                       "channels, and the launches in it.", epilog=HELP)
    p.add_argument("action", choices=("info", "launches"), help="what to do")
    p.add_argument("file", metavar="FILE", help="log file (.csv, .mf4, .blf, .asc)")
    p.add_argument("--channels", metavar="MAP", help="channel map (TOML; needed by launches)")
    p.add_argument("--dbc", metavar="DBC", help="DBC decoding a CAN log (default: the map's)")
    p.add_argument("--ratio", type=float, help="gear times final drive, for lock-up from the "
                   "vehicle speed when the log has no input shaft speed")
    p.add_argument("--tyre-radius", type=float, metavar="M", help="tyre radius [m] (vehicle "
                   "speed from a wheel speed)")
    p.add_argument("--out", metavar="DIR", help="launches: write each launch to DIR")
    add_force_flag(p)
    p.add_argument("--json", action="store_true", help="print one JSON document")


def _read(args):
    from ..data.channels import load_channel_map
    from ..data.logs import read_log
    cmap = load_channel_map(args.channels) if args.channels else None
    if cmap is None:
        if args.action == "launches":
            raise UserError("log launches: --channels MAP is required (which channel is the "
                            "vehicle speed, the clutch, the engine speed)")
        return read_log(args.file, dbc=args.dbc), None
    return None, cmap.read(args.file, dbc=args.dbc)


def run(args) -> int:
    if args.out and args.action != "launches":
        raise UserError("--out is for log launches")
    if args.action == "info":
        return _info(args)
    from .._util import claim_output_dir
    if not args.out:
        return _launches(args, None)
    with claim_output_dir(args.out, "log", force=args.force) as out:
        return _launches(args, out)


def _info(args) -> int:
    raw, mapped = _read(args)
    doc = (mapped.log if mapped else raw).describe()
    if mapped is not None:
        doc["signals"] = {name: ch.describe() for name, ch in mapped.signals.items()}
    if args.json:
        emit_json(doc)
        return 0
    print(f"{doc['file']}: {len(doc['channels'])} channels, {doc['t_start']:.3f} ... "
          f"{doc['t_end']:.3f} s")
    print(f"{'channel':<32} {'unit':>6} {'group':>10} {'samples':>8} {'rate Hz':>8} "
          f"{'t0 s':>9} {'t1 s':>9} {'gaps':>5}")
    for c in doc["channels"]:
        print(f"{c['name']:<32} {c['unit']:>6} {c['group']:>10} {c['samples']:>8} "
              f"{c['rate_hz']:>8.3g} {c['t_start']:>9.3f} {c['t_end']:>9.3f} {c['gaps']:>5}")
    for name, c in doc.get("signals", {}).items():
        print(f"  {name:<16} <- {mapped.map.channels[name].name} "
              f"({mapped.map.channels[name].unit}): {c['min']:.4g} ... {c['max']:.4g} {c['unit']}")
    for note in doc["notes"]:
        log.info("note: %s", note)
    return 0


def _launches(args, out) -> int:
    from ..data.launches import LaunchOptions, find_launches
    _, mapped = _read(args)
    try:
        opts = LaunchOptions(ratio=args.ratio, tyre_radius=args.tyre_radius)
    except ValueError as exc:
        raise UserError(f"--ratio/--tyre-radius: {exc}") from None
    found = find_launches(mapped, opts)
    if not found:
        raise UserError(f"{args.file}: no launch found (a standstill of {opts.rest_time:g} s, "
                        f"then above {opts.move_speed:g} m/s with a clutch event before it)")
    doc = {"file": args.file, "launches": [la.describe() for la in found]}
    if out is not None:
        from ..data.logs import VehicleLog, write_log
        with out.build() as part:
            for la in found:
                write_log(VehicleLog(la.name, la.signals), Path(part) / f"launch_{la.index:02d}.csv")
            import json

            from .._util import atomic_write
            atomic_write(Path(part) / "launches.json", lambda p: p.write_text(
                json.dumps(doc, indent=2, allow_nan=False)))
            write_command(part, args.argv)
    if args.json:
        emit_json(doc)
        return 0
    for la in doc["launches"]:
        lock = "no lock-up" if la["t_lockup"] is None else f"lock-up {la['t_lockup']:.3f} s"
        print(f"launch {la['index']}: {la['t_start']:.3f} ... {la['t_end']:.3f} s (clutch "
              f"closing from {la['t_clutch']:.3f} s, moving {la['t_move']:.3f} s, {lock})")
    return 0
