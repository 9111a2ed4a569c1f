"""Dahl (1968) friction model."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .._jit import jit
from ._common import sgn, sgn_right
from .base import COULOMB_STEADY_CHECKS, FrictionKernels, FrictionModel, Scales, expect, parameters

__all__ = ["Dahl", "dahl_force", "dahl_jacobian"]


@dataclass(frozen=True)
class Dahl(FrictionModel):
    """Dahl's solid friction model in bristle form (state ``z``)::

        r     = 1 - sigma0·z·sign(v)/F_c
        dz/dt = v·|r|^alpha·sign(r)          (alpha = 1: dz/dt = v - sigma0·|v|·z/F_c)
        F     = scale·sigma0·z

    Steady sliding: ``z = sign(v)·F_c/sigma0`` and ``F = scale·F_c·sign(v)``.
    Rate-independent pre-sliding hysteresis; no stiction, no Stribeck; drifts
    under a biased oscillating force.

    Parameters
    ----------
    F_c : float
        Coulomb level [N or N·m], > 0.
    sigma0 : float
        Rest stiffness [N/m or N·m/rad], > 0.
    alpha : float, optional
        Shape exponent [-], > 0, default 1.

    References
    ----------
    Dahl P.R., "A solid friction model", The Aerospace Corporation,
    TOR-0158(3107-18)-1, 1968.
    """

    F_c: float
    sigma0: float
    alpha: float = 1.0

    name: ClassVar[str] = "dahl"
    citation: ClassVar[str] = (
        "Dahl P.R., A solid friction model, The Aerospace Corporation, El Segundo, CA, "
        "Technical Report TOR-0158(3107-18)-1, 1968."
    )
    parameter_info, parameter_rules = parameters(
        F_c="> 0", sigma0=("force/displacement", "rest stiffness", "> 0"),
        alpha=("1", "shape exponent of the Dahl curve", "> 0"))
    phenomena = expect(stiction="no", stribeck="no", presliding="yes", lag="no",
                       varying_breakaway="no", no_drift="no (16.7 µm/cycle in drift test D1)")
    steady_checks: ClassVar[tuple[tuple[float, float], ...]] = COULOMB_STEADY_CHECKS
    default_parameter_set: ClassVar[str] = "dahl_d1"

    def static_capacity(self) -> float:
        """The Coulomb level ``F_c`` [N or N·m]."""
        return self.F_c

    def typical_scales(self) -> Scales:
        return Scales(self.F_c, 1e-3, (self.F_c / self.sigma0,))

    def _pack(self) -> list[float]:
        return [self.F_c, self.sigma0, self.alpha]

    def _state_spec(self) -> tuple[tuple[str, str], ...]:
        return (("z", "displacement"),)

    def _steady(self, v: np.ndarray) -> np.ndarray:
        return self.F_c * np.sign(v)

    def _sliding_state(self, v: float) -> list[float]:
        return [float(np.sign(v)) * self.F_c / self.sigma0]


@jit
def dahl_force(p, z, v, F_e, scale, dz):
    r = 1.0 - p[1] * z[0] * sgn(v) / p[0]
    if p[2] == 1.0:
        dz[0] = v * r
    else:
        dz[0] = v * abs(r) ** p[2] * sgn(r)
    return scale * p[1] * z[0]


@jit
def dahl_jacobian(p, z, v, F_e, scale, dz, Jz, dF):
    """Force and partials (see base).

    With ``s = sign(v)``: ``d dz/dz = -|v|·alpha·|r|^(alpha-1)·sigma0/F_c`` and
    ``d dz/dv = |r|^alpha·sign(r)`` (``r`` is flat in ``v`` away from 0). At ``v = 0`` the
    ``v -> 0+`` derivative (``r`` with ``s = +1``). For ``alpha < 1`` the slope in ``z`` is
    unbounded at ``r = 0`` (steady sliding); 0 is returned at that single point."""
    F = dahl_force(p, z, v, F_e, scale, dz)
    r = 1.0 - p[1] * z[0] * sgn_right(v) / p[0]
    alpha = p[2]
    if alpha == 1.0:
        slope, phi = 1.0, r
    else:
        slope = alpha * abs(r) ** (alpha - 1.0) if r != 0.0 else 0.0
        phi = abs(r) ** alpha * sgn(r)
    Jz[0, 0] = -abs(v) * slope * p[1] / p[0]
    Jz[0, 1] = phi
    dF[0], dF[1], dF[2], dF[3] = scale * p[1], 0.0, 0.0, p[1] * z[0]
    return F


#: the kernels Dahl provides (compiled code calls exactly these)
Dahl.kernels = FrictionKernels(force=dahl_force, jacobian=dahl_jacobian)
