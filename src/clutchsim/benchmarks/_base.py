"""Shared pieces of the benchmarks: the immutable result, model selection, trace helpers."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

import numpy as np

from ..core import Outcome, Result, SolverOptions
from ..core.system import closest
from ..friction import (
    MODELS,
    FrictionModel,
    get_model_class,
    list_parameter_sets,
    load_parameter_set,
)

__all__ = [
    "STIFF_OPTIONS",
    "BenchmarkResult",
    "ModelEntry",
    "failure",
    "freeze",
    "resolve_models",
    "sample",
    "thaw",
]

#: tolerances used by the benchmarks (the LuGre-type bristle ODEs are stiff and the
#: drift numbers are micrometres: tight tolerances, see friction-models.md §5.1)
STIFF_OPTIONS = SolverOptions(rtol=1e-8, atol=1e-12, h_max=2e-3, max_steps=400_000,
                              wall_time=30.0)


def freeze(obj: Any) -> Any:
    """A read-only deep copy: mappings become ``MappingProxyType``, lists tuples."""
    if isinstance(obj, Mapping):
        return MappingProxyType({k: freeze(v) for k, v in obj.items()})
    if isinstance(obj, (list, tuple)):
        return tuple(freeze(v) for v in obj)
    if isinstance(obj, np.ndarray):
        arr = np.array(obj)
        arr.flags.writeable = False
        return arr
    if isinstance(obj, np.generic):
        return obj.item()
    return obj


def thaw(obj: Any) -> Any:
    """Plain JSON-ready data (dicts, lists, floats; NaN becomes None)."""
    if isinstance(obj, Mapping):
        return {str(k): thaw(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple, np.ndarray)):
        return [thaw(v) for v in obj]
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        return float(obj) if math.isfinite(obj) else None
    return obj


@dataclass(frozen=True, eq=False)
class BenchmarkResult:
    """Outcome of one benchmark: protocol, per-model metrics and traces.

    Attributes
    ----------
    benchmark : str
        Registry name of the benchmark (``"drift"``, ...).
    protocol : str
        What was done to the rig (signals, mass, duration), in words.
    models : mapping of str to str
        Model label -> description (model and parameter set), in run order.
    metrics : mapping of str to mapping
        Model label -> metric name -> value (numbers in SI units, flags, lists).  Every
        model's metrics carry ``outcome`` (machine-readable: the first run of the model
        that did not succeed decides, e.g. ``budget``; else ``completed``) and
        ``warnings`` (those of all its runs), added from ``runs``.
    runs : mapping of str to mapping of str to Result
        Model label -> run/regime name -> simulation result.
    extra : mapping
        Benchmark-specific data used by the figure (e.g. static curves).
    references : mapping
        Reference values the benchmark is checked against (friction-models.md).
    """

    benchmark: str
    protocol: str
    models: Mapping[str, str]
    metrics: Mapping[str, Mapping[str, Any]]
    runs: Mapping[str, Mapping[str, Result]]
    extra: Mapping[str, Any] = field(default_factory=lambda: MappingProxyType({}))
    references: Mapping[str, Any] = field(default_factory=lambda: MappingProxyType({}))

    def __post_init__(self):
        metrics = {label: _with_outcome(m, _results(self.runs.get(label, {})))
                   for label, m in self.metrics.items()}
        object.__setattr__(self, "metrics", metrics)
        for name in ("models", "metrics", "runs", "extra", "references"):
            object.__setattr__(self, name, freeze(getattr(self, name)))

    def metrics_json(self) -> dict:
        """``{"benchmark": name, "results": {model: {metric: value}}}`` as plain data."""
        return {"benchmark": self.benchmark, "results": thaw(self.metrics)}

    def __repr__(self) -> str:
        return (f"BenchmarkResult({self.benchmark!r}, models={list(self.models)}, "
                f"metrics={thaw(self.metrics)!r})")


@dataclass(frozen=True)
class ModelEntry:
    """A model chosen for a benchmark: label, instance and a description for legends."""

    label: str
    model: FrictionModel
    description: str


def _value(text: str) -> Any:
    try:
        return float(text)
    except ValueError:
        return text


def entry_from_spec(spec: str) -> ModelEntry:
    """A model from ``NAME[:PARAMETER_SET][,key=value...]``, e.g. ``"mykhailevych2020,reset=zero"``.

    Raises ValueError for an unknown model, set or parameter (listing the valid names).
    """
    if not isinstance(spec, str) or not spec.strip():
        raise ValueError(f"model spec {spec!r} must be NAME[:PARAMETER_SET][,key=value...]")
    head, *pairs = [s.strip() for s in spec.split(",")]
    name, _, set_name = head.partition(":")
    cls = get_model_class(name)
    set_name = set_name or cls.default_parameter_set
    pset = load_parameter_set(set_name)
    if cls.name not in pset.models:
        raise ValueError(f"parameter set {set_name!r} is for {', '.join(pset.models)}, "
                         f"not {cls.name!r}")
    overrides = {}
    for pair in pairs:
        key, eq, text = pair.partition("=")
        if not eq or not key:
            raise ValueError(f"model spec {spec!r}: {pair!r} is not key=value")
        if key not in cls.parameter_info:
            raise ValueError(f"model spec {spec!r}: {cls.name} has no parameter "
                             f"{key!r}{closest(key, cls.parameter_info)}; parameters: "
                             f"{', '.join(cls.parameter_info)}")
        overrides[key] = _value(text)
    params = {**pset.parameters, **overrides}
    try:
        model = cls(**params)
    except TypeError as exc:
        raise ValueError(f"model spec {spec!r}: {exc}") from None
    desc = set_name + "".join(f", {k}={v:g}" if isinstance(v, float) else f", {k}={v}"
                              for k, v in overrides.items())
    return ModelEntry(spec, model, f"{cls.name} ({desc})")


def models_where(test) -> tuple[str, ...]:
    """The registered models (names, in registry order) whose class passes ``test``: a
    benchmark's applicable models follow from what the models declare, never a list of
    names."""
    return tuple(name for name, cls in MODELS.items() if test(cls))


def force_driven(cls) -> bool:
    """Can a force-driven rig in newtons run the model: has it a translational parameter
    set?  (A model whose numbers exist only in N·m, with levels of tens of N·m, is out of
    reach of protocols whose forces are a few newtons.)"""
    return bool(list_parameter_sets(cls.name, "translational"))


def velocity_driven(cls) -> bool:
    """Can a velocity-driven rig run the model: is its force defined without the stick
    force (a switching model held at a given slip has no force to report while stuck)?"""
    return not cls.uses_stick_force


def resolve_models(models, default: Sequence[str], applicable: Sequence[str] | None = None
                   ) -> tuple[ModelEntry, ...]:
    """The models a benchmark runs.

    ``models`` is None (the benchmark's ``default`` list), a sequence of specs
    (see :func:`entry_from_spec`) or :class:`FrictionModel` instances, or a mapping
    label -> instance.  ``applicable`` (model names) rejects models the protocol cannot
    drive.
    """
    if models is None:
        models = list(default)
    if isinstance(models, (str, FrictionModel)):
        models = [models]
    items = list(models.items()) if isinstance(models, Mapping) else [(None, m) for m in models]
    out: list[ModelEntry] = []
    for label, m in items:
        if isinstance(m, FrictionModel):
            set_name = type(m).default_parameter_set
            desc = set_name if type(m).from_parameters(set_name) == m else "custom parameters"
            entry = ModelEntry(label or m.name, m, f"{m.name} ({desc})")
        elif isinstance(m, str):
            entry = entry_from_spec(m)
            if label:
                entry = ModelEntry(label, entry.model, entry.description)
        else:
            raise TypeError(f"a benchmark model must be a name or a FrictionModel, got "
                            f"{type(m).__name__}")
        if applicable is not None and entry.model.name not in applicable:
            raise ValueError(f"model {entry.model.name!r} does not apply to this benchmark; "
                             f"applicable models: {', '.join(applicable)}")
        if any(e.label == entry.label for e in out):
            raise ValueError(f"model {entry.label!r} is given twice")
        out.append(entry)
    if not out:
        raise ValueError("no models given")
    return tuple(out)


def _results(runs) -> list[Result]:
    """Every Result in a (nested) mapping of runs, in order."""
    if isinstance(runs, Result):
        return [runs]
    if isinstance(runs, Mapping):
        return [r for v in runs.values() for r in _results(v)]
    if isinstance(runs, (list, tuple)):
        return [r for v in runs for r in _results(v)]
    return []


def _with_outcome(metrics, results: list[Result]):
    """``metrics`` with ``outcome`` and ``warnings`` of the model's ``results`` added."""
    if not isinstance(metrics, Mapping) or not results:
        return metrics
    bad = [r for r in results if Outcome(r.outcome).status == "failed"]
    outcome = str((bad[0] if bad else results[0]).outcome)
    warnings = [w for r in results for w in r.warnings]
    return {**metrics, "outcome": metrics.get("outcome", outcome),
            "warnings": list(metrics.get("warnings", ())) + warnings}


def failure(*results: Result) -> dict | None:
    """Metrics of a model whose run failed (``status``, ``outcome``, ``message``), else None.

    Decided on each run's machine-readable ``outcome``.  A benchmark does not stop at a
    failed model: it records this instead of the metrics and goes on with the next model.
    """
    for res in results:
        if Outcome(res.outcome).status == "failed":
            return {"status": "failed", "outcome": str(res.outcome), "message": res.message}
    return None


def sample(res: Result, name: str, times) -> np.ndarray:
    """Signal ``name`` linearly interpolated at ``times`` [s]."""
    return np.interp(np.asarray(times, dtype=float), res.t, res[name])


def crossing_times(t: np.ndarray, y: np.ndarray, level: float, rising: bool = True
                   ) -> np.ndarray:
    """Times where ``y`` crosses ``level`` upward (or downward), linearly interpolated."""
    d = y - level
    idx = np.flatnonzero((d[:-1] < 0) & (d[1:] >= 0)) if rising else \
        np.flatnonzero((d[:-1] > 0) & (d[1:] <= 0))
    w = d[idx] / (d[idx] - d[idx + 1])
    return t[idx] + w * (t[idx + 1] - t[idx])
