"""Small compiled helpers shared by the model kernels."""

from __future__ import annotations

import math

from .._jit import jit

__all__ = ["NO_EVENT", "clip", "sgn", "stribeck_level"]

#: Value of an event function that does not apply in the current mode.
NO_EVENT = 1.0


@jit
def sgn(x):
    """Sign of ``x`` as a float: -1, 0 or +1."""
    if x > 0.0:
        return 1.0
    if x < 0.0:
        return -1.0
    return 0.0


@jit
def clip(x, bound):
    """Clip ``x`` to ``[-bound, bound]`` (``bound >= 0``)."""
    if x > bound:
        return bound
    if x < -bound:
        return -bound
    return x


@jit
def stribeck_level(v, F_c, F_s, v_s, delta):
    """Stribeck magnitude ``F_c + (F_s - F_c)·exp(-|v/v_s|^delta)`` (``v_s > 0``)."""
    x = abs(v / v_s)
    # the usual exponents without a call to pow (this runs in every right-hand side)
    if delta == 2.0:
        e = x * x
    elif delta == 1.0:
        e = x
    else:
        e = x ** delta
    return F_c + (F_s - F_c) * math.exp(-e)
