"""Launch events in a vehicle log: from standstill, the clutch closing, lock-up.

:func:`find_launches` scans a mapped log (:class:`~clutchsim.data.channels.MappedLog`):

1. *standstill*: the vehicle speed (``vehicle_speed``, else ``wheel_speed`` times the tyre
   radius) at or below ``rest_speed`` for at least ``rest_time``;
2. *move*: the first sample after a standstill above ``move_speed``;
3. *clutch event*: the last time before the move at which the clutch was open: the clutch
   position within 10 % of the log's travel range from its open end (``clutch_position``),
   else the clutch switch still pressed (``clutch_switch`` = 1);
4. *lock-up*: the first time after the clutch event from which the slip ``|w_engine −
   w_input|`` stays below ``lockup_slip`` for ``lockup_time`` (the input speed is
   ``input_speed``, else the wheel speed times ``ratio``);
5. the launch record runs from ``pre`` before the clutch event to ``post`` after lock-up
   (cut short by the next standstill and the end of the log).

Every channel keeps its own stamps in the record (nothing is resampled).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .channels import MappedLog
from .logs import Channel

__all__ = ["Launch", "LaunchOptions", "cut_launch", "find_launches", "slip_end"]


@dataclass(frozen=True)
class LaunchOptions:
    """Thresholds of the launch finder (SI units: m/s, s, rad/s; ``ratio`` gear times final
    drive and ``tyre_radius`` [m] for a log without input shaft or vehicle speed)."""

    rest_speed: float = 0.1
    rest_time: float = 0.5
    move_speed: float = 0.6
    lockup_slip: float = 3.0
    lockup_time: float = 0.2
    pre: float = 0.3
    post: float = 1.5
    ratio: float | None = None
    tyre_radius: float | None = None

    def __post_init__(self):
        for name in ("rest_speed", "rest_time", "move_speed", "lockup_slip", "lockup_time",
                     "pre", "post", "ratio", "tyre_radius"):
            value = getattr(self, name)
            if value is None and name in ("ratio", "tyre_radius"):
                continue
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value >= 0):
                raise ValueError(f"launch option {name} = {value!r}: must be a finite "
                                 "number >= 0")
        if self.move_speed <= self.rest_speed:
            raise ValueError(f"launch options: move_speed = {self.move_speed:g} m/s must be "
                             f"above rest_speed = {self.rest_speed:g} m/s")


@dataclass(frozen=True, eq=False)
class Launch:
    """One launch cut from a log: its times [s] and its signals (SI, own stamps)."""

    source: str
    index: int
    t_start: float
    t_clutch: float
    t_move: float
    t_lockup: float | None
    t_end: float
    signals: dict

    @property
    def name(self) -> str:
        return f"{self.source}#{self.index}"

    def describe(self) -> dict:
        return {"source": self.source, "index": self.index, "t_start": self.t_start,
                "t_clutch": self.t_clutch, "t_move": self.t_move, "t_lockup": self.t_lockup,
                "t_end": self.t_end, "duration": self.t_end - self.t_start,
                "samples": {n: int(c.t.size) for n, c in self.signals.items()}}


def _speed(log: MappedLog, opts: LaunchOptions) -> Channel:
    if log.has("vehicle_speed"):
        return log["vehicle_speed"]
    if log.has("wheel_speed"):
        if opts.tyre_radius is None:
            raise ValueError(f"{log.source}: finding launches from wheel_speed needs the tyre "
                             "radius (tyre_radius)")
        ch = log["wheel_speed"]
        return Channel("vehicle_speed", ch.t, ch.values * opts.tyre_radius, "m/s", ch.group)
    raise ValueError(f"{log.source}: finding launches needs vehicle_speed or wheel_speed in "
                     f"the channel map {log.map.path}")


def _input_speed(log: MappedLog, opts: LaunchOptions) -> Channel:
    if log.has("input_speed"):
        return log["input_speed"]
    v = _speed(log, opts)
    if opts.ratio is None or opts.tyre_radius is None:
        raise ValueError(f"{log.source}: lock-up without input_speed needs ratio and "
                         "tyre_radius (the input speed from the vehicle speed)")
    return Channel("input_speed", v.t, v.values / opts.tyre_radius * opts.ratio, "rad/s")


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    edges = np.diff(np.concatenate([[0], mask.astype(np.int8), [0]]))
    return list(zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1))


def _clutch_open_until(log: MappedLog, t0: float, t1: float) -> float | None:
    """The last time in ``[t0, t1]`` at which the clutch was open (None: no clutch event)."""
    if log.has("clutch_position"):
        ch = log["clutch_position"]
        keep = (ch.t >= t0) & (ch.t <= t1)
        t, x = ch.t[keep], ch.values[keep]
        # open: within 10 % of the log's whole travel range from its open end
        lo, hi = float(np.min(ch.values)), float(np.max(ch.values))
        if t.size < 2 or hi - lo <= 1e-9:
            return None
        open_ = np.flatnonzero(x <= lo + 0.1 * (hi - lo))
        if open_.size == 0 or open_[-1] == t.size - 1:
            return None
        return float(t[open_[-1]])
    if log.has("clutch_switch"):
        ch = log["clutch_switch"]
        keep = (ch.t >= t0) & (ch.t <= t1)
        t, s = ch.t[keep], ch.values[keep]
        pressed = np.flatnonzero(s >= 0.5)
        if pressed.size == 0 or pressed[-1] == t.size - 1:
            return None
        return float(t[pressed[-1]])
    raise ValueError(f"{log.source}: finding a clutch event needs clutch_position or "
                     f"clutch_switch in the channel map {log.map.path}")


def slip_end(t_engine, w_engine, t_input, w_input, t_from: float, slip: float,
             hold: float) -> float | None:
    """First time after ``t_from`` from which ``|w_engine − w_input|`` stays below ``slip``
    for ``hold`` seconds (on the engine's stamps), or None."""
    t_engine = np.asarray(t_engine)
    keep = t_engine >= t_from
    t = t_engine[keep]
    if t.size == 0:
        return None
    s = np.abs(np.asarray(w_engine)[keep] - np.interp(t, t_input, w_input))
    for a, b in _runs(s < slip):
        if t[b] - t[a] >= hold:
            return float(t[a])
    return None


def _lockup(log: MappedLog, opts: LaunchOptions, t_from: float, t_to: float) -> float | None:
    if not log.has("engine_speed"):
        raise ValueError(f"{log.source}: lock-up needs engine_speed in the channel map "
                         f"{log.map.path}")
    e, i = log["engine_speed"], _input_speed(log, opts)
    keep = e.t <= t_to
    return slip_end(e.t[keep], e.values[keep], i.t, i.values, t_from, opts.lockup_slip,
                    opts.lockup_time)


def find_launches(log: MappedLog, options: LaunchOptions | None = None) -> list[Launch]:
    """The launches of ``log`` (see the module notes), in time order; empty when none."""
    opts = options or LaunchOptions()
    v = _speed(log, opts)
    rest = _runs(v.values <= opts.rest_speed)
    rest = [(a, b) for a, b in rest if v.t[b] - v.t[a] >= opts.rest_time
            or (a == 0 and v.t[b] - v.t[a] >= 0.5 * opts.rest_time)]
    out = []
    t_last = v.t[-1]
    for k, (a, b) in enumerate(rest):
        nxt = rest[k + 1][0] if k + 1 < len(rest) else v.t.size
        moving = np.flatnonzero(v.values[b + 1:nxt] > opts.move_speed)
        if moving.size == 0:
            continue
        t_move = float(v.t[b + 1 + moving[0]])
        t_open = _clutch_open_until(log, float(v.t[a]), t_move)
        if t_open is None:
            continue
        t_next = float(v.t[nxt]) if nxt < v.t.size else t_last
        out.append(_cut(log, opts, len(out) + 1, max(float(v.t[a]), t_open - opts.pre),
                        t_open, t_move, t_next))
    return out


def _cut(log, opts, index, t_start, t_open, t_move, t_limit) -> Launch:
    t_lock = _lockup(log, opts, t_open, t_limit)
    t_end = min(t_limit, (t_lock if t_lock is not None else t_move + 3.0) + opts.post)
    return Launch(log.source, index, t_start, t_open, t_move, t_lock, t_end,
                  log.window(t_start, t_end))


def cut_launch(log: MappedLog, t0: float, t1: float, options: LaunchOptions | None = None,
               index: int = 1) -> Launch:
    """The launch in the window ``[t0, t1]`` given by hand; ValueError when the window holds
    no clutch event or no move from standstill."""
    opts = options or LaunchOptions()
    if not t1 > t0:
        raise ValueError(f"launch window [{t0:g}, {t1:g}] s: t0 must be before t1")
    v = _speed(log, opts)
    keep = (v.t >= t0) & (v.t <= t1)
    moving = np.flatnonzero(v.values[keep] > opts.move_speed)
    if moving.size == 0:
        raise ValueError(f"{log.source}: launch window [{t0:g}, {t1:g}] s: the vehicle does "
                         f"not move (speed never above move_speed = {opts.move_speed:g} m/s)")
    t_move = float(v.t[keep][moving[0]])
    t_open = _clutch_open_until(log, t0, t_move)
    if t_open is None:
        raise ValueError(f"{log.source}: launch window [{t0:g}, {t1:g}] s has no clutch "
                         "event (the clutch is never open before the vehicle moves); the "
                         "rule: a launch starts with the clutch open")
    launch = _cut(log, opts, index, t0, t_open, t_move, t1)
    return Launch(launch.source, index, t0, t_open, t_move, launch.t_lockup, t1,
                  log.window(t0, t1))
