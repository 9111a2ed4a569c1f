"""Which parameters a fit adjusts, their bounds and the scaled coordinates the optimiser sees.

A fitted parameter is a field of the friction model (``"sigma0"``; an element of a tuple
field is ``"k[1]"``) or a plant parameter (``"M"``, ``"offset"``, ``"mass"``).  The optimiser
works on scaled coordinates: ``log10(value)`` for a positive parameter whose bounds span a
factor of 20 or more, otherwise ``(value − lo)/(hi − lo)`` in [0, 1].
"""

from __future__ import annotations

import dataclasses
import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from ..core.system import closest
from ..friction.base import FrictionModel

__all__ = ["ParameterSpace", "apply_to_model", "model_parameter_names", "model_value"]

_INDEXED = re.compile(r"^(\w+)\[(\d+)\]$")


def model_parameter_names(model: FrictionModel) -> tuple[str, ...]:
    """Numeric parameter names of ``model``; tuple fields expand to ``name[i]``."""
    names = []
    for f in dataclasses.fields(model):
        value = getattr(model, f.name)
        if isinstance(value, str):
            continue
        if isinstance(value, tuple):
            names += [f"{f.name}[{i}]" for i in range(len(value))]
        else:
            names.append(f.name)
    return tuple(names)


def model_value(model: FrictionModel, name: str) -> float:
    m = _INDEXED.match(name)
    if m:
        return float(getattr(model, m.group(1))[int(m.group(2))])
    return float(getattr(model, name))


def apply_to_model(model: FrictionModel, values: Mapping[str, float]) -> FrictionModel:
    """``model`` with ``values`` set, repairing order constraints the optimiser may cross.

    ``F_s`` is raised to ``F_c`` when a step puts it below, and an elasto-plastic ``z_ba``
    is held below ``F_c/sigma0``; any other violation raises the model's ValueError.
    """
    changes: dict = {}
    tuples: dict = {}
    for name, value in values.items():
        m = _INDEXED.match(name)
        if m:
            field, i = m.group(1), int(m.group(2))
            seq = tuples.setdefault(field, list(getattr(model, field)))
            seq[i] = float(value)
        else:
            changes[name] = float(value)
    changes.update({k: tuple(v) for k, v in tuples.items()})
    fields = {f.name for f in dataclasses.fields(model)}
    merged = {f: changes.get(f, getattr(model, f)) for f in fields}
    if "F_s" in fields and "F_c" in fields and merged["F_s"] < merged["F_c"]:
        changes["F_s"] = merged["F_c"]
    if "z_ba" in fields and "sigma0" in fields:
        limit = merged["F_c"] / merged["sigma0"]
        if merged["z_ba"] >= limit:
            changes["z_ba"] = 0.999 * limit
    return model.with_(**changes) if changes else model


@dataclass(frozen=True)
class ParameterSpace:
    """Names, bounds, start values and scaling of the fitted parameters."""

    names: tuple[str, ...]
    lower: np.ndarray
    upper: np.ndarray
    log: np.ndarray

    @classmethod
    def build(cls, names: Sequence[str], start: Mapping[str, float],
              bounds: Mapping[str, tuple[float, float]] | None,
              default_bounds: Mapping[str, tuple[float, float] | None]) -> ParameterSpace:
        bounds = dict(bounds or {})
        for name in bounds:
            if name not in names:
                raise ValueError(f"bounds given for {name!r}, which is not fitted"
                                 f"{closest(name, names)}; fitted: {', '.join(names)}")
        lo, hi, log = [], [], []
        for name in names:
            if name in bounds:
                try:
                    a, b = (float(x) for x in bounds[name])
                except (TypeError, ValueError):
                    raise ValueError(f"bounds for {name!r} must be a pair (lo, hi), got "
                                     f"{bounds[name]!r}") from None
                if not (math.isfinite(a) and math.isfinite(b)):
                    raise ValueError(f"bounds for {name!r}: lo = {a!r}, hi = {b!r} must be "
                                     "finite")
                if a >= b:
                    raise ValueError(f"bounds for {name!r}: lo = {a:g} must be < hi = {b:g}")
            elif default_bounds.get(name) is not None:
                a, b = default_bounds[name]
            else:
                s = start[name]
                if s > 0:
                    a, b = s / 100.0, s * 100.0
                elif s < 0:
                    a, b = s * 100.0, -s * 100.0
                else:
                    raise ValueError(f"parameter {name!r} starts at 0: give its bounds "
                                     f"(e.g. {name}=0:1)")
            lo.append(a)
            hi.append(b)
            log.append(a > 0 and b / a >= 20.0)
        return cls(tuple(names), np.array(lo), np.array(hi), np.array(log, dtype=bool))

    # scaled <-> physical
    def to_scaled(self, values: np.ndarray) -> np.ndarray:
        v = np.clip(np.asarray(values, dtype=float), self.lower, self.upper)
        return np.where(self.log, np.log10(np.maximum(v, 1e-300)),
                        (v - self.lower) / (self.upper - self.lower))

    def to_physical(self, x: np.ndarray) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        return np.where(self.log, 10.0 ** x, self.lower + x * (self.upper - self.lower))

    def derivative(self, x: np.ndarray) -> np.ndarray:
        """d(physical)/d(scaled) per parameter."""
        return np.where(self.log, np.log(10.0) * 10.0 ** np.asarray(x),
                        self.upper - self.lower)

    @property
    def scaled_bounds(self) -> tuple[np.ndarray, np.ndarray]:
        lo = np.where(self.log, np.log10(np.where(self.log, self.lower, 1.0)), 0.0)
        hi = np.where(self.log, np.log10(np.where(self.log, self.upper, 1.0)), 1.0)
        return lo, hi

    def clip_inside(self, x: np.ndarray) -> np.ndarray:
        """Scaled point moved strictly inside the bounds (least_squares needs that)."""
        lo, hi = self.scaled_bounds
        margin = 1e-6 * (hi - lo)
        return np.clip(x, lo + margin, hi - margin)

    def random(self, rng: np.random.Generator) -> np.ndarray:
        lo, hi = self.scaled_bounds
        return lo + rng.random(len(self.names)) * (hi - lo)
