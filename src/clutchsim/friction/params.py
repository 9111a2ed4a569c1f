"""Loader of the literature parameter sets shipped as TOML data files.

Each set is ``clutchsim/params/friction/<name>.toml`` with a ``[meta]`` table
(``model``: registry name or list of names, ``source``, ``notes``,
``domain``) and a ``[parameters]`` table (keyword arguments of the model).

``domain`` is ``"translational"`` (the numbers are N, m, m/s) or ``"rotational"`` (N·m,
rad, rad/s).  A model object does not know its units (the same numbers serve both), so the
domain of the set it was built from is what tells a clutch from a 1 kg test mass: the
places that put a model on an element of a known domain (scenario friction elements, the
rig) refuse a set of the other domain (:func:`clutchsim.friction.registry.domain_problem`).
"""

from __future__ import annotations

import copy
import difflib
import functools
import os
import tomllib
from dataclasses import dataclass, field
from importlib import resources
from typing import Any

from .base import DOMAINS, UNIT_KINDS, check_domain

__all__ = ["DOMAIN_UNITS", "ParameterSet", "list_parameter_sets", "load_parameter_set"]

#: the units a domain's numbers are read in, for messages
DOMAIN_UNITS = {d: ", ".join(UNIT_KINDS[k][i] for k in ("force", "displacement", "velocity"))
                for i, d in enumerate(DOMAINS)}


@dataclass(frozen=True)
class ParameterSet:
    """A named parameter set: which models it is for, its domain, values and provenance.

    ``domain`` is ``"translational"`` (N, m, m/s) or ``"rotational"`` (N·m, rad, rad/s).
    """

    name: str
    models: tuple[str, ...]
    parameters: dict[str, Any] = field(repr=False)
    meta: dict[str, Any] = field(repr=False)
    domain: str = "translational"

    def describe_domain(self) -> str:
        """``"translational (N, m, m/s)"`` or ``"rotational (N·m, rad, rad/s)"``."""
        return f"{self.domain} ({DOMAIN_UNITS[self.domain]})"


@functools.lru_cache(maxsize=1)
def _directory():
    return resources.files("clutchsim") / "params" / "friction"


def _all_names() -> tuple[str, ...]:
    d = _directory()
    try:
        stamp = os.stat(str(d)).st_mtime_ns
    except OSError:                     # not a plain directory (e.g. a zipped install)
        return _list_names(d, -1)
    return _list_names(d, stamp)


@functools.lru_cache(maxsize=8)
def _list_names(d, stamp: int) -> tuple[str, ...]:
    """Set names in directory ``d``, cached per (directory, modification time): listing it
    costs ~0.1 ms per model built, and a sweep builds models for every variant."""
    return tuple(sorted(p.name[: -len(".toml")] for p in d.iterdir()
                        if p.name.endswith(".toml")))


@functools.lru_cache(maxsize=128)
def _parse(path, stamp: int) -> dict:
    """Parsed TOML of a parameter file, cached per (path, modification time): parsing costs
    ~1 ms, as much as a whole rig simulation, and sweeps build models in loops.  Callers
    get a deep copy, so the cache cannot be altered."""
    return tomllib.loads(path.read_text(encoding="utf-8"))


def load_parameter_set(name: str) -> ParameterSet:
    """Load the parameter set ``name``.

    Raises
    ------
    ValueError
        If there is no such set; the message lists the valid names and the
        closest match.
    """
    names = _all_names()
    if name not in names:
        close = difflib.get_close_matches(name, names, n=1)
        hint = f" Did you mean {close[0]!r}?" if close else ""
        raise ValueError(
            f"unknown friction parameter set {name!r}.{hint} Valid sets: {', '.join(names)}"
        )
    path = _directory() / f"{name}.toml"
    try:
        stamp = path.stat().st_mtime_ns
    except (AttributeError, OSError):   # not a plain file (e.g. a zipped install)
        stamp = -1
    data = copy.deepcopy(_parse(path, stamp))
    meta = dict(data.get("meta", {}))
    model = meta.get("model")
    models = (model,) if isinstance(model, str) else tuple(model or ())
    if not models:
        raise ValueError(f"parameter set {name!r}: [meta] has no 'model'")
    domain = meta.get("domain")
    if domain not in DOMAINS:
        raise ValueError(f"parameter set {name!r}: [meta] domain = {domain!r} must be one of "
                         f"{', '.join(DOMAINS)} (the units its numbers are in)")
    return ParameterSet(name, models, dict(data.get("parameters", {})), meta, domain)


def list_parameter_sets(model: str | None = None, domain: str | None = None) -> list[str]:
    """Names of the available parameter sets, optionally only those for ``model`` and
    only those of ``domain`` ("translational" or "rotational")."""
    if domain is not None:
        check_domain(domain)
    out = []
    for n in _all_names():
        if model is None and domain is None:
            out.append(n)
            continue
        pset = load_parameter_set(n)
        if (model is None or model in pset.models) and (domain is None
                                                        or pset.domain == domain):
            out.append(n)
    return out
