"""Generalized Maxwell-slip model (Al-Bender, Lampaert, Swevers 2005)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .._jit import jit
from ._common import sgn, stribeck_level, stribeck_partials
from .base import STRIBECK_STEADY_CHECKS, FrictionKernels, FrictionModel, Scales, expect, parameters

__all__ = ["GMS", "gms_force", "gms_jacobian"]


@dataclass(frozen=True)
class GMS(FrictionModel):
    """Generalized Maxwell-slip model with N elements (states ``z_1..z_N``).

    Element ``i`` is a spring of stiffness ``k_i`` (deflection ``z_i``) whose
    force is limited to ``alpha_i·s(v)``, with ``sum(alpha_i) = 1`` and the
    nominal Stribeck curve ``s(v) = F_c + (F_s - F_c)·exp(-|v/v_s|^delta)``::

        r_i   = |k_i·z_i|/(alpha_i·s(v))                 (load ratio of element i)
        slip_i = (C/k_i)·(alpha_i·sign(v) - k_i·z_i/s(v))
        dz_i/dt = v                                       if z_i·v <= 0 or r_i <= 1 - b
                = w·v + (1 - w)·slip_i, w = (1 - r_i)/b    if 1 - b < r_i < 1
                = slip_i                                  if r_i >= 1   (and z_i·v > 0)
        F = scale·( sum_i (k_i·z_i + sigma1·dz_i/dt) + sigma2·v )

    with ``b = stick_band`` (default 0.01).

    Derivation: in elementary-force form ``F_i = k_i·z_i`` the GMS slip law is
    ``dF_i/dt = sign(v)·C·(alpha_i - F_i/s(v))`` (attraction rate ``C``, N/s),
    equivalently ``dF_i/dt = C·(alpha_i·sign(v) - F_i/s(v))`` when ``F_i`` has
    the sign of ``v``; dividing by ``k_i`` gives the law above (the
    FrictionModels.jl form with states scaled by ``k_i``). Sticking elements
    follow the slip velocity. The switch is memoryless: an element slips while
    it is loaded in the direction of motion at (or beyond) its capacity, and
    unloading (``z_i·v <= 0``) is elastic. The slip law vanishes on the
    capacity boundary, so a sliding element rests on it (``dz_i = 0`` in
    steady sliding). A hard switch there would make the right-hand side
    discontinuous on the boundary (a Filippov sliding surface that stalls
    implicit solvers), so the last fraction ``stick_band`` of the capacity
    blends stick into slip linearly; the blend keeps the boundary an exact,
    attracting equilibrium and the right-hand side Lipschitz in ``z``. Steady sliding: ``k_i·z_i = alpha_i·s(v)·sign(v)``
    and ``F = scale·(s(v)·sign(v) + sigma2·v)``. States use the nominal ``s``,
    so they do not depend on ``scale``.

    Parameters
    ----------
    k : tuple of float
        Element stiffnesses [N/m or N·m/rad], each > 0.
    alpha : tuple of float
        Element weights [-], each > 0, summing to 1 (tolerance 1e-9).
    C : float
        Attraction rate [N/s or N·m/s], > 0.
    F_c, F_s, v_s : float
        Stribeck curve s(v): Coulomb level, static level [N or N·m], Stribeck
        velocity [m/s or rad/s].
    sigma1 : float
        Per-element damping [N·s/m or N·m·s/rad], >= 0 (may be 0).
    sigma2 : float
        Viscous coefficient [N·s/m or N·m·s/rad], >= 0.
    delta : float, optional
        Stribeck exponent [-], > 0, default 2.
    stick_band : float, optional
        Relative width of the stick-to-slip blend below capacity [-], in
        (0, 1), default 0.01 (numerical regularisation, not physics).

    References
    ----------
    Al-Bender F., Lampaert V., Swevers J., "The generalized Maxwell-slip
    model: a novel model for friction simulation and compensation", IEEE
    Trans. Automatic Control 50(11):1883-1887, 2005.
    """

    k: tuple[float, ...]
    alpha: tuple[float, ...]
    C: float
    F_c: float
    F_s: float
    v_s: float
    sigma1: float
    sigma2: float
    delta: float = 2.0
    stick_band: float = 0.01

    name: ClassVar[str] = "gms"
    citation: ClassVar[str] = (
        "Al-Bender F., Lampaert V., Swevers J., The generalized Maxwell-slip model: a novel "
        "model for friction simulation and compensation, IEEE Transactions on Automatic "
        "Control 50(11):1883-1887, 2005."
    )
    parameter_info, parameter_rules = parameters(
        k=("force/displacement", "element stiffnesses k_i > 0 (one per element, at least one)",
           ""),
        alpha=("1", "element weights alpha_i > 0, one per element, summing to 1", ""),
        C=("force/time", "attraction rate of slipping elements", "> 0"),
        F_c=("force", "Coulomb friction level of s(v)", "> 0"),
        F_s=("force", "static friction level of s(v)", ">= F_c"),
        v_s=("velocity", "Stribeck velocity of s(v)", "> 0"),
        sigma1=("force/velocity", "per-element damping", ">= 0"), sigma2=">= 0", delta="> 0",
        stick_band=("1", "relative width of the stick-to-slip blend (numerical)", "in (0, 1)"))
    phenomena = expect(stiction="yes", stribeck="yes", presliding="yes (with non-local memory)",
                       lag="yes", varying_breakaway="yes",
                       no_drift="yes in pre-sliding (literature, unverified)")
    steady_checks: ClassVar[tuple[tuple[float, float], ...]] = STRIBECK_STEADY_CHECKS
    default_parameter_set: ClassVar[str] = "gms_illustrative"

    def static_capacity(self) -> float:
        """The static level ``F_s`` [N or N·m]."""
        return self.F_s

    def typical_scales(self) -> Scales:
        return Scales(self.F_c, self.v_s, tuple(a * self.F_s / k for a, k in zip(self.alpha, self.k)))

    def _check(self) -> None:
        self._require(len(self.k) >= 1, "k", "a non-empty sequence")
        self._require(
            len(self.alpha) == len(self.k), "alpha", f"of the same length as k ({len(self.k)})"
        )
        self._require(all(x > 0.0 for x in self.k), "k", "> 0 (every element)")
        self._require(all(x > 0.0 for x in self.alpha), "alpha", "> 0 (every element)")
        total = sum(self.alpha)
        self._require(abs(total - 1.0) <= 1e-9, "alpha", f"summing to 1 (sum is {total:.12g})")

    def _pack(self) -> list[float]:
        head = [float(len(self.k)), self.C, self.F_c, self.F_s, self.v_s, self.delta]
        return head + [self.sigma1, self.sigma2, self.stick_band, *self.k, *self.alpha]

    def _state_spec(self) -> tuple[tuple[str, str], ...]:
        return tuple((f"z_{i + 1}", "displacement") for i in range(len(self.k)))

    def _steady(self, v: np.ndarray) -> np.ndarray:
        s = self.F_c + (self.F_s - self.F_c) * np.exp(-(np.abs(v / self.v_s) ** self.delta))
        return np.sign(v) * s + self.sigma2 * v

    def _sliding_state(self, v: float) -> list[float]:
        s = self.F_c + (self.F_s - self.F_c) * np.exp(-(abs(v / self.v_s) ** self.delta))
        return [float(np.sign(v) * a * s / k) for a, k in zip(self.alpha, self.k)]


@jit(inline="always")
def _gms_element(zi, v, k, a, C, s, ds, band):
    """Deflection rate ``dz_i/dt`` of one element and its partials d/dz_i and d/dv.

    ``s`` is the Stribeck level s(v) and ``ds`` its slope s'(v). Shared by the force and
    the Jacobian kernels (inlined: where the partials are not used, in ``gms_force``, the
    compiler drops them; its machine code is the same as without them). Each piece is the
    one the switch selects; the switch lines ``z_i·v = 0``, ``r_i = 1 - b`` and ``r_i = 1``
    are kinks.
    """
    d, d_z, d_v = v, 0.0, 1.0
    if zi * v > 0.0:
        r = k * abs(zi) / (a * s)
        if r > 1.0 - band:
            slip = (C / k) * (a * sgn(v) - k * zi / s)
            slip_z, slip_v = -C / s, C * zi * ds / (s * s)
            if r >= 1.0:
                d, d_z, d_v = slip, slip_z, slip_v
            else:
                w = (1.0 - r) / band
                d = w * v + (1.0 - w) * slip
                w_z, w_v = -k * sgn(zi) / (a * s * band), r * ds / (s * band)
                d_z = (1.0 - w) * slip_z + w_z * (v - slip)
                d_v = w + (1.0 - w) * slip_v + w_v * (v - slip)
    return d, d_z, d_v


@jit
def gms_force(p, z, v, F_e, scale, dz):
    n = int(p[0])
    C = p[1]
    s = stribeck_level(v, p[2], p[3], p[4], p[5])
    band = p[8]
    total = 0.0
    for i in range(n):
        k = p[9 + i]
        zi = z[i]
        d, _d_z, _d_v = _gms_element(zi, v, k, p[9 + n + i], C, s, 0.0, band)
        dz[i] = d
        total += k * zi + p[6] * d
    return scale * (total + p[7] * v)


@jit
def gms_jacobian(p, z, v, F_e, scale, dz, Jz, dF):
    """Force and partials (see base). The elements are independent: ``Jz`` is diagonal
    in the states. At ``v = 0`` every element sticks (``dz_i = v``)."""
    F = gms_force(p, z, v, F_e, scale, dz)
    n = int(p[0])
    s, _, ds = stribeck_partials(v, p[2], p[3], p[4], p[5])
    for i in range(n):                  # (a loop, not a slice: printable as C)
        for j in range(n + 1):
            Jz[i, j] = 0.0
    dF_dv = p[7]
    total = 0.0
    for i in range(n):
        d, d_z, d_v = _gms_element(z[i], v, p[9 + i], p[9 + n + i], p[1], s, ds, p[8])
        Jz[i, i] = d_z
        Jz[i, n] = d_v
        dF[i] = scale * (p[9 + i] + p[6] * d_z)
        dF_dv += p[6] * d_v
        total += p[9 + i] * z[i] + p[6] * d
    dF[n], dF[n + 1], dF[n + 2] = scale * dF_dv, 0.0, total + p[7] * v
    return F


#: the kernels GMS provides (compiled code calls exactly these)
GMS.kernels = FrictionKernels(force=gms_force, jacobian=gms_jacobian)
