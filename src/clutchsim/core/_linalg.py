"""Dense LU with partial pivoting for the small systems of the Rosenbrock stages.

numba offers ``np.linalg.solve`` but no reusable factorisation (and a LAPACK call costs more
than the whole solve for the 3–20 states of our plants); a Rodas step solves six systems with
one matrix, so we factorise once and back-substitute six times.

The factor stores the *reciprocal* of each pivot on the diagonal, so that back-substitution
multiplies instead of dividing (a division is a ~15-cycle latency on the critical path of
every solve).  The solves are inlined into the stepper: a call with array arguments would
cost two atomic reference-count operations per array (measured: with the solves, the input
evaluation and the Rodas stage rows called out of line, reference counting was ~20 % of
the integrator's time).

Quadrature states.  The last ``n - nd`` states of a plant may be pure integrals (energy
accounts): no derivative depends on them, so their Jacobian columns are zero and the
iteration matrix is block lower triangular, ``[[A, 0], [C, I/(γh)]]``.  Every function
here takes ``nd``: only the leading ``nd × nd`` block is factorised (LU work ~nd³ instead of
n³), and a solve finishes the quadrature rows by one substitution each (CVODES treats such
"quadrature variables" the same way, outside its Newton iteration).  ``nd = n`` is the
plain dense case.
"""

from __future__ import annotations

import math

from .._jit import jit


@jit
def lu_factor(a, piv, nd):
    """Factorise the leading ``nd × nd`` block of ``a`` in place (Doolittle, partial
    pivoting). Returns False if singular.

    On return the strict lower triangle holds the multipliers, the upper triangle ``U``
    and the diagonal ``1 / U[k, k]``."""
    n = nd
    for k in range(n):
        m = k
        big = abs(a[k, k])
        for i in range(k + 1, n):
            if abs(a[i, k]) > big:
                big = abs(a[i, k])
                m = i
        piv[k] = m
        if big == 0.0 or math.isnan(big):
            return False
        if m != k:
            for j in range(n):
                tmp = a[k, j]
                a[k, j] = a[m, j]
                a[m, j] = tmp
        inv = 1.0 / a[k, k]
        a[k, k] = inv
        for i in range(k + 1, n):
            a[i, k] *= inv
            f = a[i, k]
            if f != 0.0:
                for j in range(k + 1, n):
                    a[i, j] -= f * a[k, j]
    return True


@jit(inline="always")
def lu_solve(a, piv, b, nd):
    """Solve ``a x = b`` in place in ``b`` with the factors from
    :func:`factor_iteration_matrix` (leading block ``nd``, quadrature rows below)."""
    n = a.shape[0]
    for k in range(nd):
        m = piv[k]
        if m != k:
            tmp = b[k]
            b[k] = b[m]
            b[m] = tmp
    for i in range(nd):
        s = b[i]
        for j in range(i):
            s -= a[i, j] * b[j]
        b[i] = s
    for i in range(nd - 1, -1, -1):
        s = b[i]
        for j in range(i + 1, nd):
            s -= a[i, j] * b[j]
        b[i] = s * a[i, i]
    for i in range(nd, n):
        s = b[i]
        for j in range(nd):
            s -= a[i, j] * b[j]
        b[i] = s * a[i, i]


@jit(inline="always")
def lu_solve_row(a, piv, B, r, nd):
    """Solve ``a x = B[r]`` in place in row ``r`` of ``B`` (indexing, not a row view: a
    view would cost a reference count); as :func:`lu_solve`."""
    n = a.shape[0]
    for k in range(nd):
        m = piv[k]
        if m != k:
            tmp = B[r, k]
            B[r, k] = B[r, m]
            B[r, m] = tmp
    for i in range(nd):
        s = B[r, i]
        for j in range(i):
            s -= a[i, j] * B[r, j]
        B[r, i] = s
    for i in range(nd - 1, -1, -1):
        s = B[r, i]
        for j in range(i + 1, nd):
            s -= a[i, j] * B[r, j]
        B[r, i] = s * a[i, i]
    for i in range(nd, n):
        s = B[r, i]
        for j in range(nd):
            s -= a[i, j] * B[r, j]
        B[r, i] = s * a[i, i]


@jit(inline="always")
def factor_iteration_matrix(J, inv_gamma_h, M, piv, nd):
    """Form ``M = I/(γh) − J`` and factorise it in place (the matrix of every stage of a
    Rosenbrock step): the leading ``nd × nd`` block by LU, the quadrature rows ``i >= nd``
    keep ``−J[i, :nd]`` and the reciprocal ``γh`` of their diagonal.  Returns False if it
    is singular."""
    n = J.shape[0]
    for i in range(n):
        for j in range(nd):
            M[i, j] = -J[i, j]
        M[i, i] = inv_gamma_h - J[i, i]
    for i in range(nd, n):
        M[i, i] = 1.0 / inv_gamma_h
    return lu_factor(M, piv, nd)
