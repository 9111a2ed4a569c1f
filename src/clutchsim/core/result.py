"""Immutable simulation results: named signals with units, status, statistics."""

from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType

import numpy as np

from .._util import atomic_write
from .status import Outcome

__all__ = ["Event", "Events", "Result", "Stats", "apply_violations", "assemble",
           "check_invariants"]


@dataclass(frozen=True)
class Stats:
    """Solver statistics of one run.

    ``event_evals`` counts calls of the plant's event functions (step ends, the samples
    inside a step where a crossing could hide, and the location iterations); ``jacobians``
    counts Jacobians formed, exactly (the plant's own) or by finite differences;
    ``lu_decompositions`` counts the iteration matrices inverted (the implicit methods
    solve their stages with an explicit inverse; the name predates it and is kept for the
    result files and tables that carry it)."""

    steps: int
    rejected: int
    rhs_evals: int
    jacobians: int
    lu_decompositions: int
    events: int
    min_step_s: float
    wall_s: float
    event_evals: int = 0

    def as_dict(self) -> dict:
        return {k: getattr(self, k) for k in self.__dataclass_fields__}


@dataclass(frozen=True)
class Event:
    """A located event: time [s], name, what its reset did, and the part of the plant it
    belongs to (:attr:`System.event_sources <clutchsim.core.System>`; ``""`` if the plant
    does not say)."""

    t: float
    name: str
    action: str
    source: str = ""


class Events(Sequence):
    """The located events of a run, in order: a read-only sequence of :class:`Event`.

    Kept as the integrator's arrays (times, event numbers, reset actions) with the
    plant's event names and sources; an :class:`Event` object is made only when one is
    read.  ``t`` is the times [s] as a read-only array; ``times(source)`` those of the
    events of one part of the plant.  Equal to a tuple or list of the same events.
    """

    __slots__ = ("_a", "_actions", "_items", "_k", "_names", "_sources", "_t")

    def __init__(self, t=(), k=(), action=(), names=(), sources=(), actions=()):
        self._t = np.array(t, dtype=float)
        self._t.flags.writeable = False
        self._k = np.asarray(k, dtype=np.int64)
        self._a = np.asarray(action, dtype=np.int64)
        if not (self._t.shape == self._k.shape == self._a.shape) or self._t.ndim != 1:
            raise ValueError("event times, numbers and actions must be 1-D arrays of one "
                             "length")
        self._names, self._sources, self._actions = tuple(names), tuple(sources), actions
        self._items = None

    @classmethod
    def of(cls, events) -> Events:
        """``events`` (a sequence of :class:`Event`) as an :class:`Events`."""
        if isinstance(events, Events):
            return events
        items = tuple(events)
        for e in items:
            if not isinstance(e, Event):
                raise TypeError(f"events must be Event objects, got {type(e).__name__}")
        kinds = {key: j for j, key in enumerate(dict.fromkeys((e.name, e.source)
                                                              for e in items))}
        actions = tuple(dict.fromkeys(e.action for e in items))
        out = cls([e.t for e in items], [kinds[e.name, e.source] for e in items],
                  [actions.index(e.action) for e in items], [n for n, _ in kinds],
                  [s for _, s in kinds], actions)
        out._items = items
        return out

    def _built(self) -> tuple:
        if self._items is None:
            names, sources, words = self._names, self._sources, self._actions
            self._items = tuple(Event(te, names[ke], words[a], sources[ke]) for te, ke, a
                                in zip(self._t.tolist(), self._k.tolist(), self._a.tolist()))
        return self._items

    @property
    def t(self) -> np.ndarray:
        """The event times [s] (read-only)."""
        return self._t

    def times(self, source: str) -> np.ndarray:
        """Times [s] of the events that belong to ``source`` (a component's name)."""
        if not self._t.size:
            return self._t
        mine = np.array([s == source for s in self._sources], dtype=bool)
        return self._t[mine[self._k]]

    def __len__(self) -> int:
        return self._t.size

    def __getitem__(self, i):
        return self._built()[i]

    def __iter__(self):
        return iter(self._built())

    def __eq__(self, other) -> bool:
        if isinstance(other, (Events, tuple, list)):
            return self._built() == tuple(other)
        return NotImplemented

    __hash__ = None

    def __repr__(self) -> str:
        return f"Events({list(self._built())!r})"


def _key(name: str, unit: str) -> str:
    return f"{name} [{unit}]"


def _frozen(values) -> np.ndarray:
    """``values`` as a read-only float64 array: itself when it already is one, else a
    read-only copy."""
    if isinstance(values, np.ndarray) and values.dtype == np.float64 \
            and not values.flags.writeable:
        return values
    arr = np.array(values, dtype=float)
    arr.flags.writeable = False
    return arr


@dataclass(frozen=True, eq=False)
class Result:
    """Outcome of a simulation.

    Signals are addressable by name (``res["v"]``) or by name with unit
    (``res["v [m/s]"]``); ``res.signals`` lists them.  Arrays are read-only.

    Attributes
    ----------
    t : ndarray
        Output times [s].
    outcome : str
        Why the run ended, machine-readable: one of :class:`~clutchsim.core.status.Outcome`
        (``"completed"``, ``"stopped"``, ``"event_failed"``, ``"budget"``,
        ``"wall_time"``, ``"step_collapse"``, ``"chatter"``, ``"nan"``,
        ``"solver_error"``, ``"invariant_violated"``: the plant's physics checks failed,
        :attr:`System.invariants`).  Code decides on this, never on the message.
    status : str
        The coarse status derived from ``outcome``: ``"completed"``, ``"stopped"`` (a
        terminal event ended the run as intended) or ``"failed"``.
    message : str
        What happened, and for a failure where and why, and what to do about it.
    event : str
        Name of the event that ended the run (``""`` when none did).
    event_source : str
        The part of the plant that event belongs to (a component's name; ``""`` when no
        event ended the run or the plant does not say).
    warnings : tuple of str
        Reasons not to trust a run that completed (each says the cause and the remedy).
    stats : Stats
        Solver statistics.
    events : Events
        Every located event in order (a sequence of :class:`Event`; any sequence of
        them given is kept as one).
    solver : str
        The solver that produced the result.
    """

    t: np.ndarray
    data: MappingProxyType
    units: MappingProxyType
    outcome: str
    message: str
    stats: Stats
    events: Events = ()
    solver: str = ""
    system: str = ""
    metadata: MappingProxyType = field(default_factory=lambda: MappingProxyType({}))
    event: str = ""
    warnings: tuple[str, ...] = ()
    event_source: str = ""

    def __post_init__(self):
        try:
            outcome = Outcome(self.outcome)
        except ValueError:
            raise ValueError(f"outcome = {self.outcome!r} is not one of "
                             f"{', '.join(o.value for o in Outcome)}") from None
        object.__setattr__(self, "outcome", outcome)
        if not isinstance(self.events, Events):
            object.__setattr__(self, "events", Events.of(self.events))
        object.__setattr__(self, "warnings", tuple(str(w) for w in self.warnings))

    @property
    def status(self) -> str:
        """``"completed"``, ``"stopped"`` or ``"failed"`` (from :attr:`outcome`)."""
        return Outcome(self.outcome).status

    def with_warnings(self, *warnings: str) -> Result:
        """The same result with ``warnings`` appended (results are immutable)."""
        from dataclasses import replace
        return replace(self, warnings=self.warnings + tuple(warnings))

    @classmethod
    def build(cls, t, columns: list[tuple[str, str, np.ndarray]], **kw) -> Result:
        """A result from its times and ``(name, unit, values)`` columns.  Read-only
        float64 arrays (views of the integrator's output blocks, which
        :func:`~clutchsim.core.result.assemble` makes read-only) are kept as they are;
        anything else is copied into a new read-only array."""
        names = [name for name, _, _ in columns]
        return cls._of(_frozen(t), names, [unit for _, unit, _ in columns],
                       [_frozen(values) for _, _, values in columns], kw)

    @classmethod
    def of_blocks(cls, t, names, units, blocks, **kw) -> Result:
        """A result whose columns are the columns of 2-D read-only float64 ``blocks``
        (one row per time), named ``names`` in order: views, made in one pass over the
        blocks' transposes (:meth:`build`'s checks per column cost ~20 µs for a launch's
        58 columns)."""
        return cls._of(t, names, units, [col for b in blocks for col in b.T], kw)

    @classmethod
    def _of(cls, t, names, units, values, kw) -> Result:
        data = dict(zip(names, values, strict=True))
        if len(data) != len(names):
            seen = set()
            dup = next(n for n in names if n in seen or seen.add(n))
            raise ValueError(f"duplicate signal name {dup!r}")
        meta = MappingProxyType(dict(kw.pop("metadata", {}) or {}))
        return cls(t, MappingProxyType(data),
                   MappingProxyType(dict(zip(names, units, strict=True))), metadata=meta, **kw)

    @property
    def success(self) -> bool:
        """True unless the run failed."""
        return self.status != "failed"

    @property
    def signals(self) -> tuple[str, ...]:
        return tuple(self.data)

    def __getitem__(self, key: str) -> np.ndarray:
        if key in ("t", "time"):
            return self.t
        if key in self.data:
            return self.data[key]
        for name, unit in self.units.items():
            if key == _key(name, unit):
                return self.data[name]
        from .system import closest
        raise KeyError(f"no signal {key!r}{closest(key, self.data)}; "
                       f"signals: {', '.join(self.data)}")

    def unit(self, name: str) -> str:
        return self.units[name]

    def final(self, name: str) -> float:
        """Last value of a signal."""
        return float(self[name][-1])

    def to_frame(self):
        """A pandas DataFrame with unit-carrying column names, ``time [s]`` first."""
        import pandas as pd
        cols = {"time [s]": self.t}
        cols.update({_key(n, self.units[n]): v for n, v in self.data.items()})
        return pd.DataFrame(cols)

    def to_csv(self, path: str | Path) -> Path:
        """Write the signals as CSV (atomically)."""
        frame = self.to_frame()
        return atomic_write(path, lambda p: frame.to_csv(p, index=False, float_format="%.17g"))

    def to_parquet(self, path: str | Path) -> Path:
        """Write the signals as Parquet (atomically), with status and units in the metadata."""
        import pyarrow as pa
        import pyarrow.parquet as pq
        table = pa.Table.from_pandas(self.to_frame(), preserve_index=False)
        meta = dict(table.schema.metadata or {})
        meta[b"clutchsim"] = json.dumps({"status": self.status, "outcome": str(self.outcome),
                                         "event": self.event,
                                         "warnings": list(self.warnings),
                                         "message": self.message,
                                         "solver": self.solver, "system": self.system,
                                         "stats": self.stats.as_dict()}).encode()
        table = table.replace_schema_metadata(meta)
        return atomic_write(path, lambda p: pq.write_table(table, p))

    def summary(self) -> dict:
        """Status, outcome, warnings, message, solver and statistics as plain data."""
        return {"system": self.system, "status": self.status, "outcome": str(self.outcome),
                "event": self.event, "warnings": list(self.warnings),
                "success": self.success, "message": self.message, "solver": self.solver, "t_end_s": float(self.t[-1]),
                "n_output": int(self.t.size), **self.stats.as_dict()}

    def __repr__(self) -> str:
        return (f"Result({self.system!r}, outcome={str(self.outcome)!r}, t=[{self.t[0]:g}, "
                f"{self.t[-1]:g}] s, {len(self.data)} signals, {self.stats.steps} steps, "
                f"{self.stats.events} events, solver={self.solver!r})")

    def _repr_html_(self) -> str:
        """A notebook's view: the status line and the summary as a small table (the
        richer page with statistics and every signal is
        :func:`clutchsim.report.result_html`)."""
        from html import escape
        rows = (("outcome", str(self.outcome)), ("message", self.message),
                ("solver", self.solver), ("t", f"{self.t[0]:g} .. {self.t[-1]:g} s"),
                ("signals", ", ".join(f"{n} [{u}]" if u else n
                                      for n, u in self.units.items())),
                ("steps / events", f"{self.stats.steps} / {self.stats.events}"),
                *(("warning", w) for w in self.warnings))
        body = "".join(f"<tr><th style='text-align:left'>{escape(k)}</th>"
                       f"<td style='text-align:left'>{escape(str(v))}</td></tr>"
                       for k, v in rows)
        return (f"<div class='clutchsim-result'><b>{escape(str(self.system))}: "
                f"{escape(str(self.status))}</b><table>{body}</table></div>")


def check_invariants(system, ts, ys, outs, outcome: Outcome, message: str,
                     warnings: tuple, tolerances) -> tuple[Outcome, str, tuple, str]:
    """Run the plant's physics checks (:attr:`System.invariants`) on a run's rows with the
    solver's ``(rtol, atol)``: ``(outcome, message, warnings, source)`` after them.  A
    fatal violation turns a run that completed (or stopped as intended) into
    :attr:`Outcome.INVARIANT_VIOLATED`, its message naming the part, the check, the time
    and the values (``source``: the part); the others become warnings."""
    if system.invariants is None or tolerances is None:
        return outcome, message, warnings, ""
    return apply_violations(system.invariants(ts, ys, outs, *tolerances), outcome, message,
                            warnings)


def apply_violations(found, outcome: Outcome, message: str, warnings: tuple
                     ) -> tuple[Outcome, str, tuple, str]:
    """:func:`check_invariants` for the violations ``found`` (a run's physics checks, or a
    batch's, which scans each run in its compiled loop)."""
    if not found:
        return outcome, message, warnings, ""
    found = sorted(found, key=lambda v: v.t)
    fatal = [v for v in found if v.fatal]
    soft = tuple(f"physics check: {v.text}" for v in found if not v.fatal)
    source = ""
    if fatal and outcome in (Outcome.COMPLETED, Outcome.STOPPED):
        v = fatal[0]
        outcome, source = Outcome.INVARIANT_VIOLATED, v.element
        message = (f"invariant violated: {v.text}; the result is not physical (a friction "
                   "element must dissipate and slide with its slip): do not use its numbers"
                   + (f"; {len(fatal) - 1} more" if len(fatal) > 1 else ""))
    elif fatal:
        soft = tuple(f"physics check: {v.text}" for v in fatal) + soft
    return outcome, message, tuple(warnings) + soft, source


def assemble(system, ts, ys, us, outs, outcome, message, stats, events, solver, *,
             event: str = "", warnings: tuple[str, ...] = (), event_source: str = "",
             tolerances: tuple[float, float] | None = None) -> Result:
    """Build a :class:`Result` from raw output arrays (shared by all backends).  The
    arrays are made read-only and the result's columns are views of them (no copies).
    With the solver's ``tolerances`` ``(rtol, atol)`` the plant's physics checks run on
    the rows (:func:`check_invariants`)."""
    outcome, message, warnings, source = check_invariants(
        system, ts, ys, outs, outcome, message, warnings, tolerances)
    if source:
        event, event_source = "", source
    blocks = []
    for a in (ts, ys, us, outs):
        if a.dtype != np.float64:
            a = a.astype(np.float64)
        a.flags.writeable = False
        blocks.append(a)
    ts, ys, us, outs = blocks
    return Result.of_blocks(ts, system.state_names + system.input_names + system.output_names,
                            system.state_units + system.input_units + system.output_units,
                            (ys, us, outs), outcome=outcome, message=message, stats=stats,
                            events=events, solver=solver, system=system.name,
                            metadata=system.metadata, event=event, warnings=warnings,
                            event_source=event_source)
