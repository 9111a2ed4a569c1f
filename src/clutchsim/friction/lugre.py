"""LuGre friction model (Canudas de Wit, Olsson, Åström, Lischinsky 1995)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .._jit import jit
from ._common import sgn_right, stribeck_level, stribeck_partials
from .base import STRIBECK_STEADY_CHECKS, FrictionKernels, FrictionModel, Scales, expect, parameters

__all__ = ["LuGre", "lugre_force", "lugre_jacobian"]

#: the rules of :class:`BristleModel`'s parameters (each model's :func:`parameters` adds its
#: own)
BRISTLE_RULES = {"F_c": "> 0", "F_s": ">= F_c", "v_s": "> 0", "sigma0": "> 0",
                 "sigma1": ">= 0", "sigma2": ">= 0"}


@dataclass(frozen=True)
class BristleModel(FrictionModel):
    """What LuGre and the elasto-plastic model share: the parameters ``F_c``, ``F_s``,
    ``v_s`` (the Stribeck level ``g(v)``, with the subclass's exponent ``delta``),
    ``sigma0``, ``sigma1``, ``sigma2``, the one state ``z`` (mean bristle deflection) and
    steady sliding ``z = sign(v)·g(v)/sigma0``, ``F = sign(v)·g(v) + sigma2·v``."""

    F_c: float
    F_s: float
    v_s: float
    sigma0: float
    sigma1: float
    sigma2: float

    def static_capacity(self) -> float:
        """The static level ``F_s`` [N or N·m]."""
        return self.F_s

    def typical_scales(self) -> Scales:
        return Scales(self.F_c, self.v_s, (self.F_c / self.sigma0,))

    def _state_spec(self) -> tuple[tuple[str, str], ...]:
        return (("z", "displacement"),)

    def _steady(self, v: np.ndarray) -> np.ndarray:
        g = self.F_c + (self.F_s - self.F_c) * np.exp(-(np.abs(v / self.v_s) ** self.delta))
        return np.sign(v) * g + self.sigma2 * v

    def _sliding_state(self, v: float) -> list[float]:
        g = self.F_c + (self.F_s - self.F_c) * np.exp(-(abs(v / self.v_s) ** self.delta))
        return [float(np.sign(v) * g / self.sigma0)]


@dataclass(frozen=True)
class LuGre(BristleModel):
    """LuGre bristle model (state ``z``, mean bristle deflection)::

        g(v)  = F_c + (F_s - F_c)·exp(-|v/v_s|^delta)
        dz/dt = v - sigma0·|v|·z/g(v)
        F     = scale·(sigma0·z + sigma1·dz/dt + sigma2·v)

    Steady sliding: ``z = sign(v)·g(v)/sigma0``, ``F = scale·(sign(v)·g(v) +
    sigma2·v)``. The state equation uses the nominal ``g`` so it is independent
    of ``scale``. If ``|z| <= F_s/sigma0`` initially it stays so.

    Parameters
    ----------
    F_c : float
        Coulomb level [N or N·m], > 0.
    F_s : float
        Static level [N or N·m], >= F_c.
    v_s : float
        Stribeck velocity [m/s or rad/s], > 0.
    sigma0 : float
        Bristle stiffness [N/m or N·m/rad], > 0.
    sigma1 : float
        Bristle damping [N·s/m or N·m·s/rad], >= 0.
    sigma2 : float
        Viscous coefficient [N·s/m or N·m·s/rad], >= 0.
    delta : float, optional
        Stribeck exponent [-], > 0, default 2.

    References
    ----------
    Canudas de Wit C., Olsson H., Åström K.J., Lischinsky P., "A new model
    for control of systems with friction", IEEE Trans. Automatic Control
    40(3):419-425, 1995, doi:10.1109/9.376053.
    """

    delta: float = 2.0

    name: ClassVar[str] = "lugre"
    citation: ClassVar[str] = (
        "Canudas de Wit C., Olsson H., Åström K.J., Lischinsky P., A new model for control of "
        "systems with friction, IEEE Transactions on Automatic Control 40(3):419-425, 1995, "
        "doi:10.1109/9.376053."
    )
    parameter_info, parameter_rules = parameters(**BRISTLE_RULES, delta="> 0")
    phenomena = expect(stiction="yes", stribeck="yes", presliding="yes", lag="yes",
                       varying_breakaway="yes", no_drift="no (6.64 µm/cycle in drift test D1)")
    steady_checks: ClassVar[tuple[tuple[float, float], ...]] = STRIBECK_STEADY_CHECKS
    default_parameter_set: ClassVar[str] = "lugre_canudas1995"

    def _pack(self) -> list[float]:
        return [self.F_c, self.F_s, self.v_s, self.sigma0, self.sigma1, self.sigma2, self.delta]


@jit
def lugre_force(p, z, v, F_e, scale, dz):
    g = stribeck_level(v, p[0], p[1], p[2], p[6])
    dz[0] = v - p[3] * abs(v) * z[0] / g
    return scale * (p[3] * z[0] + p[4] * dz[0] + p[5] * v)


@jit
def lugre_jacobian(p, z, v, F_e, scale, dz, Jz, dF):
    """Force and partials (see base)::

        d dz/dz = -sigma0·|v|/g,   d dz/dv = 1 - sigma0·z·sign(v)·(g - v·g')/g^2

    At ``v = 0`` (the kink of ``|v|``) the ``v -> 0+`` derivative (``sign = +1``)."""
    F = lugre_force(p, z, v, F_e, scale, dz)
    g, v_dg, _ = stribeck_partials(v, p[0], p[1], p[2], p[6])
    Jz[0, 0] = -p[3] * abs(v) / g
    Jz[0, 1] = 1.0 - p[3] * z[0] * sgn_right(v) * (g - v_dg) / (g * g)
    dF[0] = scale * (p[3] + p[4] * Jz[0, 0])
    dF[1] = scale * (p[4] * Jz[0, 1] + p[5])
    dF[2] = 0.0
    dF[3] = p[3] * z[0] + p[4] * dz[0] + p[5] * v
    return F


#: the kernels LuGre provides (compiled code calls exactly these)
LuGre.kernels = FrictionKernels(force=lugre_force, jacobian=lugre_jacobian)
