"""Vehicle logs: channels at their own rates from CSV, MDF4 and raw CAN files.

A log is a set of :class:`Channel` s, each with its own time stamps [s], values and unit, as
a data logger records them (25 Hz engine speed beside 17 Hz vehicle speed).  Nothing is
resampled here: a channel keeps its stamps.

Readers (:func:`read_log`, chosen by the file's suffix):

* ``.csv``/``.txt``: a time column per channel group.  A column named ``t``, ``time`` or
  starting ``t_``/``time_`` opens a group; the columns to its right, up to the next time
  column, are sampled at its stamps.  A header ``name [unit]`` gives the unit.  A group with
  fewer samples than the file has rows ends in empty cells; an empty cell inside a group is a
  gap (that sample is missing).
* ``.mf4``/``.mdf``/``.dat``: ASAM MDF through ``asammdf`` (each channel with its group's
  time base and its unit).
* ``.blf``/``.asc``: raw CAN frames through ``python-can``, decoded with a DBC through
  ``cantools``.  J1939 frames are matched by parameter group number (priority and source
  address ignored); each signal becomes a channel named as in the DBC, stamped with its
  frame's time.

Time stamps: a channel whose stamps go backwards is refused (``time_order="sort"`` sorts it,
said in the log's notes); equal stamps are refused too (``duplicates="first"`` keeps the
first sample, ``"mean"`` averages them).

Writers (:func:`write_log`): the same formats (CSV, MDF4, BLF/ASC through a DBC), atomically.
"""

from __future__ import annotations

import csv
import os
import re
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType

import numpy as np

from .._util import atomic_write, toml_line
from ..core.system import closest

__all__ = ["CAN_SUFFIXES", "CSV_SUFFIXES", "DUPLICATE_POLICIES", "MDF_SUFFIXES",
           "TIME_ORDER_POLICIES", "Channel", "VehicleLog", "read_log", "read_toml",
           "write_log"]

CSV_SUFFIXES = (".csv", ".txt")
MDF_SUFFIXES = (".mf4", ".mdf", ".dat")
CAN_SUFFIXES = (".blf", ".asc")
TIME_ORDER_POLICIES = ("error", "sort")
DUPLICATE_POLICIES = ("error", "first", "mean")
#: the policies of :func:`clean_stamps` (and of a channel map's [log]): key -> the values
POLICIES = {"time_order": TIME_ORDER_POLICIES, "duplicates": DUPLICATE_POLICIES}

_TIME_COLUMN = re.compile(r"^(t|time)(_.*)?$", re.IGNORECASE)
_HEADER_UNIT = re.compile(r"^\s*(.*?)\s*\[(.*)\]\s*$")


@dataclass(frozen=True, eq=False)
class Channel:
    """One logged channel: stamps ``t`` [s] (strictly increasing), ``values``, ``unit`` (""
    when the file gives none), and the ``group`` (CSV time column, MDF group, CAN message)
    it was recorded in."""

    name: str
    t: np.ndarray
    values: np.ndarray
    unit: str = ""
    group: str = ""

    @property
    def rate(self) -> float:
        """Median sampling rate [Hz]."""
        return 1.0 / float(np.median(np.diff(self.t))) if self.t.size > 1 else 0.0

    def gaps(self, factor: float = 3.0) -> list[tuple[float, float]]:
        """Intervals between samples longer than ``factor`` times the median interval."""
        if self.t.size < 3:
            return []
        dt = np.diff(self.t)
        big = np.flatnonzero(dt > factor * np.median(dt))
        return [(float(self.t[k]), float(self.t[k + 1])) for k in big]

    def describe(self) -> dict:
        return {"name": self.name, "unit": self.unit, "group": self.group,
                "samples": int(self.t.size), "rate_hz": round(self.rate, 3),
                "t_start": float(self.t[0]), "t_end": float(self.t[-1]),
                "min": float(np.min(self.values)), "max": float(np.max(self.values)),
                "gaps": len(self.gaps())}


@dataclass(frozen=True, eq=False)
class VehicleLog:
    """The channels of one log file, by name, and what the reader did (``notes``)."""

    source: str
    channels: Mapping[str, Channel]
    notes: tuple[str, ...] = ()

    def __post_init__(self):
        object.__setattr__(self, "channels", MappingProxyType(dict(self.channels)))

    def __getitem__(self, name: str) -> Channel:
        try:
            return self.channels[name]
        except KeyError:
            raise ValueError(f"{self.source}: no channel {name!r}"
                             f"{closest(name, self.channels)}; channels: "
                             f"{', '.join(self.channels) or '(none)'}") from None

    @property
    def span(self) -> tuple[float, float]:
        return (min(float(c.t[0]) for c in self.channels.values()),
                max(float(c.t[-1]) for c in self.channels.values()))

    def describe(self) -> dict:
        t0, t1 = self.span
        return {"file": self.source, "t_start": t0, "t_end": t1,
                "channels": [c.describe() for c in self.channels.values()],
                "notes": list(self.notes)}


# --------------------------------------------------------------------------- time stamps
def check_policy(key: str, value, where: str = "") -> None:
    """A ValueError (its message opening with ``where``) unless ``value`` is one of the
    :data:`POLICIES` of ``key``."""
    if value not in POLICIES[key]:
        raise ValueError(f"{where}{key} = {value!r}: must be one of {', '.join(POLICIES[key])}")


def clean_stamps(t, values, *, source: str, name: str, time_order: str = "error",
                 duplicates: str = "error", notes: list | None = None):
    """``(t, values)`` with finite, strictly increasing stamps, by the policies (see the
    module notes); NaN values are dropped (a missing sample)."""
    check_policy("time_order", time_order)
    check_policy("duplicates", duplicates)
    t = np.asarray(t, dtype=float)
    values = np.asarray(values, dtype=float)
    notes = [] if notes is None else notes
    keep = np.isfinite(t) & np.isfinite(values)
    t, values = t[keep], values[keep]
    if t.size < 2:
        raise ValueError(f"{source}: channel {name!r} has {t.size} valid sample(s); need >= 2")
    dt = np.diff(t)
    back = np.flatnonzero(dt < 0)
    if back.size:
        k = int(back[0])
        if time_order == "error":
            raise ValueError(
                f"{source}: channel {name!r}: the time base goes backwards at sample {k + 1} "
                f"(t = {t[k]:.6g} s, then {t[k + 1]:.6g} s; {back.size} place(s)); the rule: "
                "stamps must increase (set time_order = \"sort\" in the channel map's [log] "
                "table to sort them)")
        order = np.argsort(t, kind="stable")
        t, values = t[order], values[order]
        notes.append(f"{name}: {back.size} backward stamp(s) sorted")
        dt = np.diff(t)
    same = np.flatnonzero(dt == 0)
    if same.size:
        if duplicates == "error":
            k = int(same[0])
            raise ValueError(
                f"{source}: channel {name!r}: duplicated time stamp t = {t[k]:.6g} s at samples "
                f"{k} and {k + 1} ({same.size} duplicate(s)); the rule: one sample per stamp "
                "(set duplicates = \"first\" or \"mean\" in the channel map's [log] table)")
        uniq, start, count = np.unique(t, return_index=True, return_counts=True)
        if duplicates == "first":
            values = values[start]
        else:
            values = np.add.reduceat(values, start) / count
        t = uniq
        notes.append(f"{name}: {same.size} duplicated stamp(s), kept the {duplicates}")
    return t, values


# --------------------------------------------------------------------------- readers
def read_log(path: str | Path, *, dbc: str | Path | None = None, time_order: str = "error",
             duplicates: str = "error") -> VehicleLog:
    """Read a vehicle log (CSV, MDF4, or BLF/ASC with ``dbc``); see the module notes.

    Raises ValueError naming the file, the channel and the rule broken.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if not path.is_file():
        raise FileNotFoundError(2, "no such log file", str(path))
    notes: list[str] = []
    if suffix in CSV_SUFFIXES:
        raw = _read_csv(path)
    elif suffix in MDF_SUFFIXES:
        raw = _read_mdf(path)
    elif suffix in CAN_SUFFIXES:
        if dbc is None:
            raise ValueError(f"{path}: a CAN log needs a DBC to decode its frames (--dbc, or "
                             "dbc in the channel map's [log] table)")
        raw = _read_can(path, Path(dbc))
    else:
        raise ValueError(f"{path}: unknown log format {suffix or '(no suffix)'!r}; read are "
                         f"{', '.join(CSV_SUFFIXES + MDF_SUFFIXES + CAN_SUFFIXES)}")
    channels = {}
    for name, (t, values, unit, group) in raw.items():
        t, values = clean_stamps(t, values, source=str(path), name=name,
                                 time_order=time_order, duplicates=duplicates, notes=notes)
        channels[name] = Channel(name, t, values, unit, group)
    if not channels:
        raise ValueError(f"{path}: no channels found")
    return VehicleLog(str(path), channels, tuple(notes))


def _read_csv(path: Path) -> dict:
    with open(path, newline="", encoding="utf-8-sig") as fh:
        rows = [row for row in csv.reader(fh) if row and any(c.strip() for c in row)]
    if not rows:
        raise ValueError(f"{path}: empty file")
    header = [_split_header(h) for h in rows[0]]
    if not _TIME_COLUMN.match(header[0][0]):
        raise ValueError(f"{path}: the first column {rows[0][0]!r} is not a time column (name "
                         "it t, time, t_GROUP or time_GROUP; each time column opens a group)")
    data = np.full((len(rows) - 1, len(header)), np.nan)
    for i, row in enumerate(rows[1:], start=2):
        for j, cell in enumerate(row[:len(header)]):
            cell = cell.strip()
            if cell:
                try:
                    data[i - 2, j] = float(cell)
                except ValueError:
                    raise ValueError(f"{path}:{i}: column {rows[0][j]!r}: {cell!r} is not a "
                                     "number") from None
    out = {}
    time_col = 0
    for j, (name, unit) in enumerate(header):
        if _TIME_COLUMN.match(name):
            time_col = j
            if unit not in ("", "s"):
                raise ValueError(f"{path}: time column {rows[0][j]!r} is in {unit!r}; the "
                                 "rule: time columns are in s")
            continue
        if name in out:
            raise ValueError(f"{path}: column {name!r} appears twice")
        group = re.sub(r"^(t|time)_", "", header[time_col][0], flags=re.IGNORECASE)
        out[name] = (data[:, time_col], data[:, j], unit, group)
    return out


def _split_header(text: str) -> tuple[str, str]:
    m = _HEADER_UNIT.match(text)
    return (m.group(1), m.group(2).strip()) if m else (text.strip(), "")


def _need(module: str, what: str):
    """Import an optional dependency of the log formats, or say which extra installs it."""
    import importlib
    import logging
    # asammdf imports numexpr, which says how many threads it takes on the root logger
    logging.getLogger("numexpr").setLevel(logging.WARNING)
    try:
        return importlib.import_module(module)
    except ImportError:
        raise ValueError(f"{what} needs the package {module!r}: install clutchsim[logs]") \
            from None


def _read_mdf(path: Path) -> dict:
    MDF = _need("asammdf", f"reading {path.name} (MDF)").MDF
    out = {}
    with MDF(str(path)) as mdf:
        for name, places in mdf.channels_db.items():
            gi, ci = places[0]
            if mdf.masters_db.get(gi) == ci or name in out:
                continue
            sig = mdf.get(name, group=gi, index=ci)
            if sig.samples.dtype.kind not in "fiub":
                continue
            comment = str(mdf.groups[gi].channel_group.comment or "") or f"group {gi}"
            out[name] = (np.asarray(sig.timestamps, dtype=float),
                         np.asarray(sig.samples, dtype=float), str(sig.unit or ""), comment)
    return out


def _pgn(arbitration_id: int) -> int:
    """The J1939 parameter group number of a 29-bit identifier (destination of PDU1 off)."""
    pgn = (arbitration_id >> 8) & 0x3FFFF
    if (pgn >> 8) & 0xFF < 240:
        pgn &= 0x3FF00
    return pgn


def load_dbc(dbc: Path):
    cantools = _need("cantools", f"decoding with {dbc.name}")
    if not dbc.is_file():
        raise FileNotFoundError(2, "no such DBC file", str(dbc))
    try:
        return cantools.database.load_file(str(dbc))
    except Exception as exc:  # noqa: BLE001  (cantools raises its own parse errors)
        raise ValueError(f"{dbc}: not a readable DBC: {exc}") from None


def _read_can(path: Path, dbc: Path) -> dict:
    can = _need("can", f"reading {path.name} (CAN)")
    db = load_dbc(dbc)
    by_id = {m.frame_id: m for m in db.messages}
    by_pgn = {_pgn(m.frame_id): m for m in db.messages if m.is_extended_frame}
    stamps: dict[str, list] = {}
    frames = unknown = 0
    ids = set()
    reader = can.LogReader(str(path))
    try:
        for frame in reader:
            if frame.is_error_frame or frame.is_remote_frame:
                continue
            frames += 1
            ids.add(frame.arbitration_id)
            msg = by_pgn.get(_pgn(frame.arbitration_id)) if frame.is_extended_id \
                else by_id.get(frame.arbitration_id)
            if msg is None:
                unknown += 1
                continue
            try:
                decoded = msg.decode(bytes(frame.data), decode_choices=False)
            except Exception as exc:  # noqa: BLE001  (cantools' decode errors vary)
                raise ValueError(f"{path}: frame 0x{frame.arbitration_id:X} at t = "
                                 f"{frame.timestamp:.6g} s: the DBC {dbc.name} message "
                                 f"{msg.name} does not decode it ({exc})") from None
            for name, value in decoded.items():
                stamps.setdefault(name, [msg.name, []])[1].append((frame.timestamp, value))
    finally:
        stop = getattr(reader, "stop", None)
        if stop is not None:
            stop()
    if frames and unknown == frames:
        shown = ", ".join(f"0x{i:X}" for i in sorted(ids)[:5])
        raise ValueError(f"{path}: the DBC {dbc} decodes none of its {frames} frames (ids "
                         f"{shown}{', ...' if len(ids) > 5 else ''}); the rule: the log's "
                         "frames must be messages of the DBC")
    units = {s.name: str(s.unit or "") for m in db.messages for s in m.signals}
    out = {}
    for name, (group, pairs) in stamps.items():
        arr = np.array(pairs, dtype=float)
        out[name] = (arr[:, 0], arr[:, 1], units.get(name, ""), group)
    return out


# --------------------------------------------------------------------------- writers
def write_log(log: VehicleLog, path: str | Path, *, dbc: str | Path | None = None) -> Path:
    """Write ``log`` to ``path`` (format by suffix; a CAN log encodes the channels into the
    messages of ``dbc`` whose signals they are, one frame per stamp of its group)."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix in CSV_SUFFIXES:
        return atomic_write(path, lambda p: _write_csv(log, p))
    if suffix in MDF_SUFFIXES:
        return atomic_write(path, lambda p: _via_suffix(p, ".mf4", lambda q: _write_mdf(log, q)))
    if suffix in CAN_SUFFIXES:
        if dbc is None:
            raise ValueError(f"{path}: writing a CAN log needs a DBC")
        return atomic_write(path, lambda p: _via_suffix(
            p, suffix, lambda q: _write_can(log, q, Path(dbc))))
    raise ValueError(f"{path}: unknown log format {suffix!r}")


def _via_suffix(tmp: Path, suffix: str, write) -> None:
    """Let a writer that picks its format by suffix write ``tmp`` (a temporary name)."""
    inner = tmp.with_name(tmp.name + suffix)
    try:
        write(inner)
        os.replace(inner, tmp)
    finally:
        inner.unlink(missing_ok=True)


def _groups(log: VehicleLog) -> dict[str, list[Channel]]:
    groups: dict[str, list[Channel]] = {}
    for ch in log.channels.values():
        groups.setdefault(ch.group or ch.name, []).append(ch)
    for name, members in groups.items():
        for ch in members[1:]:
            if not np.array_equal(ch.t, members[0].t):
                raise ValueError(f"group {name!r}: channels {members[0].name!r} and "
                                 f"{ch.name!r} have different stamps")
    return groups


def _write_csv(log: VehicleLog, p: Path) -> None:
    groups = _groups(log)
    n = max(members[0].t.size for members in groups.values())
    header, cols = [], []
    for gname, members in groups.items():
        header.append(f"t_{gname} [s]")
        cols.append(members[0].t)
        for ch in members:
            header.append(f"{ch.name} [{ch.unit}]" if ch.unit else ch.name)
            cols.append(ch.values)
    with open(p, "w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(header)
        for i in range(n):
            w.writerow([repr(float(c[i])) if i < c.size else "" for c in cols])


def _write_mdf(log: VehicleLog, p: Path) -> None:
    asammdf = _need("asammdf", "writing MDF")
    MDF, Signal = asammdf.MDF, asammdf.Signal
    mdf = MDF(version="4.10")
    for gname, members in _groups(log).items():
        mdf.append([Signal(samples=np.asarray(ch.values), timestamps=np.asarray(ch.t),
                           name=ch.name, unit=ch.unit, comment=gname) for ch in members],
                   comment=gname)
    mdf.save(str(p), overwrite=True)
    mdf.close()


def _write_can(log: VehicleLog, p: Path, dbc: Path) -> None:
    can = _need("can", "writing a CAN log")
    db = load_dbc(dbc)
    frames = []
    for gname, members in _groups(log).items():
        try:
            msg = db.get_message_by_name(gname)
        except KeyError:
            raise ValueError(f"group {gname!r}: no message of that name in {dbc}") from None
        given = {ch.name: ch.values for ch in members}
        for ch in members:
            if ch.name not in [s.name for s in msg.signals]:
                raise ValueError(f"channel {ch.name!r}: not a signal of {dbc.name} message "
                                 f"{msg.name}")
        for k, stamp in enumerate(members[0].t):
            data = {s.name: float(given[s.name][k]) if s.name in given
                    else float(s.minimum if s.minimum is not None else 0.0)
                    for s in msg.signals}
            frames.append(can.Message(timestamp=float(stamp), arbitration_id=msg.frame_id,
                                      is_extended_id=msg.is_extended_frame,
                                      data=msg.encode(data), channel=0))
    frames.sort(key=lambda m: m.timestamp)
    with can.Logger(str(p)) as writer:
        for frame in frames:
            writer.on_message_received(frame)


def read_toml(path: Path, error: type[Exception] = ValueError):
    """``(locate, document, text)`` of a TOML file: ``locate(table, key=None)`` is the
    ``"FILE:LINE: [table] key"`` prefix of a message (:func:`clutchsim._util.toml_line`); a
    file that is not TOML raises ``error`` naming it."""
    import tomllib
    text = path.read_text(encoding="utf-8")
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise error(f"{path}: not valid TOML: {exc}") from None

    def locate(table: str, key: str | None = None) -> str:
        line = toml_line(text, table, key)
        return f"{path}{f':{line}' if line else ''}: [{table}]" + (f" {key}" if key else "")
    return locate, doc, text
