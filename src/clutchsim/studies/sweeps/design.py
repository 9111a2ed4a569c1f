"""What a sweep varies: grids and seeded random samples over scenario keys.

A *design* is the table of variants, one row per run, computed once by the caller (never on
a worker), so every backend runs exactly the same rows in the same order.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, fields
from typing import ClassVar

import numpy as np

__all__ = [
    "Design",
    "Grid",
    "LogUniform",
    "Normal",
    "SweepError",
    "Uniform",
    "Values",
    "design_size",
    "key_unit",
    "make_design",
    "parse_spec",
    "parse_vary",
]


class SweepError(ValueError):
    """Bad sweep input: a range, a key, an output directory, a Dask address."""


@dataclass(frozen=True)
class Grid:
    """``n`` evenly spaced values from ``lo`` to ``hi`` (both included)."""

    lo: float
    hi: float
    n: int

    def __post_init__(self):
        if not isinstance(self.n, (int, np.integer)) or self.n < 1:
            raise SweepError(f"grid {self.lo}:{self.hi}:{self.n}: N must be an integer >= 1")
        if not (math.isfinite(self.lo) and math.isfinite(self.hi)):
            raise SweepError(f"grid {self.lo}:{self.hi}:{self.n}: LO and HI must be finite")
        if self.lo > self.hi:
            raise SweepError(f"grid {self.lo:g}:{self.hi:g}:{self.n}: LO > HI (write "
                             f"{self.hi:g}:{self.lo:g}:{self.n})")
        if self.n == 1 and self.lo != self.hi:
            raise SweepError(f"grid {self.lo:g}:{self.hi:g}:1: one point needs LO == HI "
                             f"(or N >= 2)")

    def values(self) -> np.ndarray:
        return np.linspace(self.lo, self.hi, self.n)

    def text(self) -> str:
        return f"{self.lo!r}:{self.hi!r}:{self.n}"


@dataclass(frozen=True)
class Values:
    """An explicit list of values (a grid axis)."""

    items: tuple

    def __post_init__(self):
        if not self.items:
            raise SweepError("an empty list of values")

    def values(self) -> np.ndarray:
        return np.asarray(self.items, dtype=float)

    def text(self) -> str:
        return ",".join(repr(float(v)) for v in self.items)


class _Random:
    """A distribution of random samples given by two numbers: ``name(p, q)``, the fields
    in their order."""

    name: ClassVar[str]

    def _two(self) -> tuple[float, float]:
        p, q = fields(self)
        return getattr(self, p.name), getattr(self, q.name)

    def _require(self, ok: bool, rule: str) -> None:
        if not ok:
            p, q = self._two()
            raise SweepError(f"{self.name}({p:g}, {q:g}): needs {rule}")

    def text(self) -> str:
        p, q = self._two()
        return f"{self.name}({p!r},{q!r})"


@dataclass(frozen=True)
class Uniform(_Random):
    """Random samples, uniform on [a, b]."""

    a: float
    b: float
    name: ClassVar[str] = "uniform"

    def __post_init__(self):
        self._require(self.a <= self.b, "a <= b")

    def draw(self, rng, n):
        return rng.uniform(self.a, self.b, n)


@dataclass(frozen=True)
class LogUniform(_Random):
    """Random samples whose logarithm is uniform on [log a, log b] (a, b > 0)."""

    a: float
    b: float
    name: ClassVar[str] = "loguniform"

    def __post_init__(self):
        self._require(0 < self.a <= self.b, "0 < a <= b")

    def draw(self, rng, n):
        return np.exp(rng.uniform(math.log(self.a), math.log(self.b), n))


@dataclass(frozen=True)
class Normal(_Random):
    """Random samples, normal with mean ``mu`` and standard deviation ``sigma``."""

    mu: float
    sigma: float
    name: ClassVar[str] = "normal"

    def __post_init__(self):
        self._require(self.sigma >= 0, "sigma >= 0")

    def draw(self, rng, n):
        return rng.normal(self.mu, self.sigma, n)


_RANDOM = {d.name: d for d in (Uniform, LogUniform, Normal)}
_SPEC_HELP = ("LO:HI:N (grid), V1,V2,... (values), uniform(A,B), loguniform(A,B) or "
              "normal(MU,SIGMA) (random, with samples)")


def _num(text: str, what: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise SweepError(f"{what}: {text.strip()!r} is not a number") from None


def parse_spec(spec, key: str = "") -> object:
    """A spec object from a string (``"0:10:5"``, ``"uniform(1, 2)"``, ``"1,2,4"``), a
    ``(lo, hi, n)`` tuple, a list of values or a spec object."""
    where = f"--vary {key}={spec}" if key else f"{spec!r}"
    if isinstance(spec, (Grid, Values, Uniform, LogUniform, Normal)):
        return spec
    if isinstance(spec, tuple) and len(spec) == 3:
        return Grid(float(spec[0]), float(spec[1]), spec[2])
    if isinstance(spec, (list, np.ndarray)):
        return Values(tuple(float(v) for v in spec))
    if isinstance(spec, (int, float)) and not isinstance(spec, bool):
        return Values((float(spec),))
    if not isinstance(spec, str):
        raise SweepError(f"{where}: expected {_SPEC_HELP}")
    s = spec.strip()
    m = re.fullmatch(r"([a-z]+)\s*\((.*)\)", s)
    if m:
        name, args = m.group(1), [a for a in m.group(2).split(",")]
        if name not in _RANDOM:
            from ...scenario.schema import suggest
            raise SweepError(f"{where}: unknown distribution {name!r}{suggest(name, _RANDOM)} "
                             f"(known: {', '.join(_RANDOM)})")
        if len(args) != 2:
            raise SweepError(f"{where}: {name}() takes two numbers")
        try:
            return _RANDOM[name](*(_num(a, where) for a in args))
        except SweepError as exc:
            raise SweepError(f"{where}: {exc}") from None
    if ":" in s:
        parts = s.split(":")
        if len(parts) != 3:
            raise SweepError(f"{where}: expected LO:HI:N")
        n_txt = parts[2].strip()
        if not re.fullmatch(r"[+-]?\d+", n_txt):
            raise SweepError(f"{where}: N must be an integer >= 1, got {n_txt!r}")
        try:
            return Grid(_num(parts[0], where), _num(parts[1], where), int(n_txt))
        except SweepError as exc:
            raise SweepError(f"{where}: {exc}") from None
    return Values(tuple(_num(v, where) for v in s.split(",")))


def parse_vary(items) -> dict:
    """``{key: spec}`` from ``["KEY=SPEC", ...]`` (the CLI's ``--vary``) or a mapping."""
    if isinstance(items, dict):
        out = {str(k): parse_spec(v, k) for k, v in items.items()}
    else:
        out = {}
        for item in items:
            if "=" not in item:
                raise SweepError(f"--vary {item!r}: expected KEY={_SPEC_HELP.split(' (')[0]}")
            key, spec = item.split("=", 1)
            key = key.strip()
            if key in out:
                raise SweepError(f"--vary {key}: given twice")
            out[key] = parse_spec(spec, key)
    if not out:
        raise SweepError("nothing to vary: give at least one KEY=SPEC")
    return out


def key_unit(data: dict, key: str) -> str:
    """The unit of a scenario key from the schema ("" if the schema does not say)."""
    from ...scenario.schema import SECTIONS, key_spec
    parts = re.findall(r"([A-Za-z0-9_\-]+)(?:\[(\d+)\])?", key)
    if not parts or parts[0][0] not in SECTIONS:
        return ""
    section, index = parts[0]
    table = data.get(section)
    rest = [p[0] for p in parts[1:]]
    if len(rest) == 1:
        spec = key_spec(data, key)
        return spec.unit if spec is not None else ""
    if len(rest) == 3 and rest[0] == "friction" and rest[1] == "overrides" and \
            isinstance(table, list) and index and int(index) < len(table):
        try:
            from ...friction import get_model_class
            model = table[int(index)].get("friction", {}).get("model")
            return get_model_class(model).unit_of(rest[2], "rotational")
        except (ValueError, KeyError, TypeError):   # reported by the validation
            return ""
    return ""


@dataclass(frozen=True)
class Design:
    """The variants: ``columns[key]`` holds one value per run (run ``i`` is row ``i``)."""

    keys: tuple
    columns: dict
    grid_keys: tuple
    random_keys: tuple
    n: int

    def row(self, i: int) -> tuple:
        return tuple(float(self.columns[k][i]) for k in self.keys)

    def digest(self) -> str:
        """A hash of the keys and every value (the identity of a design given as a table)."""
        import hashlib
        h = hashlib.sha256(repr(self.keys).encode())
        for k in self.keys:
            h.update(np.ascontiguousarray(self.columns[k], dtype=np.float64).tobytes())
        return h.hexdigest()


def design_size(vary: dict, samples: int | None = None) -> int:
    """The number of runs of a design, computed without building it."""
    sizes = [s.n if isinstance(s, Grid) else len(s.items) for s in vary.values()
             if isinstance(s, (Grid, Values))]
    random = any(not isinstance(s, (Grid, Values)) for s in vary.values())
    return math.prod(sizes) * (int(samples) if random and samples else 1)


def make_design(vary: dict, samples: int | None = None, seed: int | None = None, *,
                max_runs: int | None = None) -> Design:
    """Grid axes form the full product (first key slowest); random keys are drawn
    ``samples`` times from ``numpy.random.default_rng(seed)`` in the order given; with both,
    every grid point is combined with every sample.

    ``max_runs``: refuse (:class:`~clutchsim._util.ResourceError`) a design of more runs,
    before anything is allocated."""
    grid = {k: s for k, s in vary.items() if isinstance(s, (Grid, Values))}
    rand = {k: s for k, s in vary.items() if not isinstance(s, (Grid, Values))}
    if rand and samples is None:
        raise SweepError(f"random keys ({', '.join(rand)}) need a number of samples "
                         "(--samples N)")
    if samples is not None and (not isinstance(samples, (int, np.integer)) or samples < 1):
        raise SweepError(f"samples must be an integer >= 1, got {samples!r}")
    if samples is not None and not rand:
        raise SweepError("samples given but no key has a distribution (use e.g. "
                         "KEY=uniform(A,B))")
    if rand and seed is None:
        raise SweepError("random samples need a seed (--seed S) so the sweep can be repeated "
                         "and resumed")
    if max_runs is not None:
        from ..._util import check_run_count
        check_run_count(design_size(vary, samples), max_runs)
    axes = [grid[k].values() for k in grid]
    n_grid = math.prod(len(a) for a in axes) if axes else 1
    n_rand = samples if rand else 1
    cols = {}
    if axes:
        mesh = np.meshgrid(*axes, indexing="ij")
        for k, m in zip(grid, mesh):
            cols[k] = np.repeat(m.ravel(), n_rand)
    if rand:
        rng = np.random.default_rng(seed)
        for k, s in rand.items():
            cols[k] = np.tile(s.draw(rng, samples), n_grid)
    keys = tuple(vary)
    return Design(keys, {k: np.asarray(cols[k], dtype=float) for k in keys},
                  tuple(grid), tuple(rand), n_grid * n_rand)
