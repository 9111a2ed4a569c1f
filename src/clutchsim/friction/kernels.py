"""Compiled dispatchers over all friction models (plain if/elif on ``code``).

The integer codes are the ``code`` class variables of the model classes:
1 coulomb-naive, 2 coulomb-robust, 3 karnopp, 4 tanh, 5 stribeck,
6 rotational-friction, 7 dahl, 8 lugre, 9 elastoplastic, 10 gms,
11 mykhailevych2020. See :mod:`clutchsim.friction.base` for the meaning of
the arguments.
"""

from __future__ import annotations

from .._jit import jit
from .base import RESET_NONE
from .coulomb_naive import (
    coulomb_naive_events,
    coulomb_naive_force,
    coulomb_naive_jacobian,
    coulomb_naive_reset,
)
from .coulomb_robust import (
    coulomb_robust_events,
    coulomb_robust_force,
    coulomb_robust_jacobian,
    coulomb_robust_reset,
)
from .dahl import dahl_force, dahl_jacobian
from .elastoplastic import elastoplastic_force, elastoplastic_jacobian
from .gms import gms_force, gms_jacobian
from .karnopp import karnopp_force, karnopp_jacobian
from .lugre import lugre_force, lugre_jacobian
from .mykhailevych2020 import (
    mykhailevych2020_events,
    mykhailevych2020_force,
    mykhailevych2020_jacobian,
    mykhailevych2020_reset,
)
from .rotational_friction import rotational_friction_force, rotational_friction_jacobian
from .stribeck import stribeck_force, stribeck_jacobian
from .tanh import tanh_force, tanh_jacobian

__all__ = [
    "friction_events",
    "friction_force",
    "friction_jacobian",
    "friction_reset",
    "smooth_at_events",
    "uses_stick_force",
]


@jit(inline="always")
def uses_stick_force(code):
    """Does model ``code``'s force read the stick force ``F_e``?  Only the switching
    models do (the class variable ``uses_stick_force``); for the others a plant can pass
    ``F_e = 0`` and skip computing it."""
    return code == 1 or code == 2 or code == 3


@jit(inline="always")
def smooth_at_events(code):
    """Is model ``code``'s force continuous across its event crossings when its reset
    changes nothing (the class variable ``smooth_at_events``)?  Plants then answer
    ``Action.PASS`` instead of ``Action.CONTINUE``."""
    return code == 11


@jit(inline="always")
def friction_force(code, p, z, v, F_e, scale, dz):
    """Friction force of model ``code``; writes the state derivatives into ``dz``.

    Inlined into the caller: where ``code`` is a compile-time constant (the rig) the
    dispatch folds to one kernel call, and no reference counts are taken for the arrays."""
    if code == 8:
        return lugre_force(p, z, v, F_e, scale, dz)
    elif code == 11:
        return mykhailevych2020_force(p, z, v, F_e, scale, dz)
    elif code == 9:
        return elastoplastic_force(p, z, v, F_e, scale, dz)
    elif code == 10:
        return gms_force(p, z, v, F_e, scale, dz)
    elif code == 7:
        return dahl_force(p, z, v, F_e, scale, dz)
    elif code == 1:
        return coulomb_naive_force(p, z, v, F_e, scale, dz)
    elif code == 2:
        return coulomb_robust_force(p, z, v, F_e, scale, dz)
    elif code == 3:
        return karnopp_force(p, z, v, F_e, scale, dz)
    elif code == 4:
        return tanh_force(p, z, v, F_e, scale, dz)
    elif code == 5:
        return stribeck_force(p, z, v, F_e, scale, dz)
    elif code == 6:
        return rotational_friction_force(p, z, v, F_e, scale, dz)
    return 0.0


@jit(inline="always")
def friction_jacobian(code, p, z, v, F_e, scale, dz, Jz, dF):
    """Friction force of model ``code`` and its exact partial derivatives.

    Returns the same force and writes the same ``dz`` as :func:`friction_force`, and writes
    ``Jz[i, j] = d dz_i/d z_j`` (``j < nz``), ``Jz[i, nz] = d dz_i/d v`` and ``dF`` =
    (dF/dz_0, ..., dF/dz_{nz-1}, dF/dv, dF/dF_e, dF/dscale); see
    :mod:`clutchsim.friction.base`. Inlined like :func:`friction_force`."""
    if code == 8:
        return lugre_jacobian(p, z, v, F_e, scale, dz, Jz, dF)
    elif code == 11:
        return mykhailevych2020_jacobian(p, z, v, F_e, scale, dz, Jz, dF)
    elif code == 9:
        return elastoplastic_jacobian(p, z, v, F_e, scale, dz, Jz, dF)
    elif code == 10:
        return gms_jacobian(p, z, v, F_e, scale, dz, Jz, dF)
    elif code == 7:
        return dahl_jacobian(p, z, v, F_e, scale, dz, Jz, dF)
    elif code == 1:
        return coulomb_naive_jacobian(p, z, v, F_e, scale, dz, Jz, dF)
    elif code == 2:
        return coulomb_robust_jacobian(p, z, v, F_e, scale, dz, Jz, dF)
    elif code == 3:
        return karnopp_jacobian(p, z, v, F_e, scale, dz, Jz, dF)
    elif code == 4:
        return tanh_jacobian(p, z, v, F_e, scale, dz, Jz, dF)
    elif code == 5:
        return stribeck_jacobian(p, z, v, F_e, scale, dz, Jz, dF)
    elif code == 6:
        return rotational_friction_jacobian(p, z, v, F_e, scale, dz, Jz, dF)
    return 0.0


@jit
def friction_events(code, p, z, v, F_e, scale, g):
    """Event-function values of model ``code`` into ``g`` (no-op without events)."""
    if code == 11:
        mykhailevych2020_events(p, z, v, F_e, scale, g)
    elif code == 2:
        coulomb_robust_events(p, z, v, F_e, scale, g)
    elif code == 1:
        coulomb_naive_events(p, z, v, F_e, scale, g)


@jit
def friction_reset(code, p, z, v, F_e, scale, k):
    """Apply the reset of event ``k`` of model ``code``; returns a
    :class:`~clutchsim.friction.base.FrictionReset` code."""
    if code == 11:
        return mykhailevych2020_reset(p, z, v, F_e, scale, k)
    elif code == 2:
        return coulomb_robust_reset(p, z, v, F_e, scale, k)
    elif code == 1:
        return coulomb_naive_reset(p, z, v, F_e, scale, k)
    return RESET_NONE
