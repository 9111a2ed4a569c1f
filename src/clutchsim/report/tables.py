"""Turn JSON documents into plain tables, status entries and solver statistics.

Nothing here knows about HTML: :func:`analyse` walks a document and sorts what it finds
into :class:`Sections`, which :mod:`clutchsim.report.html` then draws.

Rules
-----
* a mapping whose values are all mappings (``{"models": {MODEL: {metric: value}}}``) or a
  list of mappings is a *record table*: one row per key, one column per scalar entry
  (an empty list is no entry: a column of nothing is not drawn);
  mapping-valued entries of the rows (``{MODEL: {"D1": {...}, "D2": {...}}}``) become one
  further table per sub-key;
* any other mapping gives a key/value table of its scalar entries, and its mapping or list
  entries are walked in turn;
* ``completed``/``status``/``success``/``message``/``warnings`` entries go to the status
  section, solver statistics (``steps``, ``rhs_evals``, ``events``, ``min_step_s``,
  ``wall_s``, ...) to the solver table, ``parameters`` entries to parameter tables.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from .units import split_unit

__all__ = ["MISSING", "STATS_KEYS", "Sections", "StatusEntry", "Table", "analyse", "is_scalar"]

STATUS_KEYS = ("completed", "status", "outcome", "success", "message")
STATS_KEYS = ("solver", "steps", "rejected", "rhs_evals", "jacobians", "lu_decompositions",
              "events", "min_step_s", "wall_s")
META_KEYS = ("kind", "command")
FAILED_WORDS = {"failed", "error", "aborted", "diverged", "stalled", "timeout"}
#: machine-readable outcomes (clutchsim.core.Outcome and launch metrics) that are a success
OK_OUTCOMES = {"completed", "stopped"}
OK_WORDS = {"completed", "ok", "success", "succeeded", "converged", "done"}
PARAM_SIBLINGS = ("unit", "units", "source", "sources")   # always joined, even if partial
SHORT_LIST = 8


@dataclass(frozen=True)
class Table:
    """A titled table of raw values; ``rows[i][0]`` is the row label.

    ``units_from`` says where units come from: ``"columns"`` (metric names in the header)
    or ``"rows"`` (a key/value table, metric names in the first column).
    """

    title: str
    columns: tuple[str, ...]
    rows: tuple[tuple[Any, ...], ...]
    row_label: str = ""
    units_from: str = "columns"
    failed: frozenset = frozenset()


@dataclass(frozen=True)
class StatusEntry:
    """What a document says about one run: ``ok`` is True, False (failed) or None;
    ``warnings`` is how many warnings the run carries (listed in :attr:`Sections.warnings`)."""

    where: str
    ok: bool | None
    status: str
    message: str
    warnings: int = 0


@dataclass
class Sections:
    """What :func:`analyse` found in one document."""

    tables: list[Table] = field(default_factory=list)
    parameters: list[Table] = field(default_factory=list)
    stats: list[tuple[str, dict]] = field(default_factory=list)
    status: list[StatusEntry] = field(default_factory=list)
    warnings: list[tuple[str, str]] = field(default_factory=list)
    meta: dict = field(default_factory=dict)


def is_scalar(v) -> bool:
    """Numbers, strings, booleans, None and short flat lists: fit in one table cell."""
    if v is None or isinstance(v, (str, int, float, bool)):
        return True
    if isinstance(v, list):
        return all(x is None or isinstance(x, (str, int, float, bool)) for x in v)
    return False


_SPECIAL = set(STATUS_KEYS) | set(STATS_KEYS) | set(META_KEYS) | {"warnings", "parameters"}


def _is_records(v) -> bool:
    if isinstance(v, dict):
        return bool(v) and all(isinstance(x, dict) for x in v.values()) \
            and not _SPECIAL.intersection(v)
    if isinstance(v, list):
        return bool(v) and all(isinstance(x, dict) for x in v)
    return False


def _as_mapping(records) -> dict:
    if isinstance(records, dict):
        return {str(k): v for k, v in records.items()}
    out = {}
    for i, rec in enumerate(records):
        key = next((k for k in ("name", "label", "model", "id") if is_str(rec.get(k))), None)
        name = rec[key] if key else str(i)
        rest = {k: v for k, v in rec.items() if k != key}
        out[name if name not in out else f"{name} ({i})"] = rest
    return out


def is_str(v) -> bool:
    return isinstance(v, str)


def _path(parts) -> str:
    return " › ".join(str(p) for p in parts)


def analyse(source: str, doc) -> Sections:
    """Sort a JSON document (from file ``source``) into tables, status and statistics.

    Parameters
    ----------
    source : str
        Name shown as the first element of every table title, e.g. ``"summary.json"``.
    doc : object
        The parsed JSON document.

    Returns
    -------
    Sections
    """
    out = Sections()
    if isinstance(doc, dict):
        for k in META_KEYS:
            if k in doc and doc[k] is not None:
                out.meta[k] = doc[k]
        doc = {k: v for k, v in doc.items() if k not in META_KEYS}
    _walk(doc, (source,), out)
    return out


def _extract(obj: dict, path, out: Sections) -> tuple[dict, bool | None]:
    """Move status, warnings, statistics and parameters out of ``obj``; return the rest."""
    rest = dict(obj)
    ok = None
    items = []
    if "warnings" in obj:
        w = rest.pop("warnings")
        items = w if isinstance(w, list) else ([] if w in (None, "") else [w])
        out.warnings.extend((_path(path), _text(x)) for x in items)
    if any(k in obj for k in ("completed", "status", "outcome", "success")) or \
            (is_str(obj.get("message")) and len(path) > 1):
        ok, status = _status_of(obj)
        out.status.append(StatusEntry(_path(path), ok, status, str(obj.get("message") or ""),
                                      len(items)))
        for k in STATUS_KEYS:
            rest.pop(k, None)
    elif is_str(obj.get("message")):
        out.status.append(StatusEntry(_path(path), None, "", obj["message"], len(items)))
        rest.pop("message")
    stats = {k: obj[k] for k in STATS_KEYS if k in obj and is_scalar(obj[k])}
    if sum(1 for k in stats if k != "solver") >= 2:
        out.stats.append((_path(path), stats))
        for k in stats:
            rest.pop(k)
    for k in ("stats", "solver_stats", "statistics"):
        if isinstance(rest.get(k), dict) and all(is_scalar(v) for v in rest[k].values()):
            out.stats.append((_path(path), rest.pop(k)))
    if "parameters" in rest and not is_scalar(rest["parameters"]):
        params = rest.pop("parameters")
        used = _parameters(path + ("parameters",), params, rest, out)
        for k in used:
            rest.pop(k)
    return rest, ok


def _status_of(obj: dict) -> tuple[bool | None, str]:
    ok = None
    words = []
    for k in ("completed", "success"):
        v = obj.get(k)
        if isinstance(v, bool):
            ok = v if ok is None else (ok and v)
            words.append(f"{k}" if v else f"not {k}")
        elif v is not None:
            words.append(f"{k}: {_text(v)}")
    outcome = obj.get("outcome")
    if is_str(outcome):
        # the machine-readable reason decides; the words show it beside the status
        ok = outcome in OK_OUTCOMES if ok is None else (ok and outcome in OK_OUTCOMES)
        if outcome != "completed":
            words.append(f"outcome: {outcome}")
    st = obj.get("status")
    if st is not None:
        s = _text(st)
        words = [s] + [w for w in words if w != "completed" or s.lower() != "completed"]
        low = s.strip().lower()
        if low in FAILED_WORDS or any(low.startswith(w) for w in FAILED_WORDS):
            ok = False
        elif low in OK_WORDS and ok is None:
            ok = True
    return ok, ", ".join(words)


def _text(v) -> str:
    if isinstance(v, dict):
        return "; ".join(f"{k}: {x}" for k, x in v.items())
    return str(v)


def _walk(obj, path, out: Sections) -> None:
    if _is_records(obj):
        _records(_as_mapping(obj), path, out)
        return
    if isinstance(obj, list):
        if obj:
            out.tables.append(Table(_path(path), ("value",), ((path[-1], obj),),
                                    units_from="rows"))
        return
    if not isinstance(obj, dict):
        out.tables.append(Table(_path(path), ("value",), ((path[-1], obj),), units_from="rows"))
        return
    rest, _ = _extract(obj, path, out)
    scalars = tuple((k, v) for k, v in rest.items() if is_scalar(v))
    if scalars:
        out.tables.append(Table(_path(path), ("value",), scalars, row_label="",
                                units_from="rows"))
    for k, v in rest.items():
        if not is_scalar(v):
            _walk(v, path + (k,), out)


#: what a null says in a column of a records table, by (table key, column); the JSON keeps
#: its null (summary.json: a triggered fault that never struck has ``time_s`` null)
NULL_MEANS = {("faults", "time_s"): "not struck"}


def _records(records: dict, path, out: Sections) -> None:
    rows, failed, columns, nested = [], set(), [], {}
    for i, (name, rec) in enumerate(records.items()):
        rest, ok = _extract(rec, path + (name,), out)
        if ok is False:
            failed.add(i)
        row = {}
        for k, v in rest.items():
            if isinstance(v, list) and not v:     # nothing to show (a run without events)
                continue
            if is_scalar(v):
                row[k] = NULL_MEANS.get((str(path[-1]), k), v) if v is None else v
                if k not in columns:
                    columns.append(k)
            else:
                nested.setdefault(k, {})[name] = v
        rows.append((name, row))
    if columns:
        out.tables.append(Table(
            _path(path), tuple(columns),
            tuple((name,) + tuple(row.get(c, MISSING) for c in columns) for name, row in rows),
            row_label=_row_label(path), failed=frozenset(failed)))
    for k, sub in nested.items():
        if all(isinstance(v, dict) for v in sub.values()):
            _records(sub, path + (k,), out)
        else:
            for name, v in sub.items():
                _walk(v, path + (name, k), out)


def _row_label(path) -> str:
    last = str(path[-1]).lower()
    if last in ("models", "results", "runs"):
        return "model" if last != "runs" else "run"
    if last.endswith("s") and len(last) > 3:
        return last[:-1]
    return ""


class _Missing:
    """An absent cell (a row without this column), drawn as an empty cell."""

    def __repr__(self) -> str:
        return "MISSING"


MISSING = _Missing()


def _parameters(path, params, siblings: dict, out: Sections) -> list[str]:
    """Parameter tables; returns the sibling keys joined as extra columns."""
    if _is_records(params):
        recs = _as_mapping(params)
        if all(any(is_scalar(v) for v in r.values()) for r in recs.values()) and \
                not all(_is_records(r) for r in recs.values()):
            _param_records(path, recs, out)
            return []
        for group, sub in recs.items():
            _parameters(path + (group,), sub, {}, out)
        return []
    if not isinstance(params, dict):
        _walk(params, path, out)
        return []
    values = {k: v for k, v in params.items() if is_scalar(v)}
    names = set(values)
    joined = [k for k, v in siblings.items()
              if isinstance(v, dict) and v and set(v) <= names
              and all(is_scalar(x) for x in v.values())
              and (k in PARAM_SIBLINGS or len(v) >= min(2, len(names)))]
    if values:
        cols = ["value"] + joined
        units = [k for k in joined if k in ("unit", "units")]
        if not units and any(split_unit(n)[1] for n in values):
            cols.insert(1, "unit")
        rows = []
        for n, v in values.items():
            row = [n, v]
            for c in cols[1:]:
                if c == "unit" and c not in joined:
                    row.append(split_unit(n)[1] or "")
                else:
                    row.append(siblings[c].get(n, MISSING))
            rows.append(tuple(row))
        out.parameters.append(Table(_path(path), tuple(cols), tuple(rows),
                                    row_label="parameter", units_from="none"))
    for k, v in params.items():
        if k not in values:
            _parameters(path + (k,), v, {}, out)
    return joined


def _param_records(path, recs: dict, out: Sections) -> None:
    first = ("value", "unit", "units", "source", "sources", "description")
    cols = [c for c in first if any(c in r for r in recs.values())]
    for r in recs.values():
        cols += [k for k, v in r.items() if k not in cols and k != "name" and is_scalar(v)]
    if "unit" not in cols and "units" not in cols and any(split_unit(n)[1] for n in recs):
        cols.insert(1 if cols and cols[0] == "value" else 0, "unit")
        recs = {n: {**r, "unit": split_unit(n)[1] or ""} for n, r in recs.items()}
    rows = tuple((n,) + tuple(r.get(c, MISSING) for c in cols) for n, r in recs.items())
    out.parameters.append(Table(_path(path), tuple(cols), rows, row_label="parameter",
                                units_from="none"))
