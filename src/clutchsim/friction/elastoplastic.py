"""Elasto-plastic friction model (Dupont, Hayward, Armstrong, Altpeter 2002)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

from .._jit import jit
from ._common import sgn, sgn_right, stribeck_level, stribeck_partials
from .base import STRIBECK_STEADY_CHECKS, FrictionKernels, expect, parameters
from .lugre import BRISTLE_RULES, BristleModel

__all__ = ["ElastoPlastic", "elastoplastic_force", "elastoplastic_jacobian"]


@dataclass(frozen=True)
class ElastoPlastic(BristleModel):
    """Single-state elasto-plastic model (LuGre with a true elastic zone)::

        g(v)   = F_c + (F_s - F_c)·exp(-|v/v_s|^delta),   z_max(v) = g(v)/sigma0
        dz/dt  = v·(1 - alpha(z, v)·z/z_ss(v)) = v - alpha·sigma0·|v|·z/g(v)
        F      = scale·(sigma0·z + sigma1·dz/dt + sigma2·v)

        alpha = 0                                        if sign(v) != sign(z)
              = 0                                        if |z| <= z_ba
              = (1 + sin(pi·(|z| - (z_max + z_ba)/2)/(z_max - z_ba)))/2
                                                         if z_ba < |z| < z_max
              = 1                                        if |z| >= z_max

    The sine uses ``|z|`` and unloading (``sign(v) != sign(z)``) is purely
    elastic. Requires ``0 < z_ba < F_c/sigma0`` so that ``z_ba < z_max(v)``.
    No drift while ``|z| <= z_ba``.

    Parameters
    ----------
    F_c, F_s, v_s, sigma0, sigma1, sigma2, delta
        As in :class:`~clutchsim.friction.LuGre`.
    z_ba : float
        Break-away displacement [m or rad], ``0 < z_ba < F_c/sigma0``.

    References
    ----------
    Dupont P., Hayward V., Armstrong B., Altpeter F., "Single state
    elastoplastic friction models", IEEE Trans. Automatic Control
    47(5):787-792, 2002, doi:10.1109/TAC.2002.1000274.
    """

    z_ba: float
    delta: float = 2.0

    name: ClassVar[str] = "elastoplastic"
    citation: ClassVar[str] = (
        "Dupont P., Hayward V., Armstrong B., Altpeter F., Single state elastoplastic friction "
        "models, IEEE Transactions on Automatic Control 47(5):787-792, 2002, "
        "doi:10.1109/TAC.2002.1000274."
    )
    parameter_info, parameter_rules = parameters(
        **BRISTLE_RULES,
        z_ba=("displacement", "break-away displacement (end of the elastic zone)", "> 0"),
        delta="> 0")
    phenomena = expect(stiction="yes", stribeck="yes", presliding="yes (true elastic zone)",
                       lag="yes", varying_breakaway="yes",
                       no_drift="yes while |F| < sigma0·z_ba (0 in drift test D1 with "
                                "z_ba = 0.95 F_c/sigma0)")
    steady_checks: ClassVar[tuple[tuple[float, float], ...]] = STRIBECK_STEADY_CHECKS
    default_parameter_set: ClassVar[str] = "elastoplastic_dupont2002"

    def _check(self) -> None:
        limit = self.F_c / self.sigma0
        self._require(self.z_ba < limit, "z_ba", f"< F_c/sigma0 = {limit:g} m")

    def _pack(self) -> list[float]:
        return [
            self.F_c, self.F_s, self.v_s, self.sigma0, self.sigma1, self.sigma2, self.delta,
            self.z_ba,
        ]  # fmt: skip


@jit
def elastoplastic_alpha(z, s, z_ba, z_max):
    """Elasto-plastic blending factor alpha(z, v) in [0, 1]; ``s = sign(v)``."""
    if s != sgn(z):
        return 0.0
    a = abs(z)
    if a <= z_ba:
        return 0.0
    if a >= z_max:
        return 1.0
    return 0.5 * math.sin(math.pi * (a - 0.5 * (z_max + z_ba)) / (z_max - z_ba)) + 0.5


@jit
def elastoplastic_force(p, z, v, F_e, scale, dz):
    g = stribeck_level(v, p[0], p[1], p[2], p[6])
    alpha = elastoplastic_alpha(z[0], sgn(v), p[7], g / p[3])
    dz[0] = v - alpha * p[3] * abs(v) * z[0] / g
    return scale * (p[3] * z[0] + p[4] * dz[0] + p[5] * v)


@jit
def elastoplastic_alpha_partials(z, s, z_ba, z_max):
    """alpha of :func:`elastoplastic_alpha` and its partials d/dz and d/dz_max."""
    alpha = elastoplastic_alpha(z, s, z_ba, z_max)
    a = abs(z)
    if s != sgn(z) or a <= z_ba or a >= z_max:
        return alpha, 0.0, 0.0
    width = z_max - z_ba
    u = (a - 0.5 * (z_max + z_ba)) / width          # the sine's argument over pi
    c = 0.5 * math.pi * math.cos(math.pi * u) / width
    return alpha, c * sgn(z), -c * (0.5 + u)


@jit
def elastoplastic_jacobian(p, z, v, F_e, scale, dz, Jz, dF):
    """Force and partials (see base). With ``Q = sigma0·|v|·z/g`` (``dz = v - alpha·Q``)
    and ``z_max = g/sigma0``::

        d dz/dz = -(d alpha/dz)·Q - alpha·sigma0·|v|/g
        d dz/dv = 1 - (d alpha/dz_max)·z·sign(v)·v·g'/g - alpha·sigma0·z·sign(v)·(g - v·g')/g^2

    The edges of the blend (``|z| = z_ba``, ``|z| = z_max``) and ``sign(v) = sign(z)`` are
    kinks; there the piece :func:`elastoplastic_alpha` selects. At ``v = 0`` the ``v -> 0+``
    derivative: ``alpha`` is taken with ``sign(v) = +1`` (``Q`` vanishes there, so ``dz``
    itself does not depend on that choice)."""
    F = elastoplastic_force(p, z, v, F_e, scale, dz)
    g, v_dg, _ = stribeck_partials(v, p[0], p[1], p[2], p[6])
    s = sgn_right(v)
    zj = z[0]
    alpha, da_dz, da_dzmax = elastoplastic_alpha_partials(zj, s, p[7], g / p[3])
    q = p[3] * abs(v) * zj / g
    Jz[0, 0] = -da_dz * q - alpha * p[3] * abs(v) / g
    Jz[0, 1] = (1.0 - da_dzmax * zj * s * v_dg / g
                - alpha * p[3] * zj * s * (g - v_dg) / (g * g))
    dF[0] = scale * (p[3] + p[4] * Jz[0, 0])
    dF[1] = scale * (p[4] * Jz[0, 1] + p[5])
    dF[2] = 0.0
    dF[3] = p[3] * zj + p[4] * dz[0] + p[5] * v
    return F


#: the kernels ElastoPlastic provides (compiled code calls exactly these)
ElastoPlastic.kernels = FrictionKernels(force=elastoplastic_force, jacobian=elastoplastic_jacobian)
