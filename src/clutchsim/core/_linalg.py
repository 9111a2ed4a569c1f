"""Explicit inverse of the iteration matrix for the small systems of the Rosenbrock stages.

Every stage of a Rosenbrock step solves a system with the same matrix ``M = I/(γh) − J``
(six stages for RODAS4, eight for RODAS5P).  :func:`invert_iteration_matrix` forms ``M``
and replaces its leading block by its inverse (Gauss–Jordan elimination with partial
pivoting); :func:`solve_into_row` then solves a stage as a matrix–vector product: ``nd``
independent dot products, which the CPU overlaps, where the forward and back
substitutions of an LU were chains of dependent rows.  numba offers no reusable
factorisation, and a LAPACK call costs more than the whole solve for the 3–20 states of
our plants.  A plant may bring its own factors of ``M`` instead (``factor``/``solve`` of
:mod:`clutchsim.core.system`: the network plants' straight-line elimination for the
sparsity of their Jacobian, :mod:`clutchsim.network.elimination`); this inverse is then the
fallback for the matrices their static order refuses.

Measured on the default launch (model (6), RODAS5P, 10 × 10 block, 16 states; AMD EPYC,
2 cores, load ~2, ``benchmarks/step_cost.py``): forming the matrix and inverting it costs
458 ns against 404 ns for the LU (the elimination skips zero multipliers, so not the
3× of the flop count), a stage solve 53 ns against 158 ns; the compiled loop 3.30 → 2.69 ms
(minima of 240 runs, alternating processes; medians 4.98 → 4.00 ms).  Round-off moves the
launch's steps (621 → 611 accepted) but not its lock-up time (within 4e-9 s).

The functions are inlined into the stepper: a call with array arguments would cost two
atomic reference-count operations per array (measured: with the solves, the input
evaluation and the Rodas stage rows called out of line, reference counting was ~20 % of
the integrator's time); for the same reason a solve writes into a row of the stage array
by indexing, not through a row view.

Quadrature states.  The last ``n - nd`` states of a plant may be pure integrals (energy
accounts): no derivative depends on them, so their Jacobian columns are zero and the
iteration matrix is block lower triangular, ``[[A, 0], [C, I/(γh)]]``.  Only ``A`` is
inverted (work ~nd³ instead of n³), and a solve finishes the quadrature rows by one
substitution each, ``x_q = γh·(b_q − C·x_d)`` (CVODES treats such "quadrature variables"
the same way, outside its Newton iteration).  ``nd = n`` is the plain dense case.
"""

from __future__ import annotations

import math

from .._jit import jit


@jit(inline="always")
def invert_iteration_matrix(J, inv_gamma_h, M, piv, nd):
    """Form ``M = I/(γh) − J`` with its leading ``nd × nd`` block ``A`` replaced by
    ``A⁻¹`` (in-place Gauss–Jordan elimination with partial pivoting; ``piv`` is scratch
    for the ``nd`` pivot rows).  The quadrature rows ``i >= nd`` keep ``C = −J[i, :nd]``
    and ``γh`` on the diagonal.  Returns False if ``A`` is singular (or has a NaN pivot).
    """
    n = J.shape[0]
    for i in range(n):
        for j in range(nd):
            M[i, j] = -J[i, j]
        M[i, i] = inv_gamma_h - J[i, i]
    for i in range(nd, n):
        M[i, i] = 1.0 / inv_gamma_h
    for k in range(nd):
        m = k
        big = abs(M[k, k])
        for i in range(k + 1, nd):
            if abs(M[i, k]) > big:
                big = abs(M[i, k])
                m = i
        piv[k] = m
        if big == 0.0 or math.isnan(big):
            return False
        if m != k:
            for j in range(nd):
                tmp = M[k, j]
                M[k, j] = M[m, j]
                M[m, j] = tmp
        inv = 1.0 / M[k, k]
        M[k, k] = 1.0
        for j in range(nd):
            M[k, j] *= inv
        for i in range(nd):
            f = M[i, k]
            if i != k and f != 0.0:
                M[i, k] = 0.0
                for j in range(nd):
                    M[i, j] -= f * M[k, j]
    # the row interchanges, undone as column interchanges in reverse order
    for k in range(nd - 1, -1, -1):
        m = piv[k]
        if m != k:
            for i in range(nd):
                tmp = M[i, k]
                M[i, k] = M[i, m]
                M[i, m] = tmp
    return True


@jit(inline="always")
def solve_into_row(M, b, X, r, nd):
    """``X[r] = M⁻¹·b`` with ``M`` from :func:`invert_iteration_matrix` (``b`` is not
    changed; it must not be row ``r`` of ``X``)."""
    n = M.shape[0]
    for i in range(nd):
        s = 0.0
        for j in range(nd):
            s += M[i, j] * b[j]
        X[r, i] = s
    for i in range(nd, n):
        s = b[i]
        for j in range(nd):
            s -= M[i, j] * X[r, j]
        X[r, i] = s * M[i, i]

