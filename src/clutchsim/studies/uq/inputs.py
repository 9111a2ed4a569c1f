"""Uncertain inputs: a distribution per scenario key, and rank correlations between keys.

The DIST syntax (``--vary KEY=DIST``), parsed without ``eval`` (numbers only):

=============================  ==========================================================
``uniform(A,B)``               uniform on [A, B], A < B
``normal(MU,SIGMA)``           normal, SIGMA > 0
``tnormal(MU,SIGMA,LO,HI)``    normal truncated to [LO, HI], SIGMA > 0, LO < HI
``lognormal(MEDIAN,S)``        log-normal: ln X is normal(ln MEDIAN, S); MEDIAN > 0, S > 0
``triangular(LO,MODE,HI)``     triangular, LO <= MODE <= HI, LO < HI
``discrete(V1,V2,...)``        one of the values, equally likely
``discrete(V1:W1,V2:W2,...)``  one of the values with weights W > 0 (normalised)
``tol(±T,cpk=C)``              a toleranced dimension: normal about the scenario's value of
                               the key (the nominal) with SIGMA = T / (3 C), a centred
                               process of capability Cpk = C; ``tol(NOM±T,cpk=C)`` gives
                               the nominal; ``+-`` may replace ``±``
=============================  ==========================================================

Every distribution maps a probability ``u`` in (0, 1) to a value (:meth:`Dist.ppf`, the
inverse CDF of :mod:`scipy.stats`); the study draws the ``u`` (Monte Carlo, Latin hypercube,
Sobol', Morris) and the correlations act on them through a Gaussian copula.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import numpy as np

from ..sweeps import SweepError

__all__ = ["Dist", "UQInputError", "correlation_matrix", "parse_correlation", "parse_dist",
           "parse_inputs", "scenario_value"]


class UQInputError(SweepError):
    """Bad input of an uncertainty study: a distribution, a correlation, a method."""


#: name -> (number of parameters or None for any, what they are)
FORMS = {
    "uniform": (2, "A,B"),
    "normal": (2, "MU,SIGMA"),
    "tnormal": (4, "MU,SIGMA,LO,HI"),
    "lognormal": (2, "MEDIAN,S"),
    "triangular": (3, "LO,MODE,HI"),
    "discrete": (None, "V1,V2,... or V1:W1,V2:W2,..."),
    "tol": (None, "±T,cpk=C or NOM±T,cpk=C"),
}


@dataclass(frozen=True)
class Dist:
    """One input's distribution: ``name`` (a key of :data:`FORMS`) and its parameters.

    ``params`` for ``discrete`` are the values then the normalised weights; for ``tol`` the
    normal it stands for is kept in ``normal`` (``(mu, sigma)``) beside the text."""

    name: str
    params: tuple
    source: str = ""

    def text(self) -> str:
        return self.source or f"{self.name}({','.join(repr(p) for p in self.params)})"

    def _frozen(self):
        from scipy import stats
        p = self.params
        if self.name == "uniform":
            return stats.uniform(loc=p[0], scale=p[1] - p[0])
        if self.name in ("normal", "tol"):
            return stats.norm(loc=p[0], scale=p[1])
        if self.name == "tnormal":
            mu, s, lo, hi = p
            return stats.truncnorm((lo - mu) / s, (hi - mu) / s, loc=mu, scale=s)
        if self.name == "lognormal":
            return stats.lognorm(s=p[1], scale=p[0])
        if self.name == "triangular":
            lo, mode, hi = p
            return stats.triang((mode - lo) / (hi - lo), loc=lo, scale=hi - lo)
        raise AssertionError(self.name)

    def ppf(self, u) -> np.ndarray:
        """The value of each probability in ``u`` (the inverse CDF)."""
        u = np.asarray(u, dtype=float)
        if self.name == "discrete":
            k = len(self.params) // 2
            values, weights = np.asarray(self.params[:k]), np.asarray(self.params[k:])
            edges = np.cumsum(weights)
            edges[-1] = 1.0
            return values[np.minimum(np.searchsorted(edges, u, side="right"), k - 1)]
        return self._frozen().ppf(u)

    def mean(self) -> float:
        if self.name == "discrete":
            k = len(self.params) // 2
            return float(np.dot(self.params[:k], self.params[k:]))
        return float(self._frozen().mean())

    def std(self) -> float:
        if self.name == "discrete":
            k = len(self.params) // 2
            v, w = np.asarray(self.params[:k]), np.asarray(self.params[k:])
            return float(math.sqrt(np.dot(w, (v - np.dot(v, w)) ** 2)))
        return float(self._frozen().std())


_NUM = r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?"


def _number(text: str, where: str, what: str) -> float:
    t = text.strip()
    if not re.fullmatch(_NUM, t):
        raise UQInputError(f"{where}: {what} {t!r} is not a number")
    v = float(t)
    if not math.isfinite(v):
        raise UQInputError(f"{where}: {what} {t!r} is not finite")
    return v


def _rule(ok: bool, where: str, rule: str) -> None:
    if not ok:
        raise UQInputError(f"{where}: needs {rule}")


def parse_dist(text, key: str = "", nominal=None) -> Dist:
    """The distribution of ``KEY=DIST`` (``text`` the DIST part).  ``nominal``: a callable
    giving the scenario's value of ``key``, for ``tol(±T,...)`` without a nominal.  Raises
    :class:`UQInputError` naming the key, the text and the rule it breaks."""
    if isinstance(text, Dist):
        return text
    where = f"--vary {key}={text}" if key else repr(text)
    if not isinstance(text, str):
        raise UQInputError(f"{where}: expected a distribution such as normal(MU,SIGMA)")
    m = re.fullmatch(r"\s*([a-z]+)\s*\((.*)\)\s*", text)
    if not m:
        raise UQInputError(f"{where}: expected NAME(ARGS), one of "
                           + ", ".join(f"{n}({a})" for n, (_k, a) in FORMS.items()))
    name, inner = m.group(1), m.group(2)
    if name not in FORMS:
        from ...scenario.schema import suggest
        raise UQInputError(f"{where}: unknown distribution {name!r}{suggest(name, FORMS)} "
                           f"(known: {', '.join(FORMS)})")
    args = [a.strip() for a in inner.split(",")]
    count, form = FORMS[name]
    if count is not None and len(args) != count:
        raise UQInputError(f"{where}: {name}() takes {count} numbers ({form}), got "
                           f"{len(args)}")
    if name == "discrete":
        return _discrete(args, where, text)
    if name == "tol":
        return _tolerance(args, where, text, key, nominal)
    p = tuple(_number(a, where, "parameter") for a in args)
    if name == "uniform":
        _rule(p[0] < p[1], where, f"A < B (got A = {p[0]:g}, B = {p[1]:g})")
    elif name == "normal":
        _rule(p[1] > 0, where, f"SIGMA > 0 (got {p[1]:g})")
    elif name == "tnormal":
        _rule(p[1] > 0, where, f"SIGMA > 0 (got {p[1]:g})")
        _rule(p[2] < p[3], where, f"LO < HI (got LO = {p[2]:g}, HI = {p[3]:g})")
    elif name == "lognormal":
        _rule(p[0] > 0, where, f"MEDIAN > 0 (got {p[0]:g})")
        _rule(p[1] > 0, where, f"S > 0 (got {p[1]:g})")
    elif name == "triangular":
        _rule(p[0] < p[2], where, f"LO < HI (got LO = {p[0]:g}, HI = {p[2]:g})")
        _rule(p[0] <= p[1] <= p[2], where, f"LO <= MODE <= HI (got {p[0]:g}, {p[1]:g}, "
              f"{p[2]:g})")
    return Dist(name, p, text.strip())


def _discrete(args: list, where: str, text: str) -> Dist:
    if not args or args == [""]:
        raise UQInputError(f"{where}: discrete() needs at least one value")
    weighted = [":" in a for a in args]
    if any(weighted) and not all(weighted):
        raise UQInputError(f"{where}: give a weight to every value (V:W) or to none")
    values, weights = [], []
    for a in args:
        v, _, w = a.partition(":")
        values.append(_number(v, where, "value"))
        weights.append(_number(w, where, "weight") if w else 1.0)
    for v, w in zip(values, weights):
        _rule(w > 0, where, f"weights > 0 (value {v:g} has weight {w:g})")
    if len(set(values)) != len(values):
        raise UQInputError(f"{where}: a value is listed twice")
    order = np.argsort(values)
    total = sum(weights)
    vs = tuple(float(values[i]) for i in order)
    ws = tuple(float(weights[i] / total) for i in order)
    return Dist("discrete", vs + ws, text.strip())


def _tolerance(args: list, where: str, text: str, key: str, nominal) -> Dist:
    spec, cpk = None, None
    for a in args:
        name, eq, value = a.partition("=")
        if eq:
            if name.strip() != "cpk":
                raise UQInputError(f"{where}: unknown option {name.strip()!r} (tol() takes "
                                   "cpk=C)")
            cpk = _number(value, where, "cpk")
        elif spec is None:
            spec = a
        else:
            raise UQInputError(f"{where}: tol() takes one ±T (or NOM±T) and cpk=C")
    if spec is None or cpk is None:
        raise UQInputError(f"{where}: tol() takes ±T (or NOM±T) and cpk=C, e.g. "
                           "tol(±0.2,cpk=1.33)")
    m = re.fullmatch(rf"({_NUM})?\s*(?:±|\+-|\+/-)\s*({_NUM})", spec.strip())
    if not m:
        raise UQInputError(f"{where}: {spec!r} is not ±T or NOM±T (T a number)")
    t = _number(m.group(2), where, "tolerance T")
    _rule(t > 0, where, f"a tolerance T > 0 (got {t:g})")
    _rule(cpk > 0, where, f"cpk > 0 (got {cpk:g})")
    if m.group(1) is not None:
        nom = _number(m.group(1), where, "nominal")
    elif nominal is None:
        raise UQInputError(f"{where}: no nominal: give tol(NOM±T,cpk=C)")
    else:
        nom = float(nominal(key))
    return Dist("tol", (nom, t / (3.0 * cpk)), text.strip())


def scenario_value(data: dict, key: str) -> float:
    """The number at ``key`` (the ``--set`` key syntax) in scenario data; UQInputError when
    the key is not there or does not hold a number."""
    parts = re.findall(r"([A-Za-z0-9_\-]+)(?:\[(\d+)\])?", key)
    node = data
    for name, index in parts:
        if not isinstance(node, dict) or name not in node:
            where = ".".join(n for n, _ in parts)
            raise UQInputError(f"--vary {key}: the scenario has no value at {where!r} to be "
                               "the nominal of tol(±T,...); give it: tol(NOM±T,cpk=C)")
        node = node[name]
        if index:
            if not isinstance(node, list) or int(index) >= len(node):
                raise UQInputError(f"--vary {key}: {name}[{index}] does not exist")
            node = node[int(index)]
    if isinstance(node, bool) or not isinstance(node, (int, float)):
        raise UQInputError(f"--vary {key}: the scenario's value {node!r} is not a number "
                           "(tol(±T,...) needs a numeric nominal)")
    return float(node)


def parse_inputs(items, nominal=None) -> dict:
    """``{key: Dist}`` from ``["KEY=DIST", ...]`` or a mapping ``{key: DIST}``."""
    pairs = list(items.items()) if isinstance(items, dict) else []
    if not isinstance(items, dict):
        for item in items:
            if not isinstance(item, str) or "=" not in item:
                raise UQInputError(f"--vary {item!r}: expected KEY=DIST, e.g. "
                                   "vehicle.mass=normal(1500,50)")
            k, d = item.split("=", 1)
            pairs.append((k.strip(), d))
    out: dict = {}
    for k, d in pairs:
        if k in out:
            raise UQInputError(f"--vary {k}: given twice")
        out[k] = parse_dist(d, k, nominal)
    if not out:
        raise UQInputError("nothing to vary: give at least one --vary KEY=DIST")
    return out


def parse_correlation(items) -> dict:
    """``{(key_a, key_b): rho}`` from ``["KEY_A,KEY_B=RHO", ...]`` (``--corr``) or a
    mapping; rho is a rank (Spearman) correlation in [-1, 1]."""
    if isinstance(items, dict):
        pairs = [(tuple(k), v) for k, v in items.items()]
    else:
        pairs = []
        for item in items or ():
            k, eq, v = str(item).rpartition("=")
            names = [n.strip() for n in k.split(",")]
            if not eq or len(names) != 2 or not all(names):
                raise UQInputError(f"--corr {item!r}: expected KEY_A,KEY_B=RHO")
            pairs.append((tuple(names), _number(v, f"--corr {item}", "RHO")))
    out: dict = {}
    for (a, b), rho in pairs:
        where = f"--corr {a},{b}={rho}"
        rho = float(rho)
        if a == b:
            raise UQInputError(f"{where}: a key is not correlated with itself")
        _rule(-1.0 <= rho <= 1.0, where, f"-1 <= RHO <= 1 (got {rho:g})")
        if (a, b) in out or (b, a) in out:
            raise UQInputError(f"{where}: this pair is given twice")
        out[(a, b)] = rho
    return out


def correlation_matrix(keys, pairs: dict) -> np.ndarray | None:
    """The Pearson correlation of the Gaussian copula's normals (``2 sin(pi rho_s / 6)``
    of each rank correlation) over ``keys``; None without correlations.  Refuses a pair
    of keys that are not varied and a matrix that is not positive definite."""
    if not pairs:
        return None
    keys = list(keys)
    c = np.eye(len(keys))
    for (a, b), rho in pairs.items():
        for k in (a, b):
            if k not in keys:
                from ...scenario.schema import suggest
                raise UQInputError(f"--corr {a},{b}={rho:g}: {k!r} is not a varied key"
                                   f"{suggest(k, keys)} (varied: {', '.join(keys)})")
        i, j = keys.index(a), keys.index(b)
        c[i, j] = c[j, i] = 2.0 * math.sin(math.pi * rho / 6.0)
    smallest = float(np.linalg.eigvalsh(c)[0])
    if smallest <= 1e-10:
        given = ", ".join(f"{a},{b}={r:g}" for (a, b), r in pairs.items())
        raise UQInputError(f"--corr {given}: the correlation matrix over "
                           f"{', '.join(keys)} is not positive definite (smallest "
                           f"eigenvalue {smallest:.3g}); these correlations cannot hold "
                           "together: weaken them")
    return c
