"""Registry of the friction models by name."""

from __future__ import annotations

import difflib
from typing import Any

from .base import FrictionModel
from .coulomb_naive import CoulombNaive
from .coulomb_robust import CoulombRobust
from .dahl import Dahl
from .elastoplastic import ElastoPlastic
from .gms import GMS
from .karnopp import Karnopp
from .lugre import LuGre
from .mykhailevych2020 import Mykhailevych2020
from .rotational_friction import RotationalFriction
from .stribeck import StribeckFriction
from .tanh import TanhFriction

__all__ = ["MODELS", "describe_models", "get_model_class", "make_model"]

#: Registry name -> model class.
MODELS: dict[str, type[FrictionModel]] = {
    cls.name: cls
    for cls in (
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
    )
}


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
    """
    cls = get_model_class(name)
    model = cls.from_parameters(params or cls.default_parameter_set)
    return model.with_(**overrides) if overrides else model


def describe_models(domain: str = "translational") -> list[dict[str, Any]]:
    """One dict per model: name, states, parameters (name, unit, description), citation.

    The states are those of the default parameter set. Units are given in
    ``domain`` ("translational" or "rotational").
    """
    out = []
    for name, cls in MODELS.items():
        model = make_model(name)
        out.append(
            {
                "name": name,
                "states": list(model.state_names()),
                "parameters": [
                    {"name": p, "unit": cls.unit_of(p, domain), "description": info[1]}
                    for p, info in cls.parameter_info.items()
                ],
                "citation": cls.citation,
            }
        )
    return out
