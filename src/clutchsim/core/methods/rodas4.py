"""RODAS4: a 6-stage, L-stable, stiffly accurate Rosenbrock method of order 4(3).

Source: E. Hairer and G. Wanner, *Solving Ordinary Differential Equations II*, 2nd ed.,
Springer 1996, §IV.7, and their code ``rodas.f`` (coefficients in the transformed form, set
``METH = 1``), with its 3rd-order continuous extension.  Stages 5 and 6 are at ``t + h``;
the solution is the sixth stage's argument plus its increment, and the error estimate is
that increment.
"""

from __future__ import annotations

from . import DENSE_STAGES, RosenbrockTableau, register_method

_A = ((1.544,),
      (0.9466785280815826, 0.2557011698983284),
      (3.314825187068521, 2.896124015972201, 0.9986419139977817),
      (1.221224509226641, 6.019134481288629, 12.53708332932087, -0.6878860361058950))
_C = ((-5.6688,),
      (-2.430093356833875, -0.2063599157091915),
      (-0.1073529058151375, -9.594562251023355, -20.47028614809616),
      (7.496443313967647, -10.24680431464352, -33.99990352819905, 11.70890893206160),
      (8.083246795921522, -7.981132988064893, -31.52159432874371, 16.31930543123136,
       -6.058818238834054))
_A5 = _A[3]

RODAS4 = register_method(RosenbrockTableau(
    name="rodas4",
    description="RODAS4, L-stable stiffly accurate Rosenbrock 4(3), 6 stages; default",
    source="Hairer & Wanner, Solving ODEs II (1996), IV.7; rodas.f",
    gamma=0.25, order=4, embedded_order=3,
    transformed_form={
        "a": ((),) + _A + (_A5 + (1.0,),),
        "C": ((),) + _C,
        "c": (0.0, 0.386, 0.21, 0.63, 1.0, 1.0),
        "d": (0.25, -0.1043, 0.1035, -0.3620000000000023e-01, 0.0, 0.0),
        "m": _A5 + (1.0, 1.0),
        "e": (0.0, 0.0, 0.0, 0.0, 0.0, 1.0),
    },
    dense=DENSE_STAGES,
    H=((10.12623508344586, -7.487995877610167, -34.80091861555747, -7.992771707568823,
        1.025137723295662),
       (-0.6762803392801253, 6.087714651680015, 16.43084320892478, 24.76722511418386,
        -6.594389125716872)),
))
