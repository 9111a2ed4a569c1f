"""Registry of the friction models by name.

Registering a model is one entry in :data:`MODELS`' list below (and its import); the
registry checks the model's declarations and gives it its integer ``code``, its place in
the list from 1 (the compiled dispatchers of :mod:`clutchsim.friction.kernels` and the
plants' cache keys use it: append new models, never reorder).  The recipe for a new model
is ``docs/models/README.md``.
"""

from __future__ import annotations

import difflib
from dataclasses import dataclass
from dataclasses import fields as dataclass_fields
from typing import Any

from .atan import AtanFriction
from .base import (
    DOMAINS,
    EXPECTED,
    PHENOMENA,
    UNIT_KINDS,
    Expectation,
    FrictionKernels,
    FrictionModel,
    check_domain,
)
from .coulomb_naive import CoulombNaive
from .coulomb_robust import CoulombRobust
from .dahl import Dahl
from .elastoplastic import ElastoPlastic
from .gms import GMS
from .karnopp import Karnopp
from .lugre import LuGre
from .mykhailevych2020 import Mykhailevych2020
from .params import DOMAIN_UNITS, list_parameter_sets, load_parameter_set
from .rotational_friction import RotationalFriction
from .stribeck import StribeckFriction
from .tanh import TanhFriction

__all__ = ["MODELS", "ParameterSource", "describe_models", "domain_problem", "get_model_class",
           "make_model", "parameter_source", "register"]


def _check_declarations(cls: type[FrictionModel]) -> None:
    """Raise TypeError naming the model and the declaration it lacks or gets wrong."""
    who = f"friction model {cls.__name__}"
    for attr in ("name", "citation", "parameter_info", "phenomena", "default_parameter_set",
                 "kernels", "steady_checks"):
        if attr not in vars(cls):
            raise TypeError(f"{who}: declares no {attr} (see docs/models/README.md)")
    fields = [f.name for f in dataclass_fields(cls)]
    if list(cls.parameter_info) != fields or set(cls.parameter_rules) - set(fields):
        raise TypeError(f"{who}: parameter_info names {list(cls.parameter_info)} and "
                        f"parameter_rules {list(cls.parameter_rules)}; the fields are {fields}, "
                        "in that order (declare them with base.parameters)")
    if cls.__abstractmethods__:
        raise TypeError(f"{who}: implements no {', '.join(sorted(cls.__abstractmethods__))}")
    if not isinstance(cls.kernels, FrictionKernels):
        raise TypeError(f"{who}: kernels = {cls.kernels!r} must be a FrictionKernels")
    if set(cls.phenomena) != set(PHENOMENA):
        raise TypeError(f"{who}: phenomena has keys {sorted(cls.phenomena)}; it must have "
                        f"exactly {list(PHENOMENA)}")
    for key, exp in cls.phenomena.items():
        if not isinstance(exp, Expectation) or exp.expected not in EXPECTED:
            raise TypeError(f"{who}: phenomena[{key!r}] = {exp!r} must be an Expectation "
                            f"whose expected is one of {', '.join(EXPECTED)}")
    if cls.lockable and cls.kernels.reset is None:
        raise TypeError(f"{who}: lockable, but it has no events and reset kernels (its "
                        "stop and breakaway events lock and free it)")


def register(*classes: type[FrictionModel]) -> dict[str, type[FrictionModel]]:
    """``{name: class}`` of ``classes``, each checked and given its ``code`` (its place
    in ``classes``, from 1)."""
    models: dict[str, type[FrictionModel]] = {}
    for cls in classes:                 # every check before any code is given
        _check_declarations(cls)
        if cls.name in models:
            raise TypeError(f"friction model {cls.__name__}: name {cls.name!r} is taken")
        models[cls.name] = cls
    for code, cls in enumerate(classes, start=1):
        cls.code = code
    return models


#: Registry name -> model class, in code order (append new models at the end).
MODELS: dict[str, type[FrictionModel]] = register(
    CoulombNaive,
    CoulombRobust,
    Karnopp,
    TanhFriction,
    StribeckFriction,
    RotationalFriction,
    Dahl,
    LuGre,
    ElastoPlastic,
    GMS,
    Mykhailevych2020,
    AtanFriction,
)


def get_model_class(name: str) -> type[FrictionModel]:
    """Model class registered as ``name``.

    Raises
    ------
    ValueError
        For an unknown name; the message lists the valid names and the closest match.
    """
    try:
        return MODELS[name]
    except (KeyError, TypeError):
        close = difflib.get_close_matches(str(name), list(MODELS), n=1)
        hint = f" Did you mean {close[0]!r}?" if close else ""
        raise ValueError(
            f"unknown friction model {name!r}.{hint} Valid models: {', '.join(MODELS)}"
        ) from None


@dataclass(frozen=True)
class ParameterSource:
    """Where the numbers of a model built by :func:`make_model` come from.

    ``taken`` are the parameters with a unit (not ``[-]``) whose values are the set's own
    (not overridden): they are in the set's ``domain`` units.
    """

    set: str
    domain: str
    taken: tuple[str, ...]


#: instance attribute holding a model's :class:`ParameterSource` (set by make_model; not a
#: dataclass field, so equality, repr and the packed parameters ignore it; ``with_`` and a
#: constructor call give a model without one: numbers of unknown domain)
_SOURCE = "_parameter_source"


def make_model(name: str, params: str | None = None, **overrides: Any) -> FrictionModel:
    """Build model ``name`` from a parameter set (default: the model's own) plus overrides.

    Parameters
    ----------
    name : str
        Registry name, e.g. ``"lugre"``.
    params : str, optional
        Parameter-set name; default ``cls.default_parameter_set``.
    **overrides
        Parameters replacing those of the set (validated; unknown names raise TypeError).

    The model remembers the set and its domain (:func:`parameter_source`), so that an
    element of the other domain can refuse it (:func:`domain_problem`).
    """
    cls = get_model_class(name)
    set_name = params or cls.default_parameter_set
    model = cls.from_parameters(set_name)
    if overrides:
        model = model.with_(**overrides)
    pset = load_parameter_set(set_name)
    taken = tuple(k for k in pset.parameters if k not in overrides
                  and cls.parameter_info.get(k, ("1",))[0] != "1")
    object.__setattr__(model, _SOURCE, ParameterSource(set_name, pset.domain, taken))
    return model


def parameter_source(model: FrictionModel) -> ParameterSource | None:
    """The parameter set a model was built from by :func:`make_model` (None: numbers given
    directly, their domain is the caller's)."""
    return getattr(model, "__dict__", {}).get(_SOURCE)


def _sets_of(domain: str) -> str:
    """``"mykhailevych2020 (mykhailevych2020_clutch), ..."``: every model with a set of
    ``domain``."""
    items = []
    for name in MODELS:
        sets = list_parameter_sets(name, domain)
        if sets:
            items.append(f"{name} ({', '.join(sets)})")
    return "; ".join(items) or "none"


def domain_problem(model: FrictionModel, domain: str, element: str, *,
                   choose_set: str = "parameter_set = NAME",
                   give_params: str = "overrides") -> str | None:
    """Why ``model`` cannot serve on ``element`` of ``domain``, or None when it can.

    It cannot when it was built from a parameter set of the other domain and still takes
    numbers with a unit from it (a translational LuGre set on a clutch would be read as
    F_c = 1 N·m).  The message names the element, the model, the set, both domains, the
    sets of ``domain`` that exist, and the two remedies (``choose_set``: how to pick a set
    there; ``give_params``: how to give the parameters).
    """
    check_domain(domain)
    src = parameter_source(model)
    if src is None or src.domain == domain or not src.taken:
        return None
    pset = load_parameter_set(src.set)
    i = DOMAINS.index(domain)
    cls = type(model)
    example = src.taken[0]
    value = getattr(model, example)
    shown = "(" + ", ".join(f"{x:g}" for x in value) + ")" if isinstance(value, tuple) \
        else f"{value:g}"
    wrong = UNIT_KINDS[cls.parameter_info[example][0]][i]
    right = UNIT_KINDS[cls.parameter_info[example][0]][1 - i]
    own = list_parameter_sets(model.name, domain)
    if own:
        fix = (f"choose a {domain} set of {model.name} ({', '.join(own)}) with {choose_set}, "
               f"or give {', '.join(src.taken)} in {DOMAIN_UNITS[domain]} with {give_params}")
    else:
        fix = (f"{model.name} has no {domain} parameter set: give {', '.join(src.taken)} in "
               f"{DOMAIN_UNITS[domain]} with {give_params}, or use a model that has one "
               f"({_sets_of(domain)})")
    return (f"{element} works in {domain} units ({DOMAIN_UNITS[domain]}), but friction model "
            f"{model.name!r} takes {', '.join(src.taken)} from parameter set {src.set!r}, "
            f"which is {pset.describe_domain()}: {example} = {shown} {right} would be read "
            f"as {shown} {wrong}. To fix: {fix}")


def _plain(value: Any) -> Any:
    return list(value) if isinstance(value, tuple) else value


def describe_models(domain: str = "translational") -> list[dict[str, Any]]:
    """One dict per model: name, states, parameters, parameter sets, citation.

    ``parameters``: name, unit (in ``domain``, "translational" or "rotational"),
    description and ``default``, the value in the model's default parameter set
    (``default_parameter_set``, whose domain is ``default_domain``: its numbers are in
    that domain's units).  ``parameter_sets``: every set usable with the model, with its
    ``domain``, its values, its source and, where it has one, a ``caveat`` (what it does
    not show and why).  The states are those of the default parameter set.
    """
    out = []
    for name, cls in MODELS.items():
        model = make_model(name)
        default = load_parameter_set(cls.default_parameter_set)
        sets = []
        for set_name in list_parameter_sets(name):
            pset = load_parameter_set(set_name)
            entry = {"name": set_name, "domain": pset.domain,
                     "default": set_name == cls.default_parameter_set,
                     "parameters": {k: _plain(v) for k, v in pset.parameters.items()},
                     "source": pset.meta.get("source", "")}
            if pset.meta.get("caveat"):
                entry["caveat"] = " ".join(str(pset.meta["caveat"]).split())
            sets.append(entry)
        out.append(
            {
                "name": name,
                "states": list(model.state_names()),
                "default_parameter_set": cls.default_parameter_set,
                "default_domain": default.domain,
                "parameters": [
                    {"name": p, "unit": cls.unit_of(p, domain), "description": info[1],
                     "default": _plain(getattr(model, p))}
                    for p, info in cls.parameter_info.items()
                ],
                "parameter_sets": sets,
                "citation": cls.citation,
            }
        )
    return out
