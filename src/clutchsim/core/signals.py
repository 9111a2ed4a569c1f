"""Input signals: constant, step, ramp, sine, pulse, piecewise-linear table, and sums.

A signal is a small immutable object.  For the compiled integrators a set of
signals (one per system input) is flattened into a :class:`SignalBank` of plain
arrays that the kernel :func:`eval_inputs` reads.  Every signal declares its
*breakpoints* (discontinuities of the value or of its slope); the integrators
stop exactly on them instead of stepping over them.

Discontinuous signals are evaluated on a chosen side: the integrator passes the
time ``t`` and a reference time ``t_ref`` inside the current step; which branch
of a discontinuity applies is decided by ``t_ref``, the smooth formula of that
branch is evaluated at ``t``.  A step that ends exactly on a breakpoint thus
sees the left limit at its last stage, and the next step the right limit.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import NamedTuple

import numpy as np

from .._jit import jit
from .cengine import eval_series

__all__ = [
    "Constant",
    "Pulse",
    "Ramp",
    "Signal",
    "SignalBank",
    "Sine",
    "Step",
    "Sum",
    "Table",
    "as_signal",
    "build_bank",
    "eval_inputs",
]

_CONST, _STEP, _RAMP, _SINE, _PULSE, _TABLE = 0, 1, 2, 3, 4, 5
_NPAR = 6


def _finite(owner: str, **values: float) -> None:
    for name, value in values.items():
        if not isinstance(value, (int, float, np.floating, np.integer)) or not math.isfinite(value):
            raise ValueError(f"{owner}: {name} = {value!r} must be a finite number")


@dataclass(frozen=True)
class Signal:
    """Abstract input signal.  Signals add: ``Constant(0.5) + Sine(0.4, 1.0)``."""

    def terms(self) -> tuple[Signal, ...]:
        return (self,)

    def breakpoints(self) -> np.ndarray:
        """Times of value or slope discontinuities [s]."""
        raise NotImplementedError

    def __add__(self, other: Signal | float) -> Sum:
        return Sum(self.terms() + as_signal(other).terms())

    __radd__ = __add__

    def __call__(self, t) -> np.ndarray:
        """Evaluate at times ``t`` [s] (right-continuous at jumps)."""
        bank = build_bank([self])
        t = np.ascontiguousarray(np.atleast_1d(np.asarray(t, dtype=float)))
        out = np.empty_like(t)
        # one compiled call, not one per time: the C engine's evaluation where it runs (the
        # numba one took ~3 s to compile, the first check of a plant's Jacobian paid it)
        if not eval_series(bank.data, bank.n_channels, t, out):
            _eval_series(bank, t, out)
        return out

    def _encode(self) -> tuple[int, list[float], np.ndarray | None, np.ndarray | None]:
        raise NotImplementedError


@dataclass(frozen=True)
class Constant(Signal):
    """``value`` for all t."""

    value: float

    def __post_init__(self):
        _finite("Constant", value=self.value)

    def breakpoints(self):
        return np.empty(0)

    def _encode(self):
        return _CONST, [self.value], None, None


@dataclass(frozen=True)
class Step(Signal):
    """``offset`` before ``time`` [s], ``offset + height`` from ``time`` on."""

    time: float
    height: float = 1.0
    offset: float = 0.0

    def __post_init__(self):
        _finite("Step", time=self.time, height=self.height, offset=self.offset)

    def breakpoints(self):
        return np.array([self.time])

    def _encode(self):
        return _STEP, [self.time, self.height, self.offset], None, None


@dataclass(frozen=True)
class Ramp(Signal):
    """``offset`` until ``start``, rising linearly by ``height`` over ``duration`` [s], then held."""

    start: float
    duration: float
    height: float = 1.0
    offset: float = 0.0

    def __post_init__(self):
        _finite("Ramp", start=self.start, duration=self.duration, height=self.height,
                offset=self.offset)
        if self.duration < 0:
            raise ValueError(f"Ramp: duration = {self.duration} s must be >= 0")

    def breakpoints(self):
        return np.array([self.start, self.start + self.duration])

    def _encode(self):
        return _RAMP, [self.start, self.duration, self.height, self.offset], None, None


@dataclass(frozen=True)
class Sine(Signal):
    """``offset + amplitude·sin(2π·freq·(t − start) + phase)`` from ``start`` on, ``offset`` before.

    Parameters follow Modelica's ``Sine`` block: ``freq`` in Hz, ``phase`` in rad.
    """

    amplitude: float
    freq: float
    phase: float = 0.0
    offset: float = 0.0
    start: float = 0.0

    def __post_init__(self):
        _finite("Sine", amplitude=self.amplitude, freq=self.freq, phase=self.phase,
                offset=self.offset, start=self.start)
        if self.freq < 0:
            raise ValueError(f"Sine: freq = {self.freq} Hz must be >= 0")

    def breakpoints(self):
        return np.array([self.start])

    def _encode(self):
        return _SINE, [self.amplitude, self.freq, self.phase, self.offset, self.start], None, None


@dataclass(frozen=True)
class Pulse(Signal):
    """Rectangular pulse train (Modelica ``Pulse``): ``offset + amplitude`` during the first
    ``width`` percent of each ``period`` [s] from ``start`` on, ``offset`` otherwise.

    ``horizon`` [s] bounds the breakpoints that are declared (edges after it are not listed).
    """

    amplitude: float
    width: float
    period: float
    offset: float = 0.0
    start: float = 0.0
    horizon: float = 1e4

    def __post_init__(self):
        _finite("Pulse", amplitude=self.amplitude, width=self.width, period=self.period,
                offset=self.offset, start=self.start)
        if self.period <= 0:
            raise ValueError(f"Pulse: period = {self.period} s must be > 0")
        if not 0 < self.width <= 100:
            raise ValueError(f"Pulse: width = {self.width} % must be in (0, 100]")

    def breakpoints(self):
        n = int(min((self.horizon - self.start) / self.period + 1, 1e6))
        starts = self.start + self.period * np.arange(max(n, 1))
        return np.sort(np.concatenate([starts, starts + self.width / 100 * self.period]))

    def _encode(self):
        return _PULSE, [self.amplitude, self.width / 100, self.period, self.offset,
                        self.start], None, None


@dataclass(frozen=True, eq=False)
class Table(Signal):
    """Piecewise-linear table: linear between points, held constant before the first and
    after the last point.  Repeated times make a jump (left value, then right value).

    Parameters
    ----------
    times : array_like
        Non-decreasing sample times [s]; each time may appear at most twice.
    values : array_like
        Values at ``times`` (finite).
    hit_knots : bool
        Declare every interior time as a breakpoint (exact for the slope changes of the
        table); set False for long measured records where every sample would be a stop.
    """

    times: np.ndarray
    values: np.ndarray
    hit_knots: bool = True
    source: str = field(default="", compare=False)

    def __post_init__(self):
        t = np.asarray(self.times, dtype=float).ravel()
        v = np.asarray(self.values, dtype=float).ravel()
        where = f" ({self.source})" if self.source else ""
        if t.size == 0 or t.size != v.size:
            raise ValueError(f"Table{where}: times and values must be non-empty and of equal "
                             f"length (got {t.size} and {v.size})")
        bad = np.flatnonzero(~np.isfinite(t) | ~np.isfinite(v))
        if bad.size:
            i = int(bad[0])
            raise ValueError(f"Table{where}: non-finite value at row {i + 1} (time "
                             f"{float(t[i]):g} s, value {float(v[i]):g}): every row needs a "
                             "number (fill or drop the gap in the table)")
        back = np.flatnonzero(np.diff(t) < 0)
        if back.size:
            i = back[0]
            raise ValueError(f"Table{where}: time must be non-decreasing, but row {i + 2} has "
                             f"t = {float(t[i + 1]):g} s after t = {float(t[i]):g} s")
        if t.size > 2 and np.any(t[2:] == t[:-2]):
            raise ValueError(f"Table{where}: a time may appear at most twice (a jump)")
        object.__setattr__(self, "times", t)
        object.__setattr__(self, "values", v)

    @classmethod
    def from_csv(cls, path: str | Path, *, hit_knots: bool = True) -> Table:
        """Read a two-column CSV (a header row, then time [s], value).

        Errors name the file and the row.
        """
        path = Path(path)
        try:
            text = path.read_text()
        except OSError as exc:
            raise ValueError(f"{path}: cannot read input table ({exc.strerror})") from None
        rows = list(csv.reader(text.splitlines()))
        if len(rows) < 2:
            raise ValueError(f"{path}: expected a header row and at least one data row")
        times, values = [], []
        for lineno, row in enumerate(rows[1:], start=2):
            if not row or all(not c.strip() for c in row):
                raise ValueError(f"{path}:{lineno}: empty row (gaps are not allowed)")
            if len(row) != 2:
                raise ValueError(f"{path}:{lineno}: expected 2 columns (time, value), "
                                 f"found {len(row)}")
            try:
                t, v = float(row[0]), float(row[1])
            except ValueError:
                raise ValueError(f"{path}:{lineno}: not a number: {row!r}") from None
            times.append(t)
            values.append(v)
        try:
            return cls(np.array(times), np.array(values), hit_knots=hit_knots, source=str(path))
        except ValueError as exc:
            msg = str(exc)
            raise ValueError(msg.replace(f"Table ({path})", str(path))) from None

    def breakpoints(self):
        if self.hit_knots:
            return self.times.copy()
        jumps = self.times[1:][np.diff(self.times) == 0]
        return jumps

    def _encode(self):
        return _TABLE, [1.0 if self.hit_knots else 0.0], self.times, self.values


@dataclass(frozen=True)
class Sum(Signal):
    """Sum of signals (built with ``+``)."""

    parts: tuple[Signal, ...]

    def terms(self):
        return self.parts

    def breakpoints(self):
        if not self.parts:
            return np.empty(0)
        return np.unique(np.concatenate([s.breakpoints() for s in self.parts]))

    def _encode(self):  # pragma: no cover - a Sum is flattened into its terms
        raise TypeError("Sum is flattened by build_bank")


def as_signal(x) -> Signal:
    """A number becomes a :class:`Constant`; a :class:`Signal` passes through."""
    if isinstance(x, Signal):
        return x
    if isinstance(x, (int, float, np.floating, np.integer)) and not isinstance(x, bool):
        return Constant(float(x))
    raise TypeError(f"expected a Signal or a number, got {type(x).__name__}: {x!r}")


class SignalBank(NamedTuple):
    """Flat array form of a list of input channels, read by :func:`eval_inputs`.

    Everything lives in one float64 array ``data``, because every array a compiled call
    receives costs two atomic reference-count operations, and the inputs are evaluated
    six to seven times per step (seven separate arrays cost ~0.5 ms of a 2.5 ms LuGre
    run).  Layout: ``data[0]`` = number of terms; term ``i`` occupies
    ``data[1 + i*TERM_W : 1 + (i+1)*TERM_W]`` = (channel, kind, table offset, table
    length, parameters...); a table of length ``m`` at offset ``o`` holds its times in
    ``data[o:o+m]`` and its values in ``data[o+m:o+2m]``.  The terms are in channel order
    and every channel has at least one (a channel without terms gets a zero constant), so
    that the evaluation assigns each channel at its first term instead of clearing ``u``.
    """

    data: np.ndarray      # float64, layout above
    n_channels: int


_T_CH, _T_KIND, _T_TAB, _T_LEN, _T_PAR = range(5)
TERM_W = _T_PAR + _NPAR


def build_bank(channels: list[Signal]) -> SignalBank:
    """Flatten one signal per input channel into a :class:`SignalBank`."""
    terms, tables = [], []
    for c, sig in enumerate(channels):
        for term in as_signal(sig).terms() or (Constant(0.0),):
            k, pars, tt, vv = term._encode()
            terms.append((c, k, list(pars) + [0.0] * (_NPAR - len(pars)), tt, vv))
    offset = 1 + TERM_W * len(terms)
    data = [float(len(terms))]
    for c, k, pars, tt, vv in terms:
        n = 0 if tt is None else len(tt)
        data += [float(c), float(k), float(offset if n else 0), float(n)] + pars
        if n:
            tables += [np.asarray(tt, dtype=float), np.asarray(vv, dtype=float)]
            offset += 2 * n
    return SignalBank(np.concatenate([np.array(data, dtype=np.float64)] + tables),
                      len(channels))


#: tables with at most this many breakpoints are searched by counting (see interval)
SMALL_TABLE = 16


@jit(inline="always")
def interval(a, o, n, x):
    """``lo`` with ``a[o+lo] <= x < a[o+lo+1]`` for non-decreasing breakpoints ``a[o:o+n]``
    and ``a[o] <= x < a[o+n-1]`` (the last of equal breakpoints at or below ``x``).

    Up to :data:`SMALL_TABLE` breakpoints it counts the inner ones at or below ``x``:
    compares without branches, where a bisection mispredicts about one branch in two (the
    default launch's plant evaluates tables of 5 and 8 breakpoints at every right-hand
    side; ``perf`` put their bisection at ~9 % of the launch's compiled time).  Larger tables
    are bisected.  Both find the same interval, so the same bits."""
    if n <= SMALL_TABLE:
        lo = 0
        for i in range(1, n - 1):
            lo += 1 if a[o + i] <= x else 0
        return lo
    lo, hi = 0, n - 1           # invariant: a[o+lo] <= x < a[o+hi]
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if a[o + mid] <= x:
            lo = mid
        else:
            hi = mid
    return lo


@jit
def _table_value(d, o, n, hit_knots, t, t_ref):
    """Piecewise-linear value of the table at ``d[o:o+n]`` (times), ``d[o+n:o+2n]``."""
    key = t_ref if hit_knots else t
    v = o + n
    if key < d[o] or n == 1:
        return d[v]
    if key >= d[o + n - 1]:
        return d[v + n - 1]
    lo = interval(d, o, n, key)
    hi = lo + 1
    dt = d[o + hi] - d[o + lo]
    if dt <= 0.0:
        return d[v + hi]
    return d[v + lo] + (d[v + hi] - d[v + lo]) * (t - d[o + lo]) / dt


@jit
def eval_inputs(bank, t, t_ref, u):
    """Write the value of every input channel at time ``t`` into ``u``.

    ``t_ref`` selects the branch at discontinuities (see the module docstring).  Each
    channel is assigned at its first term (the bank's terms are in channel order, at least
    one per channel) and accumulated at the others: clearing ``u`` first was a ``memset``
    call per evaluation, and ``perf`` put the evaluations at 7 % of the default launch's
    samples (session 14).
    """
    d = bank.data
    ch_last = -1
    for i in range(int(d[0])):
        b = 1 + i * TERM_W
        k = int(d[b + _T_KIND])
        q = b + _T_PAR      # parameters are read by index: a view would cost a refcount
        if k == 0:
            val = d[q]
        elif k == 1:
            val = d[q + 2] + (d[q + 1] if t_ref >= d[q] else 0.0)
        elif k == 2:
            if t_ref < d[q]:
                val = d[q + 3]
            elif t_ref >= d[q] + d[q + 1]:
                val = d[q + 3] + d[q + 2]
            else:
                val = d[q + 3] + d[q + 2] * (t - d[q]) / d[q + 1]
        elif k == 3:
            if t_ref < d[q + 4]:
                val = d[q + 3]
            else:
                val = d[q + 3] + d[q] * math.sin(2.0 * math.pi * d[q + 1] * (t - d[q + 4])
                                                 + d[q + 2])
        elif k == 4:
            if t_ref < d[q + 4]:
                val = d[q + 3]
            else:
                phase = (t_ref - d[q + 4]) / d[q + 2]
                frac = phase - math.floor(phase)
                val = d[q + 3] + (d[q] if frac < d[q + 1] else 0.0)
        else:
            val = _table_value(d, int(d[b + _T_TAB]), int(d[b + _T_LEN]), d[q] != 0.0,
                               t, t_ref)
        ch = int(d[b + _T_CH])
        if ch != ch_last:
            u[ch] = val
            ch_last = ch
        else:
            u[ch] += val


@jit
def _eval_series(bank, t, out):
    """The bank's first channel at each of the times ``t`` into ``out`` (what
    :meth:`Signal.__call__` returns)."""
    u = np.zeros(max(bank.n_channels, 1))
    for i in range(t.shape[0]):
        eval_inputs(bank, t[i], t[i], u)
        out[i] = u[0]
