"""Friction models of clutchsim: classes, registry and compiled dispatchers.

Every model is a frozen dataclass of SI parameters (see
:mod:`clutchsim.friction.base` for the sign, unit and ``scale`` conventions)
whose compiled kernels are declared on its class (``kernels``) and reached through
:func:`friction_force`, :func:`friction_events` and :func:`friction_reset` with the model's
integer ``code`` (given by the registry) and packed parameters ``model.pack()``;
:func:`friction_jacobian` adds the exact partial derivatives of the force and of the state
derivatives.  A model declares its capabilities in one place, its class (see
:class:`FrictionModel` and the recipe ``docs/models/README.md``).
"""

from .base import (
    PHENOMENA,
    Expectation,
    FrictionKernels,
    FrictionModel,
    FrictionReset,
    Scales,
    SelfExcitedWarning,
)
from .coulomb_naive import CoulombNaive
from .coulomb_robust import CoulombRobust
from .dahl import Dahl
from .elastoplastic import ElastoPlastic
from .gms import GMS
from .karnopp import Karnopp
from .kernels import (
    friction_events,
    friction_force,
    friction_jacobian,
    friction_reset,
    smooth_at_events,
    uses_stick_force,
)
from .lugre import LuGre
from .mykhailevych2020 import RESET_POLICIES, Mykhailevych2020
from .params import ParameterSet, list_parameter_sets, load_parameter_set
from .registry import (
    MODELS,
    ParameterSource,
    describe_models,
    domain_problem,
    get_model_class,
    make_model,
    parameter_source,
)
from .rotational_friction import RotationalFriction
from .stribeck import StribeckFriction
from .tanh import TanhFriction

__all__ = [
    "GMS",
    "MODELS",
    "PHENOMENA",
    "RESET_POLICIES",
    "CoulombNaive",
    "CoulombRobust",
    "Dahl",
    "ElastoPlastic",
    "Expectation",
    "FrictionKernels",
    "FrictionModel",
    "FrictionReset",
    "Karnopp",
    "LuGre",
    "Mykhailevych2020",
    "ParameterSet",
    "ParameterSource",
    "RotationalFriction",
    "Scales",
    "SelfExcitedWarning",
    "StribeckFriction",
    "TanhFriction",
    "describe_models",
    "domain_problem",
    "friction_events",
    "friction_force",
    "friction_jacobian",
    "friction_reset",
    "get_model_class",
    "list_parameter_sets",
    "load_parameter_set",
    "make_model",
    "parameter_source",
    "smooth_at_events",
    "uses_stick_force",
]
