"""A cone clutch: two conical friction faces pressed together by an axial force.

An axial force ``F`` on a cone of half-angle ``α`` (between the friction surface and the
axis) and mean radius ``R_m`` presses the faces together with the normal force
``F/sin α``; the friction torque at the mean radius is (uniform wear)::

    T = μ·F·R_m / sin α

opposing the slip ``w = ω_b − ω_a``, as the friction clutch's (:mod:`.friction`): the
element *is* that clutch, with any friction model of the library, ``mu_temperature``,
``mu_slip``, ``drag`` and heat into thermal nodes, and only its scale comes from the
geometry.  The model's force levels are read as the friction coefficient ``μ`` [-]
(``coulomb-robust``: ``F_c`` the sliding, ``F_s`` the static coefficient; ``tanh``:
``F_c``; ...) and the command is the axial force ``F`` [N] (negative values read as 0), so
the scale of the model is ``F·R_m/sin α`` [m·N] and ``capacity_<name>`` is
``μ_s·F·R_m/sin α``.  A small ``α`` wedges the cone (synchroniser cones are 6-8°,
``1/sin α`` ≈ 8-10 times a flat face's torque); ``α`` → 90° is a flat face.

References
----------
Shigley J.E., Budynas R.G., *Mechanical Engineering Design*, 10th ed., McGraw-Hill, 2015,
§16-4 "Cone Clutches and Brakes", eq. (16-26) (uniform wear: ``T = F·f·(D + d)/(4 sin α)``,
``(D + d)/4 = R_m``); MathWorks Simscape Driveline, Cone Clutch block (``T = μ·F·R_m/sin α``
with the same effective radius); Razzacki S.T., Hottenstein J.E., Synchronizer Design and
Development for Dual Clutch Transmission (DCT), SAE 2007-01-0114 (cone angles of
synchronisers).
"""

from __future__ import annotations

import math

from ..spec import Param
from .friction import Clutch

#: the largest static level accepted as a friction coefficient (dry and wet linings are
#: 0.05-0.6; a level above this is a torque [N·m] read from a parameter set by mistake)
MU_MAX = 2.0


class ConeClutch(Clutch):
    """A cone clutch between flanges a and b (see the module docstring)."""

    kind = "cone_clutch"
    title = "cone clutch (T = μ·F·R_m/sin α, any friction model)"
    params = (
        Param("R_m", "m", "mean radius of the friction cone", low=0.0, strict=True,
              high=1.0),
        Param("alpha", "°", "cone half-angle between the friction surface and the axis "
              "(below 90°: 90° is a flat face, a clutch)", low=0.0, strict=True, high=89.9),
        Param("drag", "N·m", "drag torque of the open cone, drag·tanh(w/1 rad/s)",
              default=0.0, low=0.0, high=1e6),
    )

    def __init__(self, name, model, command, mu_temperature=None, mu_slip=None, heat=(),
                 locked0=None, z0=None, **values):
        super().__init__(name, model, command, mu_temperature=mu_temperature,
                         mu_slip=mu_slip, heat=heat, locked0=locked0, z0=z0, **values)
        mu_s = model.static_capacity()
        if not mu_s <= MU_MAX:
            err = ValueError(f"{self.label}: the friction model's static level {mu_s:g} must "
                             f"be a friction coefficient <= {MU_MAX:g}: a cone clutch reads "
                             "its model's force levels as mu [-] (give them as overrides, "
                             "e.g. F_c = 0.1, F_s = 0.12 for coulomb-robust)")
            err.key = "friction"        # the scenario key it concerns (scenario/build.py)
            raise err

    @property
    def reads_force(self) -> bool:
        return True

    @property
    def wedge(self) -> float:
        """``R_m/sin α`` [m]: the torque over ``μ·F``."""
        return self.R_m / math.sin(math.radians(self.alpha))

    def pack(self):
        d = super().pack()
        # the command over clamp_reference is the model's scale: F/(sin α/R_m) = F·R_m/sin α
        d["clamp_reference"] = 1.0 / self.wedge
        return d
