"""Small compiled helpers shared by the model kernels."""

from __future__ import annotations

import math

from .._jit import jit

__all__ = [
    "FREE_SCALE",
    "NO_EVENT",
    "clip",
    "clip_partials",
    "sgn",
    "sgn_right",
    "stribeck_level",
    "stribeck_partials",
]

#: Value of an event function that does not apply in the current mode.
NO_EVENT = 1.0

#: The scale a network plant hands an element's event functions when the element has none
#: (no command, no force): positive, so that a function of it keeps its sign at zero.
FREE_SCALE = 1e-300


@jit
def sgn(x):
    """Sign of ``x`` as a float: -1, 0 or +1."""
    if x > 0.0:
        return 1.0
    if x < 0.0:
        return -1.0
    return 0.0


@jit
def sgn_right(x):
    """Sign of ``x`` seen from the right at 0: -1 if ``x < 0``, else +1.

    The Jacobian kernels use it where ``|v|`` is differentiated: at exactly ``v = 0`` they
    give the one-sided derivative for ``v -> 0+`` (``d|v|/dv = +1``)."""
    return -1.0 if x < 0.0 else 1.0


@jit
def clip(x, bound):
    """Clip ``x`` to ``[-bound, bound]`` (``bound >= 0``)."""
    if x > bound:
        return bound
    if x < -bound:
        return -bound
    return x


@jit
def clip_partials(F_e, scale, F_s, dF, j):
    """Partial derivatives of the stick force ``clip(F_e, scale·F_s)`` into ``dF[j:j + 3]``
    (d/dv, d/dF_e, d/dscale) for the piece :func:`clip` evaluates: ``F_e`` itself inside
    the bound (and on it), ``±scale·F_s`` beyond it."""
    bound = scale * F_s
    dF[j] = 0.0
    if F_e > bound:
        dF[j + 1], dF[j + 2] = 0.0, F_s
    elif F_e < -bound:
        dF[j + 1], dF[j + 2] = 0.0, -F_s
    else:
        # F_e itself; with no capacity (bound 0) the force is 0 whatever F_e
        dF[j + 1], dF[j + 2] = (1.0 if bound > 0.0 else 0.0), 0.0


@jit
def _stribeck_exponent(v, v_s, delta):
    """``|v/v_s|^delta`` (``v_s > 0``)."""
    x = abs(v / v_s)
    # the usual exponents without a call to pow (this runs in every right-hand side)
    if delta == 2.0:
        return x * x
    if delta == 1.0:
        return x
    return x ** delta


@jit
def stribeck_level(v, F_c, F_s, v_s, delta):
    """Stribeck magnitude ``F_c + (F_s - F_c)·exp(-|v/v_s|^delta)`` (``v_s > 0``)."""
    return F_c + (F_s - F_c) * math.exp(-_stribeck_exponent(v, v_s, delta))


@jit
def stribeck_partials(v, F_c, F_s, v_s, delta):
    """The Stribeck level ``g`` of :func:`stribeck_level`, ``v·g'(v)`` and ``g'(v)``.

    ``v·g'(v) = -delta·e·(F_s - F_c)·exp(-e)`` with ``e = |v/v_s|^delta`` is finite
    everywhere (0 at ``v = 0``); kernels that multiply ``g'`` by ``|v|`` use it. ``g'`` at
    exactly ``v = 0``: 0 for ``delta > 1``; the limit ``v -> 0+``, ``-(F_s - F_c)/v_s``, for
    ``delta = 1``; for ``delta < 1`` the slope is unbounded there and 0 is returned (a
    finite stand-in at that single point: an infinite entry would make every stage solve fail)."""
    e = _stribeck_exponent(v, v_s, delta)
    drop = (F_s - F_c) * math.exp(-e)
    v_dg = -delta * e * drop
    if v != 0.0:
        dg = v_dg / v
    elif delta == 1.0:
        dg = -(F_s - F_c) / v_s
    else:
        dg = 0.0
    return F_c + drop, v_dg, dg
