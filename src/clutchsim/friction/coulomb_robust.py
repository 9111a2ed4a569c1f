"""Coulomb(-Stribeck) friction as a hybrid stick/slip state machine."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .._jit import jit
from ._common import NO_EVENT, clip, clip_partials, sgn, stribeck_level, stribeck_partials
from .base import (
    RESET_CHANGED,
    RESET_NONE,
    RESET_RELEASED,
    RESET_STUCK,
    FrictionKernels,
    FrictionModel,
    Scales,
    expect,
    parameters,
)

__all__ = [
    "CoulombRobust",
    "coulomb_robust_events",
    "coulomb_robust_force",
    "coulomb_robust_jacobian",
    "coulomb_robust_reset",
]


@dataclass(frozen=True)
class CoulombRobust(FrictionModel):
    """Hybrid stick/slip Coulomb friction (Modelica PartialFriction style).

    One state ``mode`` (a float holding -1 backward, 0 stuck, +1 forward; its
    derivative is 0, it only changes at events).

    * Slipping (``mode = ±1``)::

          F = scale·[s(v)·mode + sigma2·v],
          s(v) = F_c + (F_s - F_c)·exp(-|v/v_s|^delta)   if v_s > 0,
          s(v) = F_c                                       if v_s = 0.

      With ``v_s = 0`` (default) the sliding level is plain Coulomb ``F_c``
      and ``F_s`` acts as a peak (static) level only when stuck, like
      Modelica's ``peak`` factor ``F_s/F_c``.
    * Stuck (``mode = 0``): ``F = F_e`` (clipped to ``±scale·F_s``, which
      only matters in the instants before the break-away event is located
      and makes ``scale = 0`` a free element).

    Events (both falling, direction -1; a slot not applicable in the current
    mode returns the constant 1.0 so it cannot fire):

    0. ``stop``: while slipping ``g = mode·v``. At ``v = 0``: stick if
       ``|F_e| <= scale·F_s`` (reset returns 2), else continue in the
       direction of ``F_e`` (returns 1).
    1. ``breakaway``: while stuck ``g = scale·F_s - |F_e|``. When it falls
       below zero: ``mode = sign(F_e)`` (returns 3).

    ``initial_state()`` is stuck (``mode = 0``). If ``|F_e|`` already exceeds
    the capacity at the start, the break-away event fires at ``t = 0``.

    Parameters
    ----------
    F_c : float
        Coulomb friction level [N or N·m], >= 0.
    F_s : float
        Static (break-away) level [N or N·m], >= F_c.
    v_s : float, optional
        Stribeck velocity [m/s or rad/s], >= 0; 0 (default) disables the
        Stribeck term.
    delta : float, optional
        Stribeck exponent [-], > 0, default 2.
    sigma2 : float, optional
        Viscous coefficient [N·s/m or N·m·s/rad], >= 0, default 0.

    References
    ----------
    Olsson H., Åström K.J., Canudas de Wit C., Gäfvert M., Lischinsky P.,
    "Friction models and friction compensation", Eur. J. Control 4(3), 1998;
    Modelica Standard Library, Modelica.Mechanics.Rotational.Interfaces.PartialFriction.
    """

    F_c: float
    F_s: float
    v_s: float = 0.0
    delta: float = 2.0
    sigma2: float = 0.0

    name: ClassVar[str] = "coulomb-robust"
    passive: ClassVar[bool] = True
    lockable: ClassVar[bool] = True
    uses_stick_force: ClassVar[bool] = True
    citation: ClassVar[str] = (
        "Olsson H., Åström K.J., Canudas de Wit C., Gäfvert M., Lischinsky P., Friction models "
        "and friction compensation, European Journal of Control 4(3):176-195, 1998; Modelica "
        "Standard Library, Modelica.Mechanics.Rotational.Interfaces.PartialFriction."
    )
    parameter_info, parameter_rules = parameters(
        F_c=">= 0", F_s=("force", "static (break-away) friction level", ">= F_c"),
        v_s=("velocity", "Stribeck velocity (0 disables the Stribeck term)", ">= 0"), delta="> 0",
        sigma2=">= 0")
    phenomena = expect(stiction="yes", stribeck="depends: optional (static)", presliding="no",
                       lag="no", varying_breakaway="no", no_drift="yes (stuck means frozen)")
    #: F_ss(v) written out from the formula with the default parameter set
    steady_checks: ClassVar[tuple[tuple[float, float], ...]] = (
        (-0.02, -1.0),
        (0.0005, 1.0),
        (0.002, 1.0),
        (0.3, 1.0),
    )
    default_parameter_set: ClassVar[str] = "coulomb"
    event_spec: ClassVar[tuple[tuple[str, int], ...]] = (("stop", -1), ("breakaway", -1))

    def static_capacity(self) -> float:
        """The static level ``F_s`` [N or N·m]."""
        return self.F_s

    def typical_scales(self) -> Scales:
        return Scales(self.F_c, self.v_s if self.v_s > 0.0 else 1e-3, (1.0,))

    def _pack(self) -> list[float]:
        return [self.F_c, self.F_s, self.v_s, self.delta, self.sigma2]

    def _state_spec(self) -> tuple[tuple[str, str], ...]:
        return (("mode", "1"),)

    def _steady(self, v: np.ndarray) -> np.ndarray:
        level = np.full_like(v, self.F_c)
        if self.v_s > 0.0:
            level = self.F_c + (self.F_s - self.F_c) * np.exp(-(np.abs(v / self.v_s) ** self.delta))
        return level * np.sign(v) + self.sigma2 * v

    def _sliding_state(self, v: float) -> list[float]:
        return [float(np.sign(v))]


@jit
def coulomb_robust_force(p, z, v, F_e, scale, dz):
    dz[0] = 0.0
    mode = z[0]
    if mode == 0.0:
        return clip(F_e, scale * p[1])
    level = p[0]
    if p[2] > 0.0:
        level = stribeck_level(v, p[0], p[1], p[2], p[3])
    return scale * (level * sgn(mode) + p[4] * v)


@jit
def coulomb_robust_jacobian(p, z, v, F_e, scale, dz, Jz, dF):
    """Force and partials (see base). ``mode`` is discrete (it changes only at events):
    every derivative with respect to it is 0. Stuck: the clipped stick force; slipping: the
    sliding curve, whose Stribeck slope at exactly ``v = 0`` is the ``v -> 0+`` one."""
    F = coulomb_robust_force(p, z, v, F_e, scale, dz)
    Jz[0, 0], Jz[0, 1] = 0.0, 0.0
    dF[0] = 0.0
    mode = z[0]
    if mode == 0.0:
        clip_partials(F_e, scale, p[1], dF, 1)
        return F
    level, dlevel = p[0], 0.0
    if p[2] > 0.0:
        level, _, dlevel = stribeck_partials(v, p[0], p[1], p[2], p[3])
    dF[1] = scale * (dlevel * sgn(mode) + p[4])
    dF[2] = 0.0
    dF[3] = level * sgn(mode) + p[4] * v
    return F


#: the break-away function on its boundary (|F_e| equal to the capacity): positive, so that
#: leaving the boundary is a crossing
STUCK_MARGIN = 1e-300


@jit
def coulomb_robust_events(p, z, v, F_e, scale, g):
    mode = z[0]
    if mode == 0.0:
        g[0] = NO_EVENT
        # stuck while |F_e| <= capacity (MSL: it starts sliding only when the stick force
        # exceeds the capacity); on the boundary the function stays on its positive side,
        # so that a free element (capacity 0) that must carry no force (F_e = 0) still
        # breaks away the moment F_e leaves 0 (a crossing from exactly 0 is not one)
        g[1] = scale * p[1] - abs(F_e)
        if g[1] == 0.0:
            g[1] = STUCK_MARGIN
    else:
        g[0] = sgn(mode) * v
        g[1] = NO_EVENT


@jit
def coulomb_robust_reset(p, z, v, F_e, scale, k):
    if k == 0:
        # stop: stuck within the capacity, else sliding on with the stick force.  Never on
        # in the direction it stopped from: the slip came to zero because the stick force
        # did not exceed the friction that way (mode·F_e < the sliding level), so a stick
        # force that says otherwise jumped at this instant with a neighbour (a Karnopp
        # window, a naive law, a clipped stick force that depends on this element's own):
        # it locks, and the plant's lock, which solves the locked elements together, finds
        # the consistent torque and breaks it away if that is beyond the capacity (fuzzed
        # networks: a clutch slid on in mode -1 against a slip of +0.008 rad/s)
        if abs(F_e) <= scale * p[1] or sgn(F_e) == sgn(z[0]):
            z[0] = 0.0
            return RESET_STUCK
        z[0] = sgn(F_e)
        return RESET_CHANGED
    if k == 1:
        direction = sgn(F_e)
        if direction == 0.0:
            return RESET_NONE
        z[0] = direction
        return RESET_RELEASED
    return RESET_NONE


#: the kernels CoulombRobust provides (compiled code calls exactly these)
CoulombRobust.kernels = FrictionKernels(force=coulomb_robust_force, jacobian=coulomb_robust_jacobian, events=coulomb_robust_events,
                                 reset=coulomb_robust_reset)
