"""Compiled helpers the generated network plants call (compiled once, shared by all).

* :func:`table` — value and slope of a piecewise-linear table held constant outside;
* :func:`lock_solve` — the torques of the locked friction elements: the small symmetric
  positive semi-definite system ``S_AA·x_A = r_A`` of the active elements ``A``
  (``S = B·M⁻¹·Bᵀ``, see :mod:`clutchsim.network.codegen`), by Gaussian elimination in
  element order.  An element whose row depends on the ones before it (two brakes holding
  the same part, a locked clutch in parallel with a locked brake path) gets a zero torque
  and is reported as *shielded*: the elements before it carry the load, and its own
  break-away test is suspended while it is shielded.  Written by hand because it must run
  inside compiled code without allocation beyond a few scalars per element, on systems of
  one to a few unknowns, where LAPACK calls cost more than the arithmetic.
"""

from __future__ import annotations

import numpy as np

from .._jit import jit

__all__ = ["lock_solve", "table"]

#: a pivot below this fraction of its diagonal entry marks a dependent (shielded) row
SHIELD_TOL = 1e-9


@jit(inline="always")
def table(p, o, n, x):
    """(value, slope) of the table with breakpoints ``p[o:o+n]`` and values
    ``p[o+n:o+2n]`` at ``x``, held constant outside (slope 0 there)."""
    if n == 1 or x <= p[o]:
        return p[o + n], 0.0
    if x >= p[o + n - 1]:
        return p[o + 2 * n - 1], 0.0
    lo, hi = 0, n - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if p[o + mid] <= x:
            lo = mid
        else:
            hi = mid
    s = (p[o + n + hi] - p[o + n + lo]) / (p[o + hi] - p[o + lo])
    return p[o + n + lo] + s * (x - p[o + lo]), s


@jit
def lock_solve(p, s_off, m, act, r, x, shielded):
    """Solve ``S_AA·x_A = r_A`` (``S`` row-major at ``p[s_off:]``, ``m × m``; ``act[e]``
    > 0.5 marks the active elements).  Writes ``x`` (0 for inactive and shielded
    elements) and ``shielded`` (1.0 where a row depended on earlier ones)."""
    a = np.zeros((m, m))
    b = np.zeros(m)
    use = np.zeros(m)
    for i in range(m):
        x[i] = 0.0
        shielded[i] = 0.0
        if act[i] > 0.5:
            use[i] = 1.0
            b[i] = r[i]
            for j in range(m):
                if act[j] > 0.5:
                    a[i, j] = p[s_off + i * m + j]
    for k in range(m):
        if use[k] < 0.5:
            continue
        d = p[s_off + k * m + k]
        if a[k, k] <= SHIELD_TOL * d or d <= 0.0:
            use[k] = 0.0
            shielded[k] = 1.0
            continue
        for i in range(k + 1, m):
            if use[i] < 0.5 or a[i, k] == 0.0:
                continue
            f = a[i, k] / a[k, k]
            for j in range(k, m):
                a[i, j] -= f * a[k, j]
            b[i] -= f * b[k]
    for k in range(m - 1, -1, -1):
        if use[k] < 0.5:
            continue
        s = b[k]
        for j in range(k + 1, m):
            if use[j] > 0.5:
                s -= a[k, j] * x[j]
        x[k] = s / a[k, k]
