"""Static exponential Stribeck curve (seed eq. 5)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .._jit import jit
from ._common import stribeck_level, stribeck_partials
from .base import (
    STRIBECK_STEADY_CHECKS,
    FrictionKernels,
    Scales,
    StatelessModel,
    expect,
    parameters,
)

__all__ = ["StribeckFriction", "stribeck_force", "stribeck_jacobian"]


@dataclass(frozen=True)
class StribeckFriction(StatelessModel):
    """Static Stribeck friction, smoothed through zero velocity by tanh::

        F = scale·([F_c + (F_s - F_c)·exp(-|v/v_s|^delta)]·tanh(v/v_t) + sigma2·v)

    This is our reading of the seed's eq. (5) (tanh instead of sign, so the
    curve is continuous). No states; creeps under sub-break-away loads.

    Parameters
    ----------
    F_c : float
        Coulomb level [N or N·m], >= 0.
    F_s : float
        Static (Stribeck peak) level [N or N·m], >= F_c.
    v_s : float
        Stribeck velocity [m/s or rad/s], > 0.
    delta : float, optional
        Stribeck exponent, 1 or 2 (default 2).
    v_t : float, optional
        tanh regularisation velocity [m/s or rad/s], > 0, default 1e-5.
    sigma2 : float, optional
        Viscous coefficient [N·s/m or N·m·s/rad], >= 0, default 0.

    References
    ----------
    Mykhailevych M.G. (2020), eq. (5); Armstrong-Hélouvry B., Dupont P.,
    Canudas de Wit C., "A survey of models, analysis tools and compensation
    methods for the control of machines with friction", Automatica
    30(7):1083-1138, 1994.
    """

    F_c: float
    F_s: float
    v_s: float
    delta: float = 2.0
    v_t: float = 1e-5
    sigma2: float = 0.0

    name: ClassVar[str] = "stribeck"
    passive: ClassVar[bool] = True
    citation: ClassVar[str] = (
        "Armstrong-Hélouvry B., Dupont P., Canudas de Wit C., A survey of models, analysis "
        "tools and compensation methods for the control of machines with friction, "
        "Automatica 30(7):1083-1138, 1994; Mykhailevych M.G., 2020, eq. (5)."
    )
    parameter_info, parameter_rules = parameters(
        F_c=">= 0", F_s=("force", "static (Stribeck peak) friction level", ">= F_c"), v_s="> 0",
        delta="1 or 2",
        v_t=("velocity", "tanh regularisation velocity", "> 0"), sigma2=">= 0")
    phenomena = expect(stiction="no (creep; needs a switch)", stribeck="yes", presliding="no",
                       lag="no", varying_breakaway="no", no_drift="no")
    steady_checks: ClassVar[tuple[tuple[float, float], ...]] = STRIBECK_STEADY_CHECKS
    default_parameter_set: ClassVar[str] = "stribeck"

    def static_capacity(self) -> float:
        """The static level ``F_s`` [N or N·m]."""
        return self.F_s

    def typical_scales(self) -> Scales:
        return Scales(self.F_c, min(self.v_t, self.v_s), ())

    def _pack(self) -> list[float]:
        return [self.F_c, self.F_s, self.v_s, self.delta, self.v_t, self.sigma2]

    def _steady(self, v: np.ndarray) -> np.ndarray:
        level = self.F_c + (self.F_s - self.F_c) * np.exp(-(np.abs(v / self.v_s) ** self.delta))
        return level * np.tanh(v / self.v_t) + self.sigma2 * v


@jit
def stribeck_force(p, z, v, F_e, scale, dz):
    level = stribeck_level(v, p[0], p[1], p[2], p[3])
    return scale * (level * math.tanh(v / p[4]) + p[5] * v)


@jit
def stribeck_jacobian(p, z, v, F_e, scale, dz, Jz, dF):
    """Force and partials (see base). At ``v = 0`` the Stribeck level's kink (``delta = 1``)
    is multiplied by ``tanh(0) = 0``, so the curve is smooth there."""
    F = stribeck_force(p, z, v, F_e, scale, dz)
    level, _, dlevel = stribeck_partials(v, p[0], p[1], p[2], p[3])
    th = math.tanh(v / p[4])
    dF[0] = scale * (dlevel * th + level * (1.0 - th * th) / p[4] + p[5])
    dF[1] = 0.0
    dF[2] = level * th + p[5] * v
    return F


#: the kernels StribeckFriction provides (compiled code calls exactly these)
StribeckFriction.kernels = FrictionKernels(force=stribeck_force, jacobian=stribeck_jacobian)
