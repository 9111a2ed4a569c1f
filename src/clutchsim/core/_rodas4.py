"""RODAS4: a 6-stage, L-stable, stiffly accurate Rosenbrock method of order 4(3).

Coefficients and the 3rd-order dense output are those of Hairer & Wanner's ``rodas.f``
(E. Hairer, G. Wanner, *Solving Ordinary Differential Equations II*, 2nd ed., Springer
1996, §IV.7).  The Jacobian is formed by forward differences, one column per state, plus
one difference in time for non-autonomous systems.
"""

from __future__ import annotations

import math

from .._jit import jit
from ._linalg import factor_iteration_matrix, lu_solve, lu_solve_row
from .signals import eval_inputs
from .system import system_rhs

ORDER = 4

GAM = 0.25
C2, C3, C4 = 0.386, 0.21, 0.63
D1, D2, D3, D4 = 0.25, -0.1043, 0.1035, -0.3620000000000023e-01
A21 = 1.544
A31, A32 = 0.9466785280815826, 0.2557011698983284
A41, A42, A43 = 3.314825187068521, 2.896124015972201, 0.9986419139977817
A51, A52, A53, A54 = 1.221224509226641, 6.019134481288629, 12.53708332932087, \
    -0.6878860361058950
C21 = -5.6688
C31, C32 = -2.430093356833875, -0.2063599157091915
C41, C42, C43 = -0.1073529058151375, -9.594562251023355, -20.47028614809616
C51, C52, C53, C54 = 7.496443313967647, -10.24680431464352, -33.99990352819905, \
    11.70890893206160
C61, C62, C63, C64, C65 = 8.083246795921522, -7.981132988064893, -31.52159432874371, \
    16.31930543123136, -6.058818238834054
H21, H22, H23, H24, H25 = 10.12623508344586, -7.487995877610167, -34.80091861555747, \
    -7.992771707568823, 1.025137723295662
H31, H32, H33, H34, H35 = -0.6762803392801253, 6.087714651680015, 16.43084320892478, \
    24.76722511418386, -6.594389125716872

_SQRT_EPS = math.sqrt(2.220446049250313e-16)


@jit
def jacobian(tag, bank, p, t, y, t_ref, f0, atol_over_rtol, u, ytmp, ftmp, J, dfdt, nd):
    """Forward-difference Jacobian ``J = df/dy`` and ``dfdt = df/dt`` at (t, y).

    Only the first ``nd`` columns are formed: the others belong to quadrature states (no
    derivative depends on them) and stay zero.  Returns the number of right-hand-side
    evaluations used."""
    n = y.shape[0]
    eval_inputs(bank, t, t_ref, u)
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
    dt = _SQRT_EPS * max(abs(t), 1e-3)
    eval_inputs(bank, t + dt, t_ref, u)
    system_rhs(tag, t + dt, y, u, p, ftmp)
    for i in range(n):
        dfdt[i] = (ftmp[i] - f0[i]) / dt
    return nd + 1


@jit
def rodas4_step(tag, bank, p, t, y, h, t_ref, f0, J, dfdt, M, piv, K, u, ytmp, ftmp,
                y_new, err, nd):
    """One RODAS4 step; fills K[0..4], ``y_new`` and the error estimate ``err``.

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
    eval_inputs(bank, t + C4 * h, t_ref, u)
    system_rhs(tag, t + C4 * h, ytmp, u, p, ftmp)
    for i in range(n):
        K[3, i] = ftmp[i] + h * D4 * dfdt[i] + (C41 * K[0, i] + C42 * K[1, i] + C43 * K[2, i]) / h
    lu_solve_row(M, piv, K, 3, nd)
    for i in range(n):
        ytmp[i] = y[i] + A51 * K[0, i] + A52 * K[1, i] + A53 * K[2, i] + A54 * K[3, i]
    eval_inputs(bank, t + h, t_ref, u)
    system_rhs(tag, t + h, ytmp, u, p, ftmp)
    for i in range(n):
        K[4, i] = ftmp[i] + (C51 * K[0, i] + C52 * K[1, i] + C53 * K[2, i] + C54 * K[3, i]) / h
    lu_solve_row(M, piv, K, 4, nd)
    for i in range(n):
        ytmp[i] += K[4, i]
    system_rhs(tag, t + h, ytmp, u, p, ftmp)
    for i in range(n):
        err[i] = ftmp[i] + (C61 * K[0, i] + C62 * K[1, i] + C63 * K[2, i] + C64 * K[3, i]
                            + C65 * K[4, i]) / h
    lu_solve(M, piv, err, nd)
    for i in range(n):
        y_new[i] = ytmp[i] + err[i]
    return True


@jit
def rodas4_dense(K, y, y_new, dense):
    """Coefficients of the continuous extension of the last step (see ``dense_eval``)."""
    n = y.shape[0]
    for i in range(n):
        dense[0, i] = y[i]
        dense[1, i] = y_new[i]
        dense[2, i] = H21 * K[0, i] + H22 * K[1, i] + H23 * K[2, i] + H24 * K[3, i] \
            + H25 * K[4, i]
        dense[3, i] = H31 * K[0, i] + H32 * K[1, i] + H33 * K[2, i] + H34 * K[3, i] \
            + H35 * K[4, i]
