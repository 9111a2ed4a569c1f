"""Dormand–Prince 5(4) step with its 4th-order continuous extension.

Coefficients: Dormand & Prince, J. Comput. Appl. Math. 6 (1980) 19–26; the dense-output
polynomial is Shampine's (Math. Comp. 46 (1986) 135–150), the one scipy's ``RK45`` uses.
"""

from __future__ import annotations

from .._jit import jit
from .signals import eval_inputs
from .system import system_rhs

ORDER = 5

C2, C3, C4, C5 = 1 / 5, 3 / 10, 4 / 5, 8 / 9
A21 = 1 / 5
A31, A32 = 3 / 40, 9 / 40
A41, A42, A43 = 44 / 45, -56 / 15, 32 / 9
A51, A52, A53, A54 = 19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729
A61, A62, A63, A64, A65 = 9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656
B1, B3, B4, B5, B6 = 35 / 384, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84
E1, E3, E4, E5, E6, E7 = (-71 / 57600, 71 / 16695, -71 / 1920, 17253 / 339200, -22 / 525,
                          1 / 40)
# dense output: y(t0 + x h) = y0 + h * sum_i K_i * (P_i1 x + P_i2 x^2 + P_i3 x^3 + P_i4 x^4)
P11, P12, P13, P14 = 1.0, -8048581381 / 2820520608, 8663915743 / 2820520608, \
    -12715105075 / 11282082432
P31, P32, P33, P34 = 0.0, 131558114200 / 32700410799, -68118460800 / 10900136933, \
    87487479700 / 32700410799
P41, P42, P43, P44 = 0.0, -1754552775 / 470086768, 14199869525 / 1410260304, \
    -10690763975 / 1880347072
P51, P52, P53, P54 = 0.0, 127303824393 / 49829197408, -318862633887 / 49829197408, \
    701980252875 / 199316789632
P61, P62, P63, P64 = 0.0, -282668133 / 205662961, 2019193451 / 616988883, \
    -1453857185 / 822651844
P71, P72, P73, P74 = 0.0, 40617522 / 29380423, -110615467 / 29380423, 69997945 / 29380423


@jit
def dopri5_step(tag, bank, p, t, y, h, t_ref, K, u, ytmp, y_new, err):
    """One step from (t, y) with K[0] = f(t, y) given; fills K[1..6], y_new and the
    error estimate ``err`` (K[6] = f(t + h, y_new), usable as the next K[0])."""
    n = y.shape[0]
    for i in range(n):
        ytmp[i] = y[i] + h * A21 * K[0, i]
    eval_inputs(bank, t + C2 * h, t_ref, u)
    system_rhs(tag, t + C2 * h, ytmp, u, p, K[1])
    for i in range(n):
        ytmp[i] = y[i] + h * (A31 * K[0, i] + A32 * K[1, i])
    eval_inputs(bank, t + C3 * h, t_ref, u)
    system_rhs(tag, t + C3 * h, ytmp, u, p, K[2])
    for i in range(n):
        ytmp[i] = y[i] + h * (A41 * K[0, i] + A42 * K[1, i] + A43 * K[2, i])
    eval_inputs(bank, t + C4 * h, t_ref, u)
    system_rhs(tag, t + C4 * h, ytmp, u, p, K[3])
    for i in range(n):
        ytmp[i] = y[i] + h * (A51 * K[0, i] + A52 * K[1, i] + A53 * K[2, i] + A54 * K[3, i])
    eval_inputs(bank, t + C5 * h, t_ref, u)
    system_rhs(tag, t + C5 * h, ytmp, u, p, K[4])
    for i in range(n):
        ytmp[i] = y[i] + h * (A61 * K[0, i] + A62 * K[1, i] + A63 * K[2, i] + A64 * K[3, i]
                              + A65 * K[4, i])
    eval_inputs(bank, t + h, t_ref, u)
    system_rhs(tag, t + h, ytmp, u, p, K[5])
    for i in range(n):
        y_new[i] = y[i] + h * (B1 * K[0, i] + B3 * K[2, i] + B4 * K[3, i] + B5 * K[4, i]
                               + B6 * K[5, i])
    system_rhs(tag, t + h, y_new, u, p, K[6])
    for i in range(n):
        err[i] = h * (E1 * K[0, i] + E3 * K[2, i] + E4 * K[3, i] + E5 * K[4, i]
                      + E6 * K[5, i] + E7 * K[6, i])


@jit
def dopri5_dense(K, y, h, dense):
    """Coefficients of the continuous extension of the last step (see ``dense_eval``)."""
    n = y.shape[0]
    for i in range(n):
        dense[0, i] = y[i]
        dense[1, i] = h * (P11 * K[0, i])
        dense[2, i] = h * (P12 * K[0, i] + P32 * K[2, i] + P42 * K[3, i] + P52 * K[4, i]
                           + P62 * K[5, i] + P72 * K[6, i])
        dense[3, i] = h * (P13 * K[0, i] + P33 * K[2, i] + P43 * K[3, i] + P53 * K[4, i]
                           + P63 * K[5, i] + P73 * K[6, i])
        dense[4, i] = h * (P14 * K[0, i] + P34 * K[2, i] + P44 * K[3, i] + P54 * K[4, i]
                           + P64 * K[5, i] + P74 * K[6, i])
