"""What a network component declares: parameters, states, flanges (one place each).

A component class lists its :class:`Param` and :class:`StateSpec` entries as class
variables; the scenario schema and the reference docs (``docs/network.md``) are generated
from them, and :func:`check_value` validates every value against them, so a rule is
written once.  All values are SI; ``unit`` is the unit string shown to users (``-`` for
dimensionless).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["DOMAINS", "Domain", "Param", "StateSpec", "check_table", "check_value"]


@dataclass(frozen=True)
class Domain:
    """How a mechanical domain names and measures its quantities (results, messages).

    The network's mathematics is the same in both domains: a mass is an inertia, a force
    a torque, a position an angle; only the names and units differ."""

    name: str
    speed: str          # prefix of a speed column (``omega_<node>``, ``v_<node>``)
    speed_unit: str
    position: str       # prefix of a position/angle column
    position_unit: str
    effort: str         # prefix of a torque/force column
    effort_unit: str
    inertia_unit: str
    slip: str           # prefix of a friction element's slip column


#: the mechanical domains of a network (every component of one network shares one)
DOMAINS = {
    "rotational": Domain("rotational", "omega", "rad/s", "phi", "rad", "T", "N·m", "kg·m²", "w_slip"),
    "translational": Domain("translational", "v", "m/s", "s", "m", "F", "N", "kg", "v_slip"),
}


@dataclass(frozen=True)
class Param:
    """One scalar parameter of a component.

    ``low``/``high`` bound the value (``strict``: ``low`` itself excluded); ``nonzero``
    excludes 0; ``default`` None means required.
    """

    name: str
    unit: str
    doc: str
    default: float | None = None
    low: float | None = None
    high: float | None = None
    strict: bool = False
    nonzero: bool = False

    def rule(self) -> str:
        """The value's rule in words (``> 0``, ``in [0, 1]``, ...), for docs and errors."""
        parts = []
        if self.low is not None and self.high is not None:
            parts.append(f"in {'(' if self.strict else '['}{self.low:g}, {self.high:g}]")
        elif self.low is not None:
            parts.append(f"{'>' if self.strict else '>='} {self.low:g}")
        elif self.high is not None:
            parts.append(f"<= {self.high:g}")
        if self.nonzero:
            parts.append("non-zero")
        return ", ".join(parts) or "any finite number"


@dataclass(frozen=True)
class StateSpec:
    """One continuous state a component owns (``name`` is prefixed by the component's)."""

    name: str
    unit: str
    doc: str


def check_value(owner: str, spec: Param, value) -> float:
    """``value`` as a float, or a ValueError naming ``owner``, the parameter, the value,
    its unit and the rule."""
    u = f" {spec.unit}" if spec.unit and spec.unit != "-" else ""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)):
        # contract: every bad parameter raises ValueError
        raise ValueError(f"{owner}: {spec.name} = {value!r} must be a number "  # noqa: TRY004
                         f"({spec.rule()})")
    x = float(value)
    if not math.isfinite(x):
        raise ValueError(f"{owner}: {spec.name} = {x}{u} must be finite")
    bad = ((spec.low is not None and (x <= spec.low if spec.strict else x < spec.low))
           or (spec.high is not None and x > spec.high) or (spec.nonzero and x == 0.0))
    if bad:
        raise ValueError(f"{owner}: {spec.name} = {x:g}{u} must be {spec.rule()} "
                         f"({spec.doc})")
    return x


def table_entry(description: str, x, x_unit: str, y, y_unit: str) -> dict:
    """A tabulated parameter as a run's record reads it (:meth:`Component.parameter_values`):
    its breakpoints ``x`` and values ``y`` as lists, their units as ``"x_unit → y_unit"``,
    and a one-line ``value`` for tables of results (the points ``x → y``; a long table
    shows its first and last three)."""
    x = [float(v) for v in x]
    y = [float(v) for v in y]
    pts = [f"{a:g} → {b:g}" for a, b in zip(x, y)]
    if len(pts) > 8:
        pts = pts[:3] + ["…"] + pts[-3:]
    return {"value": f"{len(x)} point{'s' if len(x) != 1 else ''}: " + ", ".join(pts),
            "unit": f"{x_unit} → {y_unit}", "description": description, "x": x, "y": y}


def check_table(owner: str, key: str, xs, ys, *, min_points: int = 2,
                low: float | None = None):
    """A piecewise-linear table ``(breakpoints, values)`` as two tuples of floats, or a
    ValueError naming ``owner`` and ``key``: equal lengths, at least ``min_points``, finite,
    breakpoints strictly increasing, values >= ``low`` (None: any)."""
    x = np.asarray(xs, dtype=float).ravel()
    v = np.asarray(ys, dtype=float).ravel()
    if x.size < min_points or x.size != v.size:
        raise ValueError(f"{owner}: {key} needs at least {min_points} point"
                         f"{'s' if min_points > 1 else ''} and equal lengths "
                         f"(got {x.size} and {v.size})")
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(v))):
        raise ValueError(f"{owner}: {key} has non-finite entries")
    if np.any(np.diff(x) <= 0):
        raise ValueError(f"{owner}: {key} breakpoints must be strictly increasing")
    if low is not None and np.any(v < low):
        i = int(np.argmin(v))
        raise ValueError(f"{owner}: {key} value {v[i]:g} (entry {i}) must be >= {low:g}")
    return (tuple(x), tuple(v))
