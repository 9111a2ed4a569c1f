"""Compiled steps of the two method families, driven by tableaus passed as data.

One Rosenbrock(-W) step (:func:`ros_step`) and one explicit Runge–Kutta step
(:func:`erk_step`) serve every method of :mod:`clutchsim.core.methods`: the coefficients
arrive as arrays (``a, C, c, d, m, e`` and the dense-output rows), so the integrator is
compiled once for all methods.  Zero coefficients are skipped, so a sparse tableau costs no
more than its non-zeros.

Inputs are evaluated at most once per distinct stage time (:func:`inputs_at`): RODAS-type
methods place several stages at ``t + h``.

The steps are inlined into the integration loop: as calls they took their ~20 array
arguments through atomic reference counts every step, which made the default launch 25 %
slower (15.3 against 12.2 ms, min of 40, quiet machine) at no gain in compile time.
"""

from __future__ import annotations

import math

from .._jit import jit
from ._linalg import solve_into_row
from .methods import DENSE_HERMITE, DENSE_POLY
from .signals import eval_inputs
from .system import system_jac, system_rhs, system_solve

_SQRT_EPS = math.sqrt(2.220446049250313e-16)


@jit(inline="always")
def inputs_at(bank, t, t_ref, u, uc):
    """Evaluate the inputs into ``u`` at ``t`` (on the side of ``t_ref`` of a breakpoint)
    unless they were last evaluated there (``uc = [t, t_ref]`` of the last evaluation)."""
    if t != uc[0] or t_ref != uc[1]:
        eval_inputs(bank, t, t_ref, u)
        uc[0] = t
        uc[1] = t_ref


@jit(inline="always")
def _stage_argument(ytmp, y, A, st, K, scale):
    """``ytmp = y + scale·Σ_{j<st} A[st, j]·K[j]`` (zero coefficients skipped)."""
    n = y.shape[0]
    for i in range(n):
        ytmp[i] = y[i]
    for j in range(st):
        w = scale * A[st, j]
        if w != 0.0:
            for i in range(n):
                ytmp[i] += w * K[j, i]


@jit
def stiffly_accurate_rows(A, m, ext):
    """Mark in ``ext`` (length ``s + 1``) where RODAS' stiffly accurate structure lets a
    step reuse the previous stage's argument (derived once per run, read by
    :func:`ros_step` at every stage):

    * ``ext[st] = 1`` (``st >= 2``): row ``st`` of ``A`` is row ``st - 1`` with a 1 added
      at column ``st - 1``, so the argument of stage ``st`` is that of stage ``st - 1``
      plus ``K[st - 1]``, bit for bit (:func:`_stage_argument` adds the same terms in the
      same order, then ``1·K[st - 1]``);
    * ``ext[s] = 1``: the solution weights ``m`` are the last row of ``A`` with a 1 added
      at the last stage, so ``y_new`` is the last stage's argument plus ``K[s - 1]``."""
    s = m.shape[0]
    for st in range(s + 1):
        ext[st] = 0
    for st in range(2, s + 1):
        row_is_m = st == s
        if (m[s - 1] if row_is_m else A[st, st - 1]) != 1.0:
            continue
        same = True
        for j in range(st - 1):
            if (m[j] if row_is_m else A[st, j]) != A[st - 1, j]:
                same = False
                break
        if same:
            ext[st] = 1


@jit(inline="always")
def jacobian(tag, bank, p, t, y, t_ref, f0, atol_over_rtol, u, uc, ytmp, ftmp, J, dfdt, nd,
             exact):
    """``J = ∂f/∂y`` (the plant's exact Jacobian when ``exact``, else forward differences
    over the first ``nd`` columns; the quadrature columns stay zero) and ``dfdt = ∂f/∂t`` by
    a forward difference in time.  Returns the number of right-hand-side evaluations."""
    n = y.shape[0]
    inputs_at(bank, t, t_ref, u, uc)
    calls = 0
    if exact:
        system_jac(tag, t, y, u, p, J)
    else:
        for i in range(n):
            ytmp[i] = y[i]
        for j in range(nd):
            delta = _SQRT_EPS * max(abs(y[j]), atol_over_rtol, 1e-10)
            ytmp[j] = y[j] + delta
            delta = ytmp[j] - y[j]
            system_rhs(tag, t, ytmp, u, p, ftmp)
            for i in range(n):
                J[i, j] = (ftmp[i] - f0[i]) / delta
            ytmp[j] = y[j]
        calls = nd
    dt = _SQRT_EPS * max(abs(t), 1e-3)
    inputs_at(bank, t + dt, t_ref, u, uc)
    system_rhs(tag, t + dt, y, u, p, ftmp)
    for i in range(n):
        dfdt[i] = (ftmp[i] - f0[i]) / dt
    return calls + 1


@jit(inline="always")
def ros_step(tag, bank, p, t, y, h, t_ref, f0, dfdt, M, F, structured, K, u, uc, ytmp, ftmp,
             y_new, err, nd, tab, ext):
    """One Rosenbrock step with the iteration matrix ``I/(γh) − J`` factored by the plant
    into ``F`` (``structured``, :func:`~.system.system_factor`) or else inverted into ``M``
    (:func:`~._linalg.invert_iteration_matrix`); fills the stage increments ``K[0..s-1]``,
    ``y_new`` and the error estimate ``err`` (``ftmp`` ends as the last stage's right-hand
    side of its system).  ``ext``: the tableau's :func:`stiffly_accurate_rows`.  Returns
    the number of right-hand-side evaluations."""
    a, C, c, d, m, e = tab[0], tab[1], tab[2], tab[3], tab[4], tab[5]
    s = c.shape[0]
    n = y.shape[0]
    inv_h = 1.0 / h
    for st in range(s):
        if st == 0:
            for i in range(n):
                ftmp[i] = f0[i]
        else:
            if ext[st] != 0:    # ytmp holds stage st-1's argument
                for i in range(n):
                    ytmp[i] += K[st - 1, i]
            else:
                _stage_argument(ytmp, y, a, st, K, 1.0)
            ts = t + c[st] * h
            inputs_at(bank, ts, t_ref, u, uc)
            system_rhs(tag, ts, ytmp, u, p, ftmp)
        hd = h * d[st]
        if hd != 0.0:
            for i in range(n):
                ftmp[i] += hd * dfdt[i]
        for j in range(st):
            cij = C[st, j] * inv_h
            if cij != 0.0:
                for i in range(n):
                    ftmp[i] += cij * K[j, i]
        if structured:
            system_solve(tag, F, ftmp, K, st)
        else:
            solve_into_row(M, ftmp, K, st, nd)
    if ext[s] != 0:     # ytmp holds the last stage's argument
        for i in range(n):
            y_new[i] = ytmp[i] + K[s - 1, i]
    else:
        for i in range(n):
            y_new[i] = y[i]
        for j in range(s):
            mj = m[j]
            if mj != 0.0:
                for i in range(n):
                    y_new[i] += mj * K[j, i]
    for i in range(n):
        err[i] = 0.0
    for j in range(s):
        ej = e[j]
        if ej != 0.0:
            for i in range(n):
                err[i] += ej * K[j, i]
    return s - 1


@jit(inline="always")
def erk_step(tag, bank, p, t, y, h, t_ref, K, u, uc, ytmp, y_new, err, tab):
    """One explicit Runge–Kutta step from (t, y) with ``K[0] = f(t, y)`` given; fills the
    stages ``K[1..s-1]``, ``y_new`` and ``err``.  For a first-same-as-last pair the last
    stage is ``f(t + h, y_new)``.  Returns the number of right-hand-side evaluations."""
    A, c, b, e = tab[0], tab[2], tab[4], tab[5]
    s = c.shape[0]
    n = y.shape[0]
    for st in range(1, s):
        _stage_argument(ytmp, y, A, st, K, h)
        ts = t + c[st] * h
        inputs_at(bank, ts, t_ref, u, uc)
        system_rhs(tag, ts, ytmp, u, p, K[st])
    for i in range(n):
        y_new[i] = y[i]
        err[i] = 0.0
    for j in range(s):
        bj = h * b[j]
        ej = h * e[j]
        for i in range(n):
            y_new[i] += bj * K[j, i]
            err[i] += ej * K[j, i]
    return s - 1


@jit(inline="always")
def dense_coefficients(kind, tab, K, y, y_new, f0, f1, h, dense):
    """Coefficients of the continuous extension of the last step, read by
    :func:`dense_eval`.

    Rosenbrock forms (Hermite, stages): ``y(s) = (1−s)·d0 + s·(d1 + (1−s)·(d2 + s·(d3 +
    s·d4)))``; explicit polynomial: ``y(s) = d0 + s·(d1 + s·(d2 + s·(d3 + s·d4)))``."""
    n = y.shape[0]
    H = tab[6]
    s = K.shape[0] if kind == DENSE_POLY else tab[2].shape[0]
    for i in range(n):
        dense[0, i] = y[i]
        dense[1, i] = y_new[i]
        dense[2, i] = 0.0
        dense[3, i] = 0.0
        dense[4, i] = 0.0
    if kind == DENSE_HERMITE:
        for i in range(n):
            delta = y_new[i] - y[i]
            dense[2, i] = h * f0[i] - delta
            dense[3, i] = 2.0 * delta - h * f0[i] - h * f1[i]
    elif kind == DENSE_POLY:
        for i in range(n):
            dense[1, i] = 0.0
        for r in range(4):
            for j in range(s):
                w = h * H[r, j]
                if w != 0.0:
                    for i in range(n):
                        dense[r + 1, i] += w * K[j, i]
    else:
        for r in range(3):
            for j in range(s):
                w = H[r, j]
                if w != 0.0:
                    for i in range(n):
                        dense[r + 2, i] += w * K[j, i]


@jit
def dense_eval(kind, dense, s, out):
    """State at fraction ``s`` in [0, 1] of the last accepted step (see
    :func:`dense_coefficients`)."""
    n = out.shape[0]
    if kind == DENSE_POLY:
        for i in range(n):
            out[i] = dense[0, i] + s * (dense[1, i] + s * (dense[2, i] + s * (
                dense[3, i] + s * dense[4, i])))
    else:
        s1 = 1.0 - s
        for i in range(n):
            out[i] = dense[0, i] * s1 + s * (dense[1, i] + s1 * (dense[2, i] + s * (
                dense[3, i] + s * dense[4, i])))
