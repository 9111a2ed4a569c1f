"""Coulomb friction with stick/slip switching, naive form (seed eqs. 1-3)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .._jit import jit
from ._common import clip, clip_partials, sgn
from .base import (
    COULOMB_STEADY_CHECKS,
    RESET_NONE,
    FrictionKernels,
    Scales,
    StatelessModel,
    expect,
    parameters,
)

__all__ = [
    "CoulombNaive",
    "coulomb_naive_events",
    "coulomb_naive_force",
    "coulomb_naive_jacobian",
    "coulomb_naive_reset",
]


@dataclass(frozen=True)
class CoulombNaive(StatelessModel):
    """Two-phase Coulomb friction evaluated as a block diagram would.

    ``F = scale·F_c·sign(v)`` if ``v != 0``, else ``F = F_e`` clipped to
    ``±scale·F_s``. This is the seed's eqs. (1)-(3) (after MathWorks
    ``sldemo_clutch``) without any hybrid state: at lock-up the velocity
    never stays at exactly zero, the force flips sign each step and the
    solver chatters. The model declares one monitoring event ``g = v``
    (both directions, reset does nothing) so that the core can count the
    zero crossings and stop a chattering run with a clear message. Use
    ``coulomb-robust`` for a working stick/slip model.

    Parameters
    ----------
    F_c : float
        Coulomb (dynamic) friction level [N or N·m], >= 0.
    F_s : float
        Static friction level [N or N·m], >= F_c.

    References
    ----------
    Mykhailevych M.G., "Model of friction for dry friction clutch working
    process simulation", Avtomobil i elektronika. Suchasni tekhnolohii 18
    (2020), eqs. (1)-(3); The MathWorks, sldemo_clutch.
    """

    F_c: float
    F_s: float

    name: ClassVar[str] = "coulomb-naive"
    passive: ClassVar[bool] = True
    uses_stick_force: ClassVar[bool] = True
    jumps: ClassVar[bool] = True
    citation: ClassVar[str] = (
        "Mykhailevych M.G., Model of friction for dry friction clutch working process "
        "simulation, Avtomobil i elektronika. Suchasni tekhnolohii, no. 18, 2020, eqs. (1)-(3); "
        "The MathWorks, Building a Clutch Lock-Up Model (sldemo_clutch)."
    )
    parameter_info, parameter_rules = parameters(
        F_c=("force", "Coulomb (dynamic) friction level", ">= 0"),
        F_s=("force", "static friction level (largest stick force)", ">= F_c"))
    phenomena = expect(stiction="yes (in theory; chatters numerically at lock-up)", stribeck="no",
                       presliding="no", lag="no", varying_breakaway="no",
                       no_drift="yes (stuck means frozen) if the solver could stick")
    steady_checks: ClassVar[tuple[tuple[float, float], ...]] = COULOMB_STEADY_CHECKS
    default_parameter_set: ClassVar[str] = "coulomb"
    event_spec: ClassVar[tuple[tuple[str, int], ...]] = (("velocity_zero_crossing", 0),)

    def static_capacity(self) -> float:
        """The static level ``F_s`` [N or N·m]."""
        return self.F_s

    def typical_scales(self) -> Scales:
        #: (a chosen 1 mm/s: the model has no velocity parameter)
        return Scales(self.F_c, 1e-3, ())

    def _pack(self) -> list[float]:
        return [self.F_c, self.F_s]

    def _steady(self, v: np.ndarray) -> np.ndarray:
        return self.F_c * np.sign(v)


@jit
def coulomb_naive_force(p, z, v, F_e, scale, dz):
    if v != 0.0:
        return scale * p[0] * sgn(v)
    return clip(F_e, scale * p[1])


@jit
def coulomb_naive_jacobian(p, z, v, F_e, scale, dz, Jz, dF):
    """Force and partials (see base); both pieces are flat in ``v``."""
    F = coulomb_naive_force(p, z, v, F_e, scale, dz)
    if v != 0.0:
        dF[0], dF[1], dF[2] = 0.0, 0.0, p[0] * sgn(v)
    else:
        clip_partials(F_e, scale, p[1], dF, 0)
    return F


@jit
def coulomb_naive_events(p, z, v, F_e, scale, g):
    g[0] = v


@jit
def coulomb_naive_reset(p, z, v, F_e, scale, k):
    return RESET_NONE


#: the kernels CoulombNaive provides (compiled code calls exactly these)
CoulombNaive.kernels = FrictionKernels(force=coulomb_naive_force, jacobian=coulomb_naive_jacobian, events=coulomb_naive_events,
                                 reset=coulomb_naive_reset)
