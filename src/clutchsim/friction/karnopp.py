"""Karnopp (1985) friction: a velocity window treated as zero velocity."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .._jit import jit
from ._common import clip, clip_partials, sgn
from .base import FrictionKernels, Scales, StatelessModel, expect, parameters, steady_checks_at

__all__ = ["Karnopp", "karnopp_force", "karnopp_jacobian"]


@dataclass(frozen=True)
class Karnopp(StatelessModel):
    """Karnopp stick/slip friction without events.

    Inside the window ``|v| < DV`` the velocity is treated as zero and the
    friction balances the stick force::

        |v| <  DV:  F = clip(F_e, ±scale·F_s)
        |v| >= DV:  F = scale·(F_c·sign(v) + sigma2·v)

    No states, no events; results depend on ``DV`` (a numerical parameter).

    Parameters
    ----------
    F_c : float
        Coulomb level [N or N·m], >= 0.
    F_s : float
        Static level [N or N·m], >= F_c.
    DV : float
        Half-width of the zero-velocity window [m/s or rad/s], > 0.
    sigma2 : float, optional
        Viscous coefficient [N·s/m or N·m·s/rad], >= 0, default 0.

    References
    ----------
    Karnopp D., "Computer simulation of stick-slip friction in mechanical
    dynamic systems", ASME J. Dyn. Syst. Meas. Control 107(1):100-103, 1985.
    """

    F_c: float
    F_s: float
    DV: float
    sigma2: float = 0.0

    name: ClassVar[str] = "karnopp"
    uses_stick_force: ClassVar[bool] = True
    edge_jumps: ClassVar[bool] = True
    citation: ClassVar[str] = (
        "Karnopp D., Computer simulation of stick-slip friction in mechanical dynamic systems, "
        "ASME Journal of Dynamic Systems, Measurement, and Control 107(1):100-103, 1985."
    )
    parameter_info, parameter_rules = parameters(
        F_c=">= 0", F_s=">= F_c",
        DV=("velocity", "half-width of the velocity window treated as zero", "> 0"),
        sigma2=">= 0")
    phenomena = expect(stiction="yes", stribeck="no", presliding="no", lag="no",
                       varying_breakaway="no",
                       no_drift="yes (within the window the body is held)")
    #: F_ss(v) at STEADY_CHECK_SPEEDS written out from the formula with the default set
    steady_checks: ClassVar[tuple[tuple[float, float], ...]] = steady_checks_at(
        -1.008, 1.0002, 1.0008, 1.12)
    default_parameter_set: ClassVar[str] = "karnopp"

    def static_capacity(self) -> float:
        """The static level ``F_s`` [N or N·m]."""
        return self.F_s

    def typical_scales(self) -> Scales:
        return Scales(self.F_c, self.DV, ())

    def _pack(self) -> list[float]:
        return [self.F_c, self.F_s, self.DV, self.sigma2]

    def _steady(self, v: np.ndarray) -> np.ndarray:
        return self.F_c * np.sign(v) + self.sigma2 * v


@jit
def karnopp_force(p, z, v, F_e, scale, dz):
    if abs(v) < p[2]:
        return clip(F_e, scale * p[1])
    return scale * (p[0] * sgn(v) + p[3] * v)


@jit
def karnopp_jacobian(p, z, v, F_e, scale, dz, Jz, dF):
    """Force and partials (see base) of the piece ``karnopp_force`` evaluates (the window
    edge ``|v| = DV`` belongs to the sliding piece)."""
    F = karnopp_force(p, z, v, F_e, scale, dz)
    if abs(v) < p[2]:
        clip_partials(F_e, scale, p[1], dF, 0)
    else:
        dF[0], dF[1], dF[2] = scale * p[3], 0.0, p[0] * sgn(v) + p[3] * v
    return F


#: the kernels Karnopp provides (compiled code calls exactly these)
Karnopp.kernels = FrictionKernels(force=karnopp_force, jacobian=karnopp_jacobian)
