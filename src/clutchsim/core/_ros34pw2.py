"""ROS34PW2: a 4-stage, L-stable, stiffly accurate Rosenbrock-W method of order 3(2).

J. Rang and L. Angermann, *New Rosenbrock W-methods of order 3 for partial differential
algebraic equations of index 1*, BIT Numerical Mathematics 45:761–787, 2005.

A *W*-method keeps its order when the matrix in ``(I/(γh) − W)`` is only an approximation
of the Jacobian.  The integrator therefore reuses one finite-difference Jacobian over many
steps (it is refreshed after a rejected step, an event, a breakpoint, or after
``JAC_MAX_AGE`` steps), so a step costs four right-hand sides (plus one at the new point
for the dense output, which is the next step's first stage) instead of RODAS4's six plus
``n + 1`` for a fresh Jacobian.  For the 15–20 states of a driveline this is ~5× fewer
right-hand-side evaluations per step.

The published coefficients are in the (α, γ, b, b̂) form; below they are in the transformed
form of Hairer & Wanner (*Solving ODEs II*, §IV.7, eq. 7.25) that the code uses:
``a = A Γ⁻¹``, ``c = diag(1/γ) − Γ⁻¹``, ``m = b Γ⁻¹`` and ``e = (b − b̂) Γ⁻¹``
(``tests/core/test_ros34pw2.py`` recomputes them from the published table and checks the
order conditions).  Dense output: the cubic Hermite interpolant through both ends of the
step with their derivatives (third order, like the method), written in the same form as
RODAS4's continuous extension so that one evaluation routine serves both.
"""

from __future__ import annotations

from .._jit import jit
from ._linalg import factor_iteration_matrix, lu_solve_row
from .signals import eval_inputs
from .system import system_rhs

ORDER = 3
#: a reused Jacobian is refreshed after this many accepted steps even if all went well
JAC_MAX_AGE = 40

GAM = 0.435866521508459
# published (Rang & Angermann 2005, Table 4.2)
ALPHA = ((0.0, 0.0, 0.0),
         (0.87173304301691801, 0.0, 0.0),
         (0.84457060015369423, -0.11299064236484185, 0.0),
         (0.0, 0.0, 1.0))
GAMMA = ((0.0, 0.0, 0.0),
         (-0.87173304301691801, 0.0, 0.0),
         (-0.90338057013044082, 0.054180672388095326, 0.0),
         (0.24212380706095346, -1.2232505839045147, 0.54526025533510214))
B = (0.24212380706095346, -1.2232505839045147, 1.5452602553351020, 0.435866521508459)
B_HAT = (0.37810903145819369, -0.096042292212423178, 0.5, 0.2179332607542295)

# stage times (row sums of alpha) and time-derivative weights (row sums of gamma incl. γ)
C2, C3 = 0.871733043016918, 0.7315799577888524
D1, D2, D3 = 0.435866521508459, -0.435866521508459, -0.4133333762338865
# transformed coefficients
A21 = 2.0000000000000004
A31, A32 = 1.4192173174557652, -0.2592322116729698
A41, A42, A43 = 4.184760482319161, -0.285192017355496, 2.2942803602790423
C21 = -4.588560720558084
C31, C32 = -4.184760482319161, 0.285192017355496
C41, C42, C43 = -6.36817920012836, -6.795620944466837, 2.8700986043310555
# m = (A41, A42, A43, 1): stiffly accurate, y1 = Y4 + u4
E1, E2, E3, E4 = 0.277749947647969, -1.4032398951759988, 1.7726301276675507, 0.5


@jit
def ros34pw2_step(tag, bank, p, t, y, h, t_ref, f0, J, dfdt, M, piv, K, u, ytmp, ftmp,
                  y_new, err, nd):
    """One ROS34PW2 step with the (possibly aged) Jacobian ``J``; fills K[0..3], ``y_new``
    and the error estimate ``err``.

    Returns False when the iteration matrix is singular (the caller shrinks the step)."""
    n = y.shape[0]
    if not factor_iteration_matrix(J, 1.0 / (GAM * h), M, piv, nd):
        return False
    for i in range(n):
        K[0, i] = f0[i] + h * D1 * dfdt[i]
    lu_solve_row(M, piv, K, 0, nd)
    for i in range(n):
        ytmp[i] = y[i] + A21 * K[0, i]
    eval_inputs(bank, t + C2 * h, t_ref, u)
    system_rhs(tag, t + C2 * h, ytmp, u, p, ftmp)
    for i in range(n):
        K[1, i] = ftmp[i] + h * D2 * dfdt[i] + C21 * K[0, i] / h
    lu_solve_row(M, piv, K, 1, nd)
    for i in range(n):
        ytmp[i] = y[i] + A31 * K[0, i] + A32 * K[1, i]
    eval_inputs(bank, t + C3 * h, t_ref, u)
    system_rhs(tag, t + C3 * h, ytmp, u, p, ftmp)
    for i in range(n):
        K[2, i] = ftmp[i] + h * D3 * dfdt[i] + (C31 * K[0, i] + C32 * K[1, i]) / h
    lu_solve_row(M, piv, K, 2, nd)
    for i in range(n):
        ytmp[i] = y[i] + A41 * K[0, i] + A42 * K[1, i] + A43 * K[2, i]
    eval_inputs(bank, t + h, t_ref, u)
    system_rhs(tag, t + h, ytmp, u, p, ftmp)
    # gamma_4 = 0: no time-derivative term in the last stage
    for i in range(n):
        K[3, i] = ftmp[i] + (C41 * K[0, i] + C42 * K[1, i] + C43 * K[2, i]) / h
    lu_solve_row(M, piv, K, 3, nd)
    for i in range(n):
        y_new[i] = ytmp[i] + K[3, i]
        err[i] = E1 * K[0, i] + E2 * K[1, i] + E3 * K[2, i] + E4 * K[3, i]
    return True


@jit
def hermite_dense(y, y_new, f0, f1, h, dense):
    """Cubic Hermite coefficients of the last step in the form read by ``dense_eval``:
    ``y(s) = (1−s)·d0 + s·(d1 + (1−s)·(d2 + s·d3))``."""
    n = y.shape[0]
    for i in range(n):
        delta = y_new[i] - y[i]
        dense[0, i] = y[i]
        dense[1, i] = y_new[i]
        dense[2, i] = h * f0[i] - delta
        dense[3, i] = 2.0 * delta - h * f0[i] - h * f1[i]

