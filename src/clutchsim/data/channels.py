"""The channel map: which log channel is which model signal, in which unit.

A TOML file (examples/calibration/channels.toml)::

    [log]
    dbc = "j1939_launch.dbc"      # decodes CAN logs (relative to this file)
    time_order = "error"          # or "sort": stamps that go backwards
    duplicates = "error"          # or "first", "mean": equal stamps
    reference_torque = 400.0      # N·m: 100 % of an engine torque given in %

    [channels.engine_speed]
    name = "EngineSpeed"          # the channel in the log (CSV column, MDF channel, DBC signal)
    unit = "rpm"                  # the unit the log records it in
    scale = 1.0                   # optional: value = scale · logged + offset, in ``unit``
    offset = 0.0

Signals (:data:`SIGNALS`) and the units each accepts (:data:`UNITS`); a mapped signal is
converted to SI (rad/s, m/s, m, N·m; a pedal position or throttle in % to a fraction).  When
the log states a unit (MDF, the DBC, a CSV header ``name [unit]``) it must be the map's: a
channel in km/h mapped as m/s is refused, never converted silently.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType

import numpy as np

from .._util import toml_line
from ..core.system import closest
from .logs import POLICIES, Channel, VehicleLog, check_policy, read_log, read_toml

__all__ = ["SIGNALS", "UNITS", "ChannelMap", "ChannelSpec", "MappedLog", "load_channel_map",
           "map_log"]

#: model signal -> its quantity
SIGNALS: Mapping[str, str] = MappingProxyType({
    "engine_speed": "rotational speed",
    "input_speed": "rotational speed",       # gearbox input shaft
    "wheel_speed": "rotational speed",
    "vehicle_speed": "speed",
    "clutch_position": "travel",             # engagement travel (increasing closes)
    "clutch_switch": "switch",               # 1 pedal pressed (clutch open), 0 released
    "engine_torque": "torque",
    "throttle": "fraction",
    "gear": "count",
})
#: quantity -> unit -> factor to SI (None: % of the reference torque)
UNITS: Mapping[str, Mapping[str, float | None]] = MappingProxyType({
    "rotational speed": {"rpm": math.pi / 30.0, "1/min": math.pi / 30.0,
                         "min-1": math.pi / 30.0, "rad/s": 1.0},
    "speed": {"km/h": 1.0 / 3.6, "m/s": 1.0},
    "travel": {"mm": 1e-3, "m": 1.0, "%": 0.01},
    "switch": {"": 1.0, "-": 1.0},
    "torque": {"N·m": 1.0, "Nm": 1.0, "N m": 1.0, "%": None},
    "fraction": {"%": 0.01, "-": 1.0, "": 1.0},
    "count": {"": 1.0, "-": 1.0},
})
#: the SI unit of each quantity after mapping
SI_UNIT = {"rotational speed": "rad/s", "speed": "m/s", "travel": "m", "switch": "-",
           "torque": "N·m", "fraction": "-", "count": "-"}
_ALIASES = {"1/min": "rpm", "min-1": "rpm", "Nm": "N·m", "N m": "N·m", "N.m": "N·m",
            "kph": "km/h", "-": ""}
_LOG_KEYS = ("dbc", "time_order", "duplicates", "reference_torque")
_CHANNEL_KEYS = ("name", "unit", "scale", "offset")


def _same_unit(a: str, b: str) -> bool:
    return _ALIASES.get(a.strip(), a.strip()) == _ALIASES.get(b.strip(), b.strip())


@dataclass(frozen=True)
class ChannelSpec:
    """One mapped signal: the log channel ``name``, its ``unit``, ``scale`` and ``offset``,
    and the ``line`` of its table in the map file."""

    signal: str
    name: str
    unit: str
    scale: float = 1.0
    offset: float = 0.0
    line: int | None = None


@dataclass(frozen=True, eq=False)
class ChannelMap:
    """A parsed channel map (see the module notes)."""

    path: str
    channels: Mapping[str, ChannelSpec]
    dbc: Path | None = None
    time_order: str = "error"
    duplicates: str = "error"
    reference_torque: float | None = None
    text: str = ""

    def where(self, table: str, key: str | None = None) -> str:
        line = toml_line(self.text, table, key)
        return f"{self.path}:{line}" if line else self.path

    def read(self, path: str | Path, dbc: str | Path | None = None) -> MappedLog:
        """Read a log and map it (:func:`map_log`)."""
        log = read_log(path, dbc=dbc or self.dbc, time_order=self.time_order,
                       duplicates=self.duplicates)
        return map_log(log, self)


def load_channel_map(path: str | Path) -> ChannelMap:
    """Read and check a channel map; ValueError names the file, line, key and rule."""
    path = Path(path)
    locate, doc, text = read_toml(path)

    def where(table, key=None):
        return locate(table, key).partition(": [")[0]

    def known_keys(table, entries, keys):
        for key in entries:
            if key not in keys:
                raise ValueError(f"{where(table, key)}: [{table}] {key}: unknown key"
                                 f"{closest(key, keys)}; keys: {', '.join(keys)}")

    for top in doc:
        if top not in ("log", "channels"):
            raise ValueError(f"{where(top)}: unknown table [{top}]{closest(top, ('log', 'channels'))}"
                             "; the map has [log] and [channels.SIGNAL]")
    log = doc.get("log", {})
    known_keys("log", log, _LOG_KEYS)
    for key in POLICIES:
        if key in log:
            check_policy(key, log[key], f"{where('log', key)}: [log] ")
    ref = log.get("reference_torque")
    if ref is not None and not (isinstance(ref, (int, float)) and math.isfinite(ref) and ref > 0):
        raise ValueError(f"{where('log', 'reference_torque')}: [log] reference_torque = "
                         f"{ref!r}: must be a torque > 0 [N·m]")
    channels = {}
    raw = doc.get("channels", {})
    if not isinstance(raw, dict) or not raw:
        raise ValueError(f"{where('channels')}: no [channels.SIGNAL] tables; signals: "
                         f"{', '.join(SIGNALS)}")
    for signal, entry in raw.items():
        table = f"channels.{signal}"
        if signal not in SIGNALS:
            raise ValueError(f"{where(table)}: [{table}]: unknown signal{closest(signal, SIGNALS)}"
                             f"; signals: {', '.join(SIGNALS)}")
        if not isinstance(entry, dict):
            raise TypeError(f"{where(table)}: [{table}] must be a table with name and unit")
        known_keys(table, entry, _CHANNEL_KEYS)
        for key in ("name", "unit"):
            if not isinstance(entry.get(key), str):
                raise TypeError(f"{where(table, key)}: [{table}] {key}: give the log channel's "
                                 f"{'name' if key == 'name' else 'unit'} as a string")
        quantity = SIGNALS[signal]
        unit = _ALIASES.get(entry["unit"].strip(), entry["unit"].strip()) \
            if entry["unit"].strip() != "-" else "-"
        allowed = UNITS[quantity]
        if not any(_same_unit(unit, u) for u in allowed):
            raise ValueError(f"{where(table, 'unit')}: [{table}] unit = {entry['unit']!r}: "
                             f"{signal} is a {quantity}, in one of "
                             f"{', '.join(repr(u) for u in allowed)}")
        if unit == "%" and quantity == "torque" and ref is None:
            raise ValueError(f"{where(table, 'unit')}: [{table}] unit = '%' needs [log] "
                             "reference_torque (N·m at 100 %)")
        for key in ("scale", "offset"):
            value = entry.get(key, 1.0 if key == "scale" else 0.0)
            if not (isinstance(value, (int, float)) and math.isfinite(value)) or (
                    key == "scale" and value == 0):
                raise ValueError(f"{where(table, key)}: [{table}] {key} = {value!r}: must be a "
                                 f"finite number{' other than 0' if key == 'scale' else ''}")
        channels[signal] = ChannelSpec(signal, entry["name"], unit, float(entry.get("scale", 1.0)),
                                       float(entry.get("offset", 0.0)), toml_line(text, table))
    dbc = log.get("dbc")
    if dbc is not None and not isinstance(dbc, str):
        raise ValueError(f"{where('log', 'dbc')}: [log] dbc must be a file name")
    return ChannelMap(str(path), MappingProxyType(channels),
                      (path.parent / dbc) if dbc else None, log.get("time_order", "error"),
                      log.get("duplicates", "error"), None if ref is None else float(ref), text)


@dataclass(frozen=True, eq=False)
class MappedLog:
    """A log's mapped signals in SI units (each a :class:`Channel` named by its signal, with
    the stamps of its log channel), the log itself, and the map."""

    source: str
    signals: Mapping[str, Channel]
    log: VehicleLog
    map: ChannelMap

    def __getitem__(self, signal: str) -> Channel:
        try:
            return self.signals[signal]
        except KeyError:
            raise ValueError(f"{self.source}: signal {signal!r} is not mapped (add "
                             f"[channels.{signal}] to {self.map.path})") from None

    def has(self, signal: str) -> bool:
        return signal in self.signals

    def window(self, t0: float, t1: float) -> dict[str, Channel]:
        """The signals cut to ``t0 <= t <= t1``."""
        out = {}
        for name, ch in self.signals.items():
            keep = (ch.t >= t0) & (ch.t <= t1)
            out[name] = Channel(name, ch.t[keep], ch.values[keep], ch.unit, ch.group)
        return out


def map_log(log: VehicleLog, cmap: ChannelMap) -> MappedLog:
    """The signals of ``cmap`` taken from ``log``: channel present, unit as stated, SI."""
    out = {}
    for signal, spec in cmap.channels.items():
        table = f"channels.{signal}"
        if spec.name not in log.channels:
            raise ValueError(f"{log.source}: no channel {spec.name!r} (mapped to {signal} at "
                             f"{cmap.where(table, 'name')}){closest(spec.name, log.channels)}; "
                             f"channels: {', '.join(log.channels)}")
        ch = log.channels[spec.name]
        if ch.unit and not _same_unit(ch.unit, spec.unit):
            raise ValueError(f"{log.source}: channel {spec.name!r} is in {ch.unit!r} but "
                             f"{cmap.where(table, 'unit')} [{table}] unit says {spec.unit!r}; "
                             "the rule: the map states the unit the log records (fix the map, "
                             "or the scale)")
        quantity = SIGNALS[signal]
        factor = UNITS[quantity][next(u for u in UNITS[quantity] if _same_unit(u, spec.unit))]
        if factor is None:
            factor = 0.01 * float(cmap.reference_torque)
        values = (spec.scale * ch.values + spec.offset) * factor
        unit = "-" if (quantity == "travel" and spec.unit == "%") else SI_UNIT[quantity]
        out[signal] = Channel(signal, ch.t, np.asarray(values, dtype=float), unit, ch.group)
    return MappedLog(log.source, MappingProxyType(out), log, cmap)
