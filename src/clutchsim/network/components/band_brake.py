"""A band brake: a flexible band wrapped round a drum, its torque from the capstan law.

A band of friction coefficient ``μ`` on a drum of radius ``R`` over the wrap angle ``θ``,
pulled by the apply force ``F_a`` at one end (the slack end; the other is anchored to the
housing), carries at the anchored, tight end ``F_t = F_a·e^{μθ}`` (Euler–Eytelwein capstan
equation); the drum feels the difference of the two band forces at its radius::

    T = F_a·R·(e^{μθ} − 1)

opposing the slip ``w = ω_flange − ω_support`` (the drum's speed relative to the housing).

The band is one friction coefficient in an exponent, not a torque level a friction model
scales linearly, so the element has its own law: the library's Coulomb stick/slip law
(``coulomb-robust``: the sliding direction from the slip, the drum held at rest while the
torque that holds it stays below the capacity, located stop and break-away events) with
the capstan factor ``e^{μθ} − 1`` as its level, scaled by ``F_a·R`` (``F_a`` the command,
an apply force [N], negative values read as 0).  Its outputs are the brake's
(``T_<name>``, ``w_slip_<name>``, ``capacity_<name>`` = ``F_a·R·(e^{μθ} − 1)``, ``P_<name>``).
The law is the same in both senses of rotation (the issue's law; a band anchored at one
end is self-energising one way only, which this element does not model).

References
----------
Euler L., Remarques sur l'effet du frottement dans l'équilibre, Mém. Acad. Sci. Berlin
18 (1762) 265-278 (the capstan equation); Shigley J.E., Budynas R.G., *Mechanical
Engineering Design*, 10th ed., McGraw-Hill, 2015, §16-3 "Band-Type Clutches and Brakes",
eqs. (16-13) and (16-14); MathWorks Simscape Driveline, Band Brake block.
"""

from __future__ import annotations

import math

from ...friction.coulomb_robust import CoulombRobust
from ..component import Component
from ..spec import Param
from .friction import Brake


class BandBrake(Brake):
    """A band brake from ``flange`` (the drum) to ``support`` (see the module docstring)."""

    kind = "band_brake"
    title = "band brake (capstan law T = F_a·R·(e^(μθ) − 1))"
    #: no friction table: the capstan law is its own (the scenario builder reads this)
    own_law = True
    params = (
        Param("R", "m", "drum radius", low=0.0, strict=True, high=10.0),
        Param("theta", "rad", "wrap angle of the band round the drum (3π/2 to 2π for a "
              "single wrap)", low=0.0, strict=True, high=4.0 * math.pi),
        Param("mu", "-", "friction coefficient between band and drum", low=0.0,
              strict=True, high=2.0),
        Param("drag", "N·m", "drag torque of the released band, drag·tanh(w/1 rad/s)",
              default=0.0, low=0.0, high=1e6),
    )

    def __init__(self, name, command, heat=(), locked0=None, **values):
        Component.__init__(self, name, **values)          # the values, checked
        k = self.capstan_factor
        super().__init__(name, CoulombRobust(F_c=k, F_s=k), command, heat=heat,
                         locked0=locked0, **values)

    @property
    def capstan_factor(self) -> float:
        """``e^{μθ} − 1`` [-]: the torque over ``F_a·R``."""
        return math.expm1(self.mu * self.theta)

    @property
    def reads_force(self) -> bool:
        return True

    def with_values(self, **changes):
        Component.with_values(self, **changes)            # the changes, checked
        return type(self)(self.name, self.command, heat=self.heat, locked0=self.locked0,
                          **{**self.values, **changes})

    def pack(self):
        d = super().pack()
        # the command over clamp_reference is the scale of the law: F_a/(1/R) = F_a·R
        d["clamp_reference"] = 1.0 / self.R
        return d
