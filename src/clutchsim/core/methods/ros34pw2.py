"""ROS34PW2: a 4-stage, L-stable, stiffly accurate Rosenbrock-W method of order 3(2).

Source: J. Rang and L. Angermann, *New Rosenbrock W-methods of order 3 for partial
differential algebraic equations of index 1*, BIT Numerical Mathematics 45:761–787, 2005,
Table 4.2 (published ``α, γ, b, b̂``).

A W-method keeps its order when the matrix in ``I/(γh) − W`` only approximates the
Jacobian, so the integrator may reuse one Jacobian over many steps (and one inverted
iteration matrix while the step size changes little).  Dense output: the cubic Hermite interpolant through both ends
of the step and their slopes (third order, like the method).
"""

from __future__ import annotations

from . import DENSE_HERMITE, RosenbrockTableau, register_method

ROS34PW2 = register_method(RosenbrockTableau(
    name="ros34pw2",
    description="ROS34PW2, L-stable Rosenbrock-W 3(2), 4 stages, Jacobian reused over steps",
    source="Rang & Angermann, BIT 45:761-787 (2005), Table 4.2",
    gamma=0.435866521508459, order=3, embedded_order=2,
    alpha=((0.87173304301691801,),
           (0.84457060015369423, -0.11299064236484185),
           (0.0, 0.0, 1.0)),
    Gamma_lower=((-0.87173304301691801,),
                 (-0.90338057013044082, 0.054180672388095326),
                 (0.24212380706095346, -1.2232505839045147, 0.54526025533510214)),
    b=(0.24212380706095346, -1.2232505839045147, 1.5452602553351020, 0.435866521508459),
    b_hat=(0.37810903145819369, -0.096042292212423178, 0.5, 0.2179332607542295),
    dense=DENSE_HERMITE,
    w_method=True,
))
