"""arctan-regularised Coulomb friction (Pennestrì et al. 2016)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .._jit import jit
from .base import FrictionKernels, expect, parameters
from .tanh import RegularisedCoulomb

__all__ = ["AtanFriction", "atan_force", "atan_jacobian"]


@dataclass(frozen=True)
class AtanFriction(RegularisedCoulomb):
    """Coulomb friction smoothed by the arctangent::

        F = scale·(F_c·(2/π)·atan(v/v_t) + sigma2·v)

    Reaches half the Coulomb level at ``v = v_t`` and approaches it only as ``1/v``
    (``tanh`` does exponentially), so its slope at zero slip, ``(2/π)·F_c/v_t``, is
    ``2/π`` of tanh's for the same ``v_t``.  No true stiction: under a constant force
    below ``F_c`` the body creeps.

    Parameters
    ----------
    F_c : float
        Coulomb level [N or N·m], >= 0.
    v_t : float
        Regularisation velocity [m/s or rad/s], > 0: the slip at which F = F_c/2.
    sigma2 : float, optional
        Viscous coefficient [N·s/m or N·m·s/rad], >= 0, default 0.

    References
    ----------
    Pennestrì E., Rossi V., Salvini P., Valentini P.P. (2016), Review and comparison of dry
    friction force models, Nonlinear Dynamics 83, 1785–1801 (the arctan regularisation of
    Coulomb's law).
    """

    name: ClassVar[str] = "atan"
    passive: ClassVar[bool] = True
    citation: ClassVar[str] = (
        "Pennestrì E., Rossi V., Salvini P., Valentini P.P., Review and comparison of dry "
        "friction force models, Nonlinear Dynamics 83, 1785–1801, 2016 (arctan-regularised "
        "Coulomb friction)."
    )
    parameter_info, parameter_rules = parameters(
        F_c=">= 0", v_t=("velocity", "arctan regularisation velocity (F = F_c/2 there)", "> 0"),
        sigma2=">= 0")
    phenomena = expect(stiction="no (creep)", stribeck="no", presliding="no", lag="no",
                       varying_breakaway="no", no_drift="no")
    #: atan(1/√3) = π/6, atan(1) = π/4, atan(√3) = π/3 with the default set (F_c = 1 N,
    #: v_t = 1e-4 m/s, sigma2 = 0.4 N·s/m)
    steady_checks: ClassVar[tuple[tuple[float, float], ...]] = (
        (1e-4 / math.sqrt(3.0), 1.0 / 3.0 + 0.4e-4 / math.sqrt(3.0)),
        (1e-4, 0.5 + 0.4e-4),
        (-1e-4 * math.sqrt(3.0), -2.0 / 3.0 - 0.4e-4 * math.sqrt(3.0)),
    )
    default_parameter_set: ClassVar[str] = "atan"

    def _steady(self, v: np.ndarray) -> np.ndarray:
        return self.F_c * (2.0 / np.pi) * np.arctan(v / self.v_t) + self.sigma2 * v


@jit
def atan_force(p, z, v, F_e, scale, dz):
    return scale * (p[0] * (2.0 / math.pi) * math.atan(v / p[1]) + p[2] * v)


@jit
def atan_jacobian(p, z, v, F_e, scale, dz, Jz, dF):
    """Force and partials (see base); smooth everywhere."""
    F = atan_force(p, z, v, F_e, scale, dz)
    x = v / p[1]
    dF[0] = scale * (p[0] * (2.0 / math.pi) / (p[1] * (1.0 + x * x)) + p[2])
    dF[1] = 0.0
    dF[2] = p[0] * (2.0 / math.pi) * math.atan(x) + p[2] * v
    return F


#: the kernels AtanFriction provides (compiled code calls exactly these)
AtanFriction.kernels = FrictionKernels(force=atan_force, jacobian=atan_jacobian)
