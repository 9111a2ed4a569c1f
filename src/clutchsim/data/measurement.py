"""A measured record (time plus named columns) and its readers for CSV, NPZ and MAT files.

Every reader returns the same :class:`Measurement`: a strictly increasing time vector and
float columns in SI units after the caller's column mapping and unit factors.  Problems in
the file are reported as ``ValueError`` naming the file, the column and the row:

* a mapped column that is not in the file (the message lists the columns found);
* a time column that does not increase (the first offending row);
* NaN values (every gap, with its rows and times).  They are dropped or interpolated only
  when asked with ``nan="drop"`` or ``nan="interpolate"``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType

import numpy as np

from ..core.system import closest

__all__ = ["NAN_POLICIES", "Measurement", "read_measurements"]

#: what to do with NaN samples
NAN_POLICIES = ("error", "drop", "interpolate")


@dataclass(frozen=True, eq=False)
class Measurement:
    """A measured record: time [s] and named float columns of the same length.

    Attributes
    ----------
    t : ndarray
        Strictly increasing sample times [s].
    columns : mapping of str to ndarray
        Read-only columns, in the units stated in ``units``.
    units : mapping of str to str
        Unit label per column ("" when not given).
    source : str
        File (or description) the data came from, used in messages.
    scalars : mapping of str to float
        Scalar entries of NPZ/MAT files (e.g. controller gains), unconverted.
    """

    t: np.ndarray
    columns: Mapping[str, np.ndarray]
    units: Mapping[str, str] = field(default_factory=dict)
    source: str = "data"
    scalars: Mapping[str, float] = field(default_factory=dict)

    def __post_init__(self):
        t = np.array(self.t, dtype=np.float64).ravel()
        cols = {}
        for name, values in self.columns.items():
            arr = np.array(values, dtype=np.float64).ravel()
            if arr.size != t.size:
                raise ValueError(f"{self.source}: column {name!r} has {arr.size} samples, "
                                 f"time has {t.size}")
            arr.flags.writeable = False
            cols[str(name)] = arr
        _check_time(t, self.source, "t")
        t.flags.writeable = False
        object.__setattr__(self, "t", t)
        object.__setattr__(self, "columns", MappingProxyType(cols))
        object.__setattr__(self, "units", MappingProxyType(
            {n: str(self.units.get(n, "")) for n in cols}))
        object.__setattr__(self, "scalars", MappingProxyType(dict(self.scalars)))

    def __getitem__(self, name: str) -> np.ndarray:
        if name == "t":
            return self.t
        try:
            return self.columns[name]
        except KeyError:
            raise ValueError(f"{self.source}: no column {name!r}{closest(name, self.columns)}; "
                             f"columns: {', '.join(self.columns) or '(none)'}") from None

    def __len__(self) -> int:
        return int(self.t.size)

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(self.columns)

    def window(self, t_start: float | None = None, t_end: float | None = None) -> Measurement:
        """The samples with ``t_start <= t <= t_end`` (either end may be None)."""
        lo = -math.inf if t_start is None else float(t_start)
        hi = math.inf if t_end is None else float(t_end)
        keep = (self.t >= lo) & (self.t <= hi)
        if np.count_nonzero(keep) < 2:
            raise ValueError(f"{self.source}: window [{lo:g}, {hi:g}] s holds fewer than 2 "
                             f"samples (data span {self.t[0]:g} ... {self.t[-1]:g} s)")
        return Measurement(self.t[keep], {n: c[keep] for n, c in self.columns.items()},
                           self.units, self.source, self.scalars)

    def with_column(self, name: str, values, unit: str = "") -> Measurement:
        """A copy with one column added or replaced."""
        cols = dict(self.columns)
        cols[name] = values
        units = dict(self.units)
        units[name] = unit
        return Measurement(self.t, cols, units, self.source, self.scalars)

    @classmethod
    def from_arrays(cls, t, source: str = "data", units=None, **columns) -> Measurement:
        """Build a record from arrays; NaNs are rejected like in the file readers."""
        t = np.asarray(t, dtype=float).ravel()
        cols = {n: np.asarray(v, dtype=float).ravel() for n, v in columns.items()}
        _check_nan(source, "t", t, t)
        for n, v in cols.items():
            if v.size == t.size:
                _check_nan(source, n, v, t)
        return cls(t, cols, units or {}, source)


# ---------------------------------------------------------------- validation helpers
def _check_time(t: np.ndarray, source: str, name: str) -> None:
    if t.size < 2:
        raise ValueError(f"{source}: time column {name!r} has {t.size} sample(s); need >= 2")
    bad = np.flatnonzero(~np.isfinite(t))
    if bad.size:
        raise ValueError(f"{source}: time column {name!r} is not finite at row {bad[0]}")
    back = np.flatnonzero(np.diff(t) <= 0)
    if back.size:
        i = back[0]
        raise ValueError(f"{source}: time column {name!r} must increase strictly, but row "
                         f"{i + 1} has t = {float(t[i + 1])!r} after t = {float(t[i])!r} at row {i} "
                         "(rows counted from 0 after the header)")


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """Inclusive (start, end) index pairs of the True runs of ``mask``."""
    idx = np.flatnonzero(mask)
    if idx.size == 0:
        return []
    breaks = np.flatnonzero(np.diff(idx) > 1)
    starts = np.concatenate([[idx[0]], idx[breaks + 1]])
    ends = np.concatenate([idx[breaks], [idx[-1]]])
    return list(zip(starts.tolist(), ends.tolist()))


def _describe_gaps(name: str, values: np.ndarray, t: np.ndarray, limit: int = 3) -> str:
    runs = _runs(~np.isfinite(values))
    parts = []
    for a, b in runs[:limit]:
        ta = t[a] if np.isfinite(t[a]) else float("nan")
        parts.append(f"rows {a}-{b} (t = {ta:g} s)" if b > a else f"row {a} (t = {ta:g} s)")
    more = f" and {len(runs) - limit} more gap(s)" if len(runs) > limit else ""
    n = int(np.count_nonzero(~np.isfinite(values)))
    return f"column {name!r} has {n} NaN/inf value(s) at {', '.join(parts)}{more}"


def _check_nan(source, name, values, t) -> None:
    if not np.all(np.isfinite(values)):
        raise ValueError(f"{source}: {_describe_gaps(name, values, t)}; drop those rows "
                         "(command line: --nan drop; Python: nan='drop') or fill them "
                         "linearly (--nan interpolate; nan='interpolate')")


# ---------------------------------------------------------------- file readers
def _read_csv(path: Path) -> tuple[dict[str, np.ndarray], dict[str, float]]:
    import pandas as pd
    try:
        frame = pd.read_csv(path, sep=None, engine="python")
    except UnicodeDecodeError as exc:
        raise ValueError(f"{path}: not a text file (byte 0x{exc.object[exc.start]:02x} at "
                         f"offset {exc.start} is not UTF-8): a CSV table is text, one row per "
                         "line, columns separated by commas") from None
    except OSError as exc:
        raise ValueError(f"{path}: cannot read CSV ({exc})") from None
    except pd.errors.ParserError as exc:
        raise ValueError(f"{path}: malformed CSV ({str(exc).strip()})") from None
    except pd.errors.EmptyDataError:
        raise ValueError(f"{path}: the file is empty") from None
    cols = {}
    for name in frame.columns:
        values = pd.to_numeric(frame[name], errors="coerce").to_numpy(dtype=float)
        text = frame[name].astype(str).str.strip()
        junk = np.flatnonzero(np.isnan(values) & frame[name].notna().to_numpy() & ~text.str.lower()
                              .isin(["nan", "", "na", "none", "null"]).to_numpy())
        if junk.size:
            i = junk[0]
            raise ValueError(f"{path}: column {str(name).strip()!r} row {i} "
                             f"(file line {i + 2}) is not a number: {frame[name].iloc[i]!r}")
        cols[str(name).strip()] = values
    return cols, {}


def _split_arrays(items, path) -> tuple[dict[str, np.ndarray], dict[str, float]]:
    cols, scalars = {}, {}
    for key, value in items:
        if key.startswith("__"):
            continue
        arr = np.asarray(value)
        if arr.dtype.kind not in "fiub":
            continue
        if arr.size == 1:
            scalars[key] = float(arr.ravel()[0])
        elif arr.ndim == 1 or (arr.ndim == 2 and 1 in arr.shape):
            cols[key] = arr.astype(float).ravel()
    return cols, scalars


def _read_npz(path: Path):
    try:
        with np.load(path, allow_pickle=False) as z:
            return _split_arrays(((k, z[k]) for k in z.files), path)
    except (OSError, ValueError) as exc:
        raise ValueError(f"{path}: cannot read NPZ ({exc})") from None


def _read_mat(path: Path):
    from scipy.io import loadmat
    try:
        d = loadmat(path)
    except (OSError, ValueError, NotImplementedError) as exc:
        raise ValueError(f"{path}: cannot read MAT file ({exc})") from None
    return _split_arrays(d.items(), path)


_READERS = {".csv": _read_csv, ".txt": _read_csv, ".tsv": _read_csv, ".dat": _read_csv,
            ".npz": _read_npz, ".mat": _read_mat}


def read_measurements(path: str | Path, *, time: str = "t",
                      columns: Mapping[str, str] | Sequence[str] | None = None,
                      scale: Mapping[str, float] | None = None,
                      units: Mapping[str, str] | None = None,
                      tare: Sequence[str] = (), nan: str = "error",
                      optional: Sequence[str] = ()) -> Measurement:
    """Read a measured record from a CSV/TXT, NPZ or MAT file.

    Parameters
    ----------
    path : str or Path
        The file; the format follows the suffix (.csv/.txt/.tsv/.dat: delimited text with
        one header row, the delimiter is detected; .npz; .mat, MATLAB v5).
    time : str
        Name of the time column in the file [s after scaling].
    columns : mapping or sequence of str, optional
        ``{name: column in file}`` (renames) or a list of file columns to keep.  Default:
        every numeric column.  The time column is always read and named ``t``.
    scale : mapping of str to float, optional
        Unit factors per (new) column name, e.g. ``{"x": 1e-3}`` for mm to m; ``"t"`` may be
        scaled too.  A negative factor flips a sign convention.
    units : mapping of str to str, optional
        Unit labels after scaling (used in plots and reports).
    tare : sequence of str
        Columns from which the first value is subtracted (e.g. an absolute position).
    nan : {"error", "drop", "interpolate"}
        NaN/inf samples: report them (default), drop their rows, or interpolate linearly in
        time (the gap must have finite neighbours).
    optional : sequence of str
        New column names that may be missing from the file (they are then left out, not an
        error), e.g. a declared disturbance input that only some records have.  A name
        not in ``columns`` is read under its own name when the file has it.

    Returns
    -------
    Measurement
    """
    path = Path(path)
    if nan not in NAN_POLICIES:
        raise ValueError(f"nan = {nan!r} must be one of {', '.join(NAN_POLICIES)}")
    if not path.is_file():
        raise ValueError(f"{path}: no such data file")
    reader = _READERS.get(path.suffix.lower())
    if reader is None:
        raise ValueError(f"{path}: unknown data format {path.suffix!r}; use one of "
                         f"{', '.join(sorted(_READERS))}")
    raw, scalars = reader(path)
    if columns is None:
        mapping = {n: n for n in raw if n != time}
    elif isinstance(columns, Mapping):
        mapping = {str(k): str(v) for k, v in columns.items()}
    else:
        mapping = {str(c): str(c) for c in columns}
    for name in optional:
        if name not in mapping and name != time:
            mapping[name] = name
        if mapping.get(name) not in raw:
            mapping.pop(name, None)
    wanted = [time] + [c for c in mapping.values()]
    missing = [c for c in wanted if c not in raw]
    if missing:
        hint = "".join(closest(m, raw) for m in missing[:1])
        raise ValueError(f"{path}: missing column(s) {', '.join(map(repr, missing))}{hint}; "
                         f"columns found: {', '.join(map(repr, raw)) or '(none)'}")
    t = raw[time].astype(float).copy()
    cols = {new: raw[old].astype(float).copy() for new, old in mapping.items()}
    scale = dict(scale or {})
    for name in scale:
        if name != "t" and name not in cols and name not in optional:
            raise ValueError(f"{path}: scale given for unknown column {name!r}; columns: "
                             f"{', '.join(cols)}")
    for name, factor in scale.items():
        if not (math.isfinite(float(factor)) and float(factor) != 0.0):
            raise ValueError(f"{path}: scale {name} = {factor!r} must be a finite, non-zero "
                             "factor (it multiplies the column into SI units; a negative one "
                             "flips a sign convention)")
    if not np.all(np.isfinite(t)):
        raise ValueError(f"{path}: time {_describe_gaps(time, t, t)} (time gaps cannot be "
                         "dropped or interpolated)")
    t *= float(scale.get("t", 1.0))
    for name in cols:
        cols[name] *= float(scale.get(name, 1.0))
    bad = np.zeros(t.size, dtype=bool)
    for name, values in cols.items():
        gaps = ~np.isfinite(values)
        if gaps.any():
            if nan == "error":
                _check_nan(str(path), mapping[name], values, t)
            bad |= gaps
    if bad.any() and nan == "drop":
        t = t[~bad]
        cols = {n: v[~bad] for n, v in cols.items()}
    elif bad.any():
        for name, values in cols.items():
            gaps = ~np.isfinite(values)
            if gaps.any():
                if gaps[0] or gaps[-1]:
                    raise ValueError(f"{path}: {_describe_gaps(name, values, t)}: a gap at the "
                                     "start or end cannot be interpolated; drop those rows "
                                     "(command line: --nan drop; Python: nan='drop')")
                values[gaps] = np.interp(t[gaps], t[~gaps], values[~gaps])
    for name in tare:
        if name not in cols:
            raise ValueError(f"{path}: tare given for unknown column {name!r}")
        cols[name] = cols[name] - cols[name][0]
    return Measurement(t, cols, dict(units or {}), str(path), scalars)
