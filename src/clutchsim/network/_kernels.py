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
from ..core.signals import interval

__all__ = ["LOSSY_TOL", "held_by_others", "lock_solve", "lossy_bounds", "lossy_coeffs",
           "lossy_solve", "table", "table_column"]

#: a pivot below this fraction of its diagonal entry marks a dependent (shielded) row
SHIELD_TOL = 1e-9


@jit(inline="always")
def table(p, o, n, x):
    """(value, slope) of the table with breakpoints ``p[o:o+n]`` and values
    ``p[o+n:o+2n]`` at ``x``, held constant outside (slope 0 there)."""
    return table_column(p, o, n, 1, x)


@jit(inline="always")
def table_column(p, o, n, k, x):
    """(value, slope) of value column ``k`` (1-based) of a table with breakpoints
    ``p[o:o+n]`` and value columns after them (each ``n`` long) at ``x``, held constant
    outside (slope 0 there)."""
    if n == 1 or x <= p[o]:
        return p[o + k * n], 0.0
    if x >= p[o + n - 1]:
        return p[o + (k + 1) * n - 1], 0.0
    lo = interval(p, o, n, x)
    hi = lo + 1
    s = (p[o + k * n + hi] - p[o + k * n + lo]) / (p[o + hi] - p[o + lo])
    return p[o + k * n + lo] + s * (x - p[o + lo]), s


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


#: torque band [N·m] by which a stuck lossy gear's holding torque may leave its limits
#: before it rolls.  An unloaded gear without bearing friction holds exactly its limits
#: (0 = 0), and round-off torques (~1e-16 N·m) around a standstill would otherwise pick
#: its rolling direction at random; the band makes the break-away function start
#: positive and the rolling direction follow the first real torque.
LOSSY_TOL = 1e-9


@jit(inline="always")
def lossy_coeffs(p, o, n, w):
    """Loss law of a lossy gear at ``|w|``: ``(eta_mf1, eta_mf2, tau_bf1, tau_bf2, tau_bf_a)``
    and the slopes of the first four with respect to ``|w|``.  The table at ``p[o:]`` holds
    ``n`` speeds, then the four value columns (each ``n`` long)."""
    x = abs(w)
    e1, d1 = table_column(p, o, n, 1, x)
    e2, d2 = table_column(p, o, n, 2, x)
    b1, d3 = table_column(p, o, n, 3, x)
    b2, d4 = table_column(p, o, n, 4, x)
    if abs(e1 - 1.0) <= 1e-15 and abs(e2 - 1.0) <= 1e-15:
        ba = 0.5 * b1
    else:
        ba = (b1 - b2) / (e1 - 1.0 / e2)
    return e1, e2, b1, b2, ba, d1, d2, d3, d4


@jit
def lossy_bounds(p, o, n, Ta):
    """(lower, upper) loss torque [N·m] a stuck lossy gear (table at ``p[o:]``, ``n``
    rows) holds at the flange-a torque ``Ta``: the rolling laws at ``|w| = 0`` (Modelica
    ``tauLossMin_m``, ``tauLossMax_p``)."""
    e1, e2, b1, b2, ba, _d1, _d2, _d3, _d4 = lossy_coeffs(p, o, n, 0.0)
    if Ta - ba > 0.0:
        up = (1.0 - e1) * Ta + b1
    else:
        up = (1.0 - 1.0 / e2) * Ta + b2
    if Ta + ba > 0.0:
        lo = (1.0 - 1.0 / e2) * Ta - b2
    else:
        lo = (1.0 - e1) * Ta - b1
    return lo, up


@jit
def lossy_solve(mode, T0, kk, e1, e2, b1, b2, ba, d1, d2, d3, d4):
    """Loss ``L`` of a rolling lossy gear and its partials ``(L, dL/dT0, dL/d|w|)``.

    Solves ``L = law(T)`` with ``T = T0 + kk·L`` (``kk``: how much of the loss comes back
    to flange a through the accelerations or a holder; 0 <= kk <= 1).  The law (Pelchen et
    al. 2002) is continuous and piecewise linear in ``T`` with slopes ``1 - eta_mf1 < 1``
    and ``1 - 1/eta_mf2 <= 0``, so ``T - kk·law(T)`` is increasing and the solution unique:
    the branch above the power-flow switch point is tried first.  ``d1..d4`` are the slopes
    of ``eta_mf1, eta_mf2, tau_bf1, tau_bf2`` in ``|w|``.
    """
    # each branch: L = c·T + d, with dc/d|w| and dd/d|w|
    if mode > 0.0:
        sw = ba
        cu, du, dcu, ddu = 1.0 - e1, b1, -d1, d3
        cl, dl, dcl, ddl = 1.0 - 1.0 / e2, b2, d2 / (e2 * e2), d4
    else:
        sw = -ba
        cu, du, dcu, ddu = 1.0 - 1.0 / e2, -b2, d2 / (e2 * e2), -d4
        cl, dl, dcl, ddl = 1.0 - e1, -b1, -d1, -d3
    den = 1.0 - cu * kk
    L = (cu * T0 + du) / den
    if T0 + kk * L < sw:
        cu, du, dcu, ddu = cl, dl, dcl, ddl
        den = 1.0 - cu * kk
        L = (cu * T0 + du) / den
    dL_dc = (T0 + du * kk) / (den * den)
    return L, cu / den, dL_dc * dcu + ddu / den


@jit
def held_by_others(p, s_off, m, act, i):
    """Is element ``i``'s slip held at zero by the active elements ``act`` (its row of ``S``
    depends on theirs: the reduced pivot ``S_ii − S_iA·S_AA⁻¹·S_Ai`` vanishes)?"""
    a = np.zeros((m, m))
    use = np.zeros(m)
    for r in range(m):
        if act[r] > 0.5 and r != i:
            use[r] = 1.0
    use[i] = 1.0
    for r in range(m):
        if use[r] > 0.5:
            for c in range(m):
                if use[c] > 0.5:
                    a[r, c] = p[s_off + r * m + c]
    for k in range(m):
        if k == i or use[k] < 0.5:
            continue
        d = p[s_off + k * m + k]
        if a[k, k] <= SHIELD_TOL * d or d <= 0.0:
            use[k] = 0.0
            continue
        for r in range(m):
            if r == k or use[r] < 0.5 or a[r, k] == 0.0:
                continue
            f = a[r, k] / a[k, k]
            for c in range(m):
                a[r, c] -= f * a[k, c]
    d = p[s_off + i * m + i]
    return d <= 0.0 or a[i, i] <= SHIELD_TOL * d
