"""Simscape / ModelingToolkitStandardLibrary Rotational Friction curve."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .._jit import jit
from .base import (
    FrictionKernels,
    Scales,
    StatelessModel,
    expect,
    parameters,
    steady_checks_at,
)

__all__ = ["RotationalFriction", "rotational_friction_force", "rotational_friction_jacobian"]

_SQRT_2E = math.sqrt(2.0 * math.e)


@dataclass(frozen=True)
class RotationalFriction(StatelessModel):
    """Smooth Stribeck + Coulomb + viscous curve of Simscape/MTK::

        F = scale·( sqrt(2e)·(F_brk - F_c)·exp(-(v/v_St)^2)·v/v_St
                    + F_c·tanh(v/v_Coul) + f·v ),
        v_St = v_brk·sqrt(2),   v_Coul = v_brk/10.

    Names map to Simscape/MTK as ``F_brk`` = tau_brk, ``F_c`` = tau_c,
    ``v_brk`` = w_brk, ``f`` = f (rotational: N·m, rad/s).

    Peak: the Stribeck term has its maximum ``F_brk - F_c`` exactly at
    ``v = v_brk`` (``d/dx[x·exp(-x^2)] = 0`` at ``x = 1/sqrt(2)``). So exactly
    ``F(v_brk) = F_brk + f·v_brk - F_c·(1 - tanh 10)``; the last term is
    ``~4.1e-9·F_c``. The true maximum lies slightly above ``v_brk`` because the
    tanh and viscous terms still rise there; ``F_brk + f·v_brk`` is the peak to
    about 1e-8 relative for the MTK test values.

    Parameters
    ----------
    F_brk : float
        Break-away friction [N or N·m], >= F_c.
    F_c : float
        Coulomb friction [N or N·m], >= 0.
    v_brk : float
        Break-away velocity [m/s or rad/s], > 0.
    f : float
        Viscous coefficient [N·s/m or N·m·s/rad], >= 0.

    References
    ----------
    The MathWorks, Simscape Rotational Friction block documentation;
    SciML ModelingToolkitStandardLibrary.jl, Mechanical.Rotational.RotationalFriction.
    """

    F_brk: float
    F_c: float
    v_brk: float
    f: float = 0.0

    name: ClassVar[str] = "rotational-friction"
    passive: ClassVar[bool] = True
    citation: ClassVar[str] = (
        "The MathWorks, Simscape Rotational Friction block (documentation); "
        "SciML ModelingToolkitStandardLibrary.jl, Mechanical.Rotational.RotationalFriction."
    )
    parameter_info, parameter_rules = parameters(
        F_brk=("force", "break-away friction (tau_brk)", ">= F_c"),
        F_c=("force", "Coulomb friction (tau_c)", ">= 0"),
        v_brk=("velocity", "break-away velocity (w_brk)", "> 0"),
        f=("force/velocity", "viscous friction coefficient", ">= 0"))
    phenomena = expect(stiction="no (creep)", stribeck="yes", presliding="no", lag="no",
                       varying_breakaway="no", no_drift="no")
    #: F_ss(v) at STEADY_CHECK_SPEEDS written out from the formula with the default set
    steady_checks: ClassVar[tuple[tuple[float, float], ...]] = steady_checks_at(
        -22.533136258569197, 1.7215163886576725, 6.668611802551407, 20.000476467573876)
    default_parameter_set: ClassVar[str] = "rotational_friction"

    def static_capacity(self) -> float:
        """The Coulomb level ``F_c`` [N or N·m]."""
        return self.F_c

    def typical_scales(self) -> Scales:
        return Scales(self.F_brk, self.v_brk / 10.0, ())

    def _pack(self) -> list[float]:
        return [self.F_brk, self.F_c, self.v_brk * math.sqrt(2.0), self.v_brk / 10.0, self.f]

    def _steady(self, v: np.ndarray) -> np.ndarray:
        v_st = self.v_brk * math.sqrt(2.0)
        v_coul = self.v_brk / 10.0
        x = v / v_st
        return (
            _SQRT_2E * (self.F_brk - self.F_c) * np.exp(-(x**2)) * x
            + self.F_c * np.tanh(v / v_coul)
            + self.f * v
        )


@jit
def rotational_friction_force(p, z, v, F_e, scale, dz):
    x = v / p[2]
    stribeck = _SQRT_2E * (p[0] - p[1]) * math.exp(-x * x) * x
    return scale * (stribeck + p[1] * math.tanh(v / p[3]) + p[4] * v)


@jit
def rotational_friction_jacobian(p, z, v, F_e, scale, dz, Jz, dF):
    """Force and partials (see base); smooth everywhere."""
    F = rotational_friction_force(p, z, v, F_e, scale, dz)
    x = v / p[2]
    bump = _SQRT_2E * (p[0] - p[1]) * math.exp(-x * x)
    th = math.tanh(v / p[3])
    dF[0] = scale * (bump * (1.0 - 2.0 * x * x) / p[2] + p[1] * (1.0 - th * th) / p[3] + p[4])
    dF[1] = 0.0
    dF[2] = bump * x + p[1] * th + p[4] * v
    return F


#: the kernels RotationalFriction provides (compiled code calls exactly these)
RotationalFriction.kernels = FrictionKernels(force=rotational_friction_force, jacobian=rotational_friction_jacobian)
