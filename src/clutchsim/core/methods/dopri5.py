"""DOPRI5: the explicit Dormand–Prince 5(4) pair with its 4th-order continuous extension.

Source: J. R. Dormand and P. J. Prince, *A family of embedded Runge-Kutta formulae*,
J. Comput. Appl. Math. 6:19–26, 1980; dense output: L. F. Shampine, *Some practical
Runge-Kutta formulas*, Math. Comp. 46:135–150, 1986 (the one scipy's ``RK45`` uses).
First same as last: the seventh stage is ``f`` at the new point.
"""

from __future__ import annotations

from . import ExplicitTableau, register_method

DOPRI5 = register_method(ExplicitTableau(
    name="dopri5",
    description="Dormand-Prince 5(4), explicit, for non-stiff systems",
    source="Dormand & Prince, J. Comput. Appl. Math. 6 (1980); Shampine, Math. Comp. 46 (1986)",
    order=5, embedded_order=4,
    A=((1 / 5,),
       (3 / 40, 9 / 40),
       (44 / 45, -56 / 15, 32 / 9),
       (19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729),
       (9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656),
       (35 / 384, 0.0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84)),
    b=(35 / 384, 0.0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84, 0.0),
    b_hat=(5179 / 57600, 0.0, 7571 / 16695, 393 / 640, -92097 / 339200, 187 / 2100, 1 / 40),
    P=((1.0, -8048581381 / 2820520608, 8663915743 / 2820520608,
        -12715105075 / 11282082432),
       (0.0, 0.0, 0.0, 0.0),
       (0.0, 131558114200 / 32700410799, -68118460800 / 10900136933,
        87487479700 / 32700410799),
       (0.0, -1754552775 / 470086768, 14199869525 / 1410260304,
        -10690763975 / 1880347072),
       (0.0, 127303824393 / 49829197408, -318862633887 / 49829197408,
        701980252875 / 199316789632),
       (0.0, -282668133 / 205662961, 2019193451 / 616988883, -1453857185 / 822651844),
       (0.0, 40617522 / 29380423, -110615467 / 29380423, 69997945 / 29380423)),
))
