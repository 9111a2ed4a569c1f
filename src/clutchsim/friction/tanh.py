"""tanh-regularised Coulomb friction (seed eq. 4)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .._jit import jit
from .base import FrictionKernels, Scales, StatelessModel, expect, parameters, steady_checks_at

__all__ = ["TanhFriction", "tanh_force", "tanh_jacobian"]


@dataclass(frozen=True)
class RegularisedCoulomb(StatelessModel):
    """What the regularised Coulomb laws (tanh, arctan) share: the Coulomb level ``F_c``,
    the regularisation velocity ``v_t`` and the viscous coefficient ``sigma2``."""

    F_c: float
    v_t: float
    sigma2: float = 0.0

    def static_capacity(self) -> float:
        """The Coulomb level ``F_c`` [N or N·m] (the force never exceeds it at rest)."""
        return self.F_c

    def typical_scales(self) -> Scales:
        return Scales(self.F_c, self.v_t, ())

    def _pack(self) -> list[float]:
        return [self.F_c, self.v_t, self.sigma2]


@dataclass(frozen=True)
class TanhFriction(RegularisedCoulomb):
    """Coulomb friction smoothed by tanh::

        F = scale·(F_c·tanh(v/v_t) + sigma2·v)

    No true stiction: under a constant force below ``F_c`` the body creeps.

    Parameters
    ----------
    F_c : float
        Coulomb level [N or N·m], >= 0.
    v_t : float
        Regularisation velocity [m/s or rad/s], > 0.
    sigma2 : float, optional
        Viscous coefficient [N·s/m or N·m·s/rad], >= 0, default 0.

    References
    ----------
    Mykhailevych M.G. (2020), eq. (4); MathWorks Powertrain Blockset, Disc Clutch.
    """

    name: ClassVar[str] = "tanh"
    passive: ClassVar[bool] = True
    citation: ClassVar[str] = (
        "Mykhailevych M.G., Model of friction for dry friction clutch working process "
        "simulation, Avtomobil i elektronika. Suchasni tekhnolohii, no. 18, 2020, eq. (4)."
    )
    parameter_info, parameter_rules = parameters(
        F_c=">= 0", v_t=("velocity", "tanh regularisation velocity", "> 0"), sigma2=">= 0")
    phenomena = expect(stiction="no (creep)", stribeck="no", presliding="no", lag="no",
                       varying_breakaway="no", no_drift="no")
    #: F_ss(v) at STEADY_CHECK_SPEEDS written out from the formula with the default set
    steady_checks: ClassVar[tuple[tuple[float, float], ...]] = steady_checks_at(
        -1.008, 1.0001092042625952, 1.0008, 1.12)
    default_parameter_set: ClassVar[str] = "tanh"

    def _steady(self, v: np.ndarray) -> np.ndarray:
        return self.F_c * np.tanh(v / self.v_t) + self.sigma2 * v


@jit
def tanh_force(p, z, v, F_e, scale, dz):
    return scale * (p[0] * math.tanh(v / p[1]) + p[2] * v)


@jit
def tanh_jacobian(p, z, v, F_e, scale, dz, Jz, dF):
    """Force and partials (see base); smooth everywhere."""
    F = tanh_force(p, z, v, F_e, scale, dz)
    th = math.tanh(v / p[1])
    dF[0] = scale * (p[0] * (1.0 - th * th) / p[1] + p[2])
    dF[1] = 0.0
    dF[2] = p[0] * th + p[2] * v
    return F


#: the kernels TanhFriction provides (compiled code calls exactly these)
TanhFriction.kernels = FrictionKernels(force=tanh_force, jacobian=tanh_jacobian)
