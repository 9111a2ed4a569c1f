"""Compiled dispatchers over all friction models, generated from the registry.

:func:`friction_force`, :func:`friction_jacobian`, :func:`friction_events` and
:func:`friction_reset` call the kernel of the model whose integer ``code`` they are given
(:data:`~clutchsim.friction.registry.MODELS` gives the codes: a model's place there, from
1); :func:`uses_stick_force` and :func:`smooth_at_events` are the compiled twins of the
class variables of the same names.  Nothing here names a model: each dispatcher is a chain
of small compiled links, one per model that provides the kernel (its ``kernels``
declaration, :class:`~clutchsim.friction.base.FrictionKernels`), built when this module is
imported.  Every link is inlined into its caller, so where ``code`` is a compile-time
constant (the rig) the chain folds to the one kernel call.  See
:mod:`clutchsim.friction.base` for the meaning of the arguments.
"""

from __future__ import annotations

import numpy as np

from .._jit import jit
from .base import RESET_NONE
from .registry import MODELS

__all__ = [
    "friction_events",
    "friction_force",
    "friction_jacobian",
    "friction_reset",
    "smooth_at_events",
    "uses_stick_force",
]


def _flag_table(flag: str) -> np.ndarray:
    """``table[code]``: the class variable ``flag`` of the model of each code (0: none)."""
    table = np.zeros(len(MODELS) + 1, dtype=np.bool_)
    for cls in MODELS.values():
        table[cls.code] = getattr(cls, flag)
    return table


_STICK = _flag_table("uses_stick_force")
_SMOOTH = _flag_table("smooth_at_events")


@jit(inline="always")
def uses_stick_force(code):
    """Does model ``code``'s force read the stick force ``F_e``?  Only the switching
    models do (the class variable ``uses_stick_force``); for the others a plant can pass
    ``F_e = 0`` and skip computing it."""
    return 0 < code < _STICK.shape[0] and _STICK[code]


@jit(inline="always")
def smooth_at_events(code):
    """Is model ``code``'s force continuous across its event crossings when its reset
    changes nothing (the class variable ``smooth_at_events``)?  Plants then answer
    ``Action.PASS`` instead of ``Action.CONTINUE``."""
    return 0 < code < _SMOOTH.shape[0] and _SMOOTH[code]


# ------------------------------------------------------------------ the chains
# One link per (model, kernel): ``if code == <its code>: return <its kernel>(...)``, else
# the rest of the chain.  The links are closures over the model's code and kernel (numba
# freezes both as constants); the end of each chain is the answer for an unknown code.

@jit(inline="always")
def _no_force(code, p, z, v, F_e, scale, dz):
    return 0.0


@jit(inline="always")
def _no_jacobian(code, p, z, v, F_e, scale, dz, Jz, dF):
    return 0.0


@jit(inline="always")
def _no_events(code, p, z, v, F_e, scale, g):
    return


@jit(inline="always")
def _no_reset(code, p, z, v, F_e, scale, k):
    return RESET_NONE


def _link(model_code, kernel, rest):
    """The link of a kernel ``(p, z, v, F_e, scale, last)`` that returns its answer: the
    force (``last`` is ``dz``) and the reset (``last`` is the event ``k``)."""
    def link(code, p, z, v, F_e, scale, last):
        if code == model_code:
            return kernel(p, z, v, F_e, scale, last)
        return rest(code, p, z, v, F_e, scale, last)
    return link


def _jacobian_link(model_code, kernel, rest):
    def link(code, p, z, v, F_e, scale, dz, Jz, dF):
        if code == model_code:
            return kernel(p, z, v, F_e, scale, dz, Jz, dF)
        return rest(code, p, z, v, F_e, scale, dz, Jz, dF)
    return link


def _events_link(model_code, kernel, rest):
    def link(code, p, z, v, F_e, scale, g):
        if code == model_code:
            kernel(p, z, v, F_e, scale, g)
        else:
            rest(code, p, z, v, F_e, scale, g)
    return link


def _chain(kind: str, make_link, end, doc: str):
    """The dispatcher over every registered model that provides a ``kind`` kernel (the
    first registered model is tested first); ``doc`` is its docstring."""
    fn = end
    for cls in reversed(tuple(MODELS.values())):
        kernel = getattr(cls.kernels, kind)
        if kernel is None:
            continue
        link = make_link(cls.code, kernel, fn)
        link.__name__ = link.__qualname__ = f"friction_{kind}_{cls.code}"
        link.__doc__ = doc
        fn = jit(link, inline="always", cache=False)
    return fn


_FORCE_DOC = """Friction force of model ``code``; writes the state derivatives into ``dz``.

Inlined into the caller: where ``code`` is a compile-time constant (the rig) the dispatch
folds to one kernel call, and no reference counts are taken for the arrays."""

_JACOBIAN_DOC = """Friction force of model ``code`` and its exact partial derivatives.

Returns the same force and writes the same ``dz`` as :func:`friction_force`, and writes
``Jz[i, j] = d dz_i/d z_j`` (``j < nz``), ``Jz[i, nz] = d dz_i/d v`` and ``dF`` =
(dF/dz_0, ..., dF/dz_{nz-1}, dF/dv, dF/dF_e, dF/dscale); see
:mod:`clutchsim.friction.base`.  Inlined like :func:`friction_force`."""

_EVENTS_DOC = "Event-function values of model ``code`` into ``g`` (no-op without events)."

_RESET_DOC = """Apply the reset of event ``k`` of model ``code``; returns a
:class:`~clutchsim.friction.base.FrictionReset` code."""

friction_force = _chain("force", _link, _no_force, _FORCE_DOC)
friction_jacobian = _chain("jacobian", _jacobian_link, _no_jacobian, _JACOBIAN_DOC)
friction_events = _chain("events", _events_link, _no_events, _EVENTS_DOC)
friction_reset = _chain("reset", _link, _no_reset, _RESET_DOC)
