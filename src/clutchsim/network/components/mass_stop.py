"""A sliding mass with Stribeck friction to the housing and hard stops (Modelica
``Translational.Components.MassWithStopAndFriction``).

The mass ``m`` slides with speed ``v`` and centre position ``s`` (state ``s_<name>`` [m],
``ds/dt = v``) between the stops: its centre stays in ``[smin + L/2, smax − L/2]``.
Friction to the housing (Modelica's characteristic)::

    F = F_prop·v + sign·(F_Coulomb + F_Stribeck·exp(−fexp·|v|))    sliding (sign = mode)

At ``v = 0`` it sticks while the force that would keep it at rest, ``F_e``, stays inside
the break-away limit ``peak·(F_Coulomb + F_Stribeck)`` (Modelica hard-codes
``peak = 1.001``), else it slides on in the direction of ``F_e``.  When the mass reaches a
stop its position is set to the stop and its velocity to 0 (the plant locks it, as it
locks a stuck clutch: the kinetic energy it loses is booked in ``W_sync``); there it holds
any force that pushes it into the stop, and it leaves the stop only when the force pulls
it away by more than the break-away limit.  The element is one friction element with its
own law (:class:`StopLaw`, not a registry model): its states are the mode (−1, 0, +1), the
stop it rests at (−1 lower, 0 none, +1 upper) and the position (frozen while stuck); its events (located) are
the velocity zero, the break-away and the two stops.

References
----------
Modelica Standard Library 4.x, ``Modelica.Mechanics.Translational.Components.
MassWithStopAndFriction`` and ``Modelica.Mechanics.Translational.Examples.Friction``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..._jit import jit
from ...friction._common import NO_EVENT, sgn, sgn_right
from ...friction.base import (
    RESET_CHANGED,
    RESET_NONE,
    RESET_RELEASED,
    RESET_STUCK,
    ElementLaw,
    FrictionKernels,
    Scales,
    parameters,
)
from ..component import Component
from ..spec import Param
from .friction import Brake


@dataclass(frozen=True)
class StopLaw(ElementLaw):
    """The switching law of :class:`MassWithStopAndFriction` (translational units).

    ``s_low``/``s_high`` are the centre positions at the stops (``smin + L/2``,
    ``smax − L/2``).  Not a registry model: the element's own law."""

    F_prop: float
    F_Coulomb: float
    F_Stribeck: float
    fexp: float
    s_low: float
    s_high: float
    peak: float = 1.001

    name: ClassVar[str] = "mass-with-stop"
    code: ClassVar[int] = -3
    citation: ClassVar[str] = ("Modelica Standard Library 4.x, Modelica.Mechanics."
                               "Translational.Components.MassWithStopAndFriction.")
    parameter_info, parameter_rules = parameters(
        F_prop=("force/velocity", "velocity-proportional friction", ">= 0"),
        F_Coulomb=("force", "Coulomb friction", ">= 0"),
        F_Stribeck=("force", "Stribeck friction at v = 0", ">= 0"),
        fexp=("1", "exponential decay of the Stribeck term [s/m]", ">= 0"),
        s_low=("displacement", "centre position at the lower stop", ""),
        s_high=("displacement", "centre position at the upper stop", "> s_low"),
        peak=("1", "break-away over sliding force at v = 0", ">= 1"))
    event_spec: ClassVar[tuple[tuple[str, int], ...]] = (
        ("stop", -1), ("breakaway", -1), ("upper stop", -1), ("lower stop", -1))

    def static_capacity(self) -> float:
        """The largest force the stuck mass holds away from its stops (``peak·(F_Coulomb
        + F_Stribeck)``) [N]; at a stop it holds any push into it."""
        return self.peak * (self.F_Coulomb + self.F_Stribeck)

    def typical_scales(self) -> Scales:
        return Scales(self.F_Coulomb + self.F_Stribeck, 1e-3, (1.0, 1.0, self.s_high - self.s_low))

    def _pack(self) -> list[float]:
        return [self.F_prop, self.F_Coulomb, self.F_Stribeck, self.fexp, self.s_low,
                self.s_high, self.peak * (self.F_Coulomb + self.F_Stribeck)]

    def _state_spec(self) -> tuple[tuple[str, str], ...]:
        return (("mode", "1"), ("stop", "1"), ("s", "displacement"))

    def _steady(self, v: np.ndarray) -> np.ndarray:
        return self.F_prop * v + np.sign(v) * (self.F_Coulomb + self.F_Stribeck
                                               * np.exp(-self.fexp * np.abs(v)))

    def _sliding_state(self, v: float) -> list[float]:
        return [float(np.sign(v)), 0.0, 0.0]


@jit
def mass_stop_force(p, z, v, F_e, scale, dz):
    dz[0] = 0.0
    dz[1] = 0.0
    dz[2] = 0.0 if z[0] == 0.0 else v      # stuck: at rest (v is 0 up to round-off)
    lim = scale * p[6]
    if z[0] == 0.0:
        if z[1] > 0.0:              # at the upper stop: it holds any push into it
            return max(F_e, -lim)
        if z[1] < 0.0:
            return min(F_e, lim)
        return min(max(F_e, -lim), lim)
    return scale * (p[0] * v + sgn(z[0]) * (p[1] + p[2] * math.exp(-p[3] * abs(v))))


@jit
def mass_stop_jacobian(p, z, v, F_e, scale, dz, Jz, dF):
    """Force and partials (see :mod:`clutchsim.friction.base`); mode and stop are
    discrete, ``d(ds/dt)/dv = 1`` while sliding (0 stuck: the position is frozen); at
    exactly ``v = 0`` the ``v -> 0+`` slope."""
    F = mass_stop_force(p, z, v, F_e, scale, dz)
    for i in range(3):
        for j in range(4):
            Jz[i, j] = 0.0
    Jz[2, 3] = 0.0 if z[0] == 0.0 else 1.0
    for j in range(6):
        dF[j] = 0.0
    if z[0] == 0.0:
        lim = scale * p[6]
        if F_e > lim and z[1] <= 0.0:
            dF[5] = p[6]
        elif F_e < -lim and z[1] >= 0.0:
            dF[5] = -p[6]
        else:
            dF[4] = 1.0
        return F
    ex = math.exp(-p[3] * abs(v))
    dF[3] = scale * (p[0] - sgn(z[0]) * p[2] * p[3] * ex * sgn_right(v))
    dF[5] = p[0] * v + sgn(z[0]) * (p[1] + p[2] * ex)
    return F


@jit
def mass_stop_events(p, z, v, F_e, scale, g):
    lim = scale * p[6]
    g[0], g[1], g[2], g[3] = NO_EVENT, NO_EVENT, NO_EVENT, NO_EVENT
    if z[0] == 0.0:
        if z[1] > 0.0:
            g[1] = lim + F_e
        elif z[1] < 0.0:
            g[1] = lim - F_e
        else:
            g[1] = lim - abs(F_e)
    else:
        g[0] = sgn(z[0]) * v
        if z[0] > 0.0:
            g[2] = p[5] - z[2]
        else:
            g[3] = z[2] - p[4]


@jit
def mass_stop_reset(p, z, v, F_e, scale, k):
    if k == 0:          # v = 0 while sliding: stick, or slide on the way F_e pushes
        if abs(F_e) <= scale * p[6]:
            z[0] = 0.0
            return RESET_STUCK
        z[0] = sgn(F_e)
        return RESET_CHANGED
    if k == 1:          # break-away (away from a stop it rests at)
        direction = sgn(F_e)
        if direction == 0.0 or direction == z[1]:
            return RESET_NONE
        z[0] = direction
        z[1] = 0.0
        return RESET_RELEASED
    if k == 2 or k == 3:    # a stop: position to the stop, velocity to 0 (the lock)
        z[2] = p[5] if k == 2 else p[4]
        z[1] = 1.0 if k == 2 else -1.0
        z[0] = 0.0
        return RESET_STUCK
    return RESET_NONE


StopLaw.kernels = FrictionKernels(force=mass_stop_force, jacobian=mass_stop_jacobian,
                                  events=mass_stop_events, reset=mass_stop_reset)


class MassWithStopAndFriction(Brake):
    """A sliding mass with friction to the housing and hard stops (see the module
    docstring).  Flanges ``a``, ``b`` (both the mass) and ``support`` (the housing;
    grounded when unconnected)."""

    kind = "mass_with_stop_and_friction"
    title = "sliding mass with Stribeck friction and hard stops (Modelica MassWithStopAndFriction)"
    domain = "translational"
    flanges = ("a", "b", "support")
    optional_flanges = ("a", "b")
    joined = (("a", "b"),)
    grounded = ("support",)
    side_a = "support"
    side_b = "a"
    commanded = False
    #: its position is its own state (no extra position state with ``angles``)
    own_position = True
    params = (
        Param("m", "kg", "mass", low=0.0, strict=True),
        Param("L", "m", "length of the mass (its centre stops L/2 before a stop)",
              default=0.0, low=0.0),
        Param("smin", "m", "position of the lower stop (the mass's lower end stops there)"),
        Param("smax", "m", "position of the upper stop (the mass's upper end stops there)"),
        Param("s0", "m", "initial position of the centre", default=0.0),
        Param("v0", "m/s", "initial velocity", default=0.0),
        Param("F_prop", "N·s/m", "velocity-proportional friction", default=1.0, low=0.0),
        Param("F_Coulomb", "N", "Coulomb friction", default=5.0, low=0.0),
        Param("F_Stribeck", "N", "Stribeck friction at v = 0", default=10.0, low=0.0),
        Param("fexp", "s/m", "exponential decay of the Stribeck term", default=2.0, low=0.0),
        Param("peak", "-", "break-away over sliding force at v = 0 (Modelica: 1.001)",
              default=1.001, low=1.0),
    )

    lockable = True

    def __init__(self, name, locked0=None, **values):
        Component.__init__(self, name, **values)     # the values, checked
        lo, hi = self.smin + self.L / 2.0, self.smax - self.L / 2.0
        if not hi > lo:
            raise ValueError(f"{self.label}: the stops leave the mass no room: smax - smin = "
                             f"{self.smax - self.smin:g} m must be > L = {self.L:g} m")
        if not lo <= self.s0 <= hi:
            raise ValueError(f"{self.label}: s0 = {self.s0:g} m must be between the stops: "
                             f"in [smin + L/2, smax - L/2] = [{lo:g}, {hi:g}] m")
        if (self.s0 == hi and self.v0 > 0.0) or (self.s0 == lo and self.v0 < 0.0):
            raise ValueError(f"{self.label}: v0 = {self.v0:g} m/s moves the mass into the "
                             f"stop it starts at (s0 = {self.s0:g} m)")
        law = StopLaw(F_prop=self.F_prop, F_Coulomb=self.F_Coulomb,
                      F_Stribeck=self.F_Stribeck, fexp=self.fexp, s_low=lo, s_high=hi,
                      peak=self.peak)
        super().__init__(name, law, None, locked0=locked0, **values)

    def with_values(self, **changes):
        vals = {**self.values, **changes}
        return type(self)(self.name, locked0=self.locked0, **vals)

    def pack(self):
        # the equations read the law's packed values only (its friction, the stops'
        # centre positions, the break-away limit); the mass is an inertia, s0 and v0
        # initial values
        return {"model": self.model.pack(), "capacity": self.model.pack()[6]}

    def inertias(self):
        return {"a": self.m}

    def initial_speeds(self):
        return {"a": self.v0}

    def state_layout(self):
        return [("z0", f"{self.name}.mode", "-"), ("z1", f"{self.name}.stop", "-"),
                ("z2", f"s_{self.name}", "m"), ("locked", f"{self.name}.locked", "-")]

    def initial_state(self, ctx):
        v = self._slip0(ctx)
        lo, hi = self.model.s_low, self.model.s_high
        at = 1.0 if self.s0 == hi else (-1.0 if self.s0 == lo else 0.0)
        locked = bool(self.locked0) if self.locked0 is not None else v == 0.0
        return [0.0 if locked else float(np.sign(v)), at, self.s0, 1.0 if locked else 0.0]

    def _locked0(self, ctx) -> bool:
        return self.initial_state(ctx)[3] == 1.0
