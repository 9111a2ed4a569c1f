"""A synchroniser: a cone that brings two speeds together, a blocker ring, then a dog.

One element between flanges ``a`` (the idler gear) and ``b`` (the shaft with the sleeve),
slip ``w = ω_b − ω_a``, driven by the sleeve force ``F`` [N] (the command; negative values
read as 0).  It is the cone clutch of :mod:`.cone_clutch` and the dog of :mod:`.dog_clutch`
in one housing, with the blocker (indexing) ring between them:

* **Synchronising** (``mode`` ±1, ``engaged`` 0): the sleeve presses the cone with ``F``;
  the cone's friction torque ``T = μ·F·R_m/sin α`` (coulomb-robust: ``μ`` the sliding
  coefficient ``F_c``, ``μ_s = F_s`` the static one; its kernels are called, not copied)
  opposes the slip.  The blocker ring's chamfers hold the sleeve back while the cone
  carries a friction torque, i.e. while ``|w|`` is above the blocker's window ``w_sync``:
  the dog teeth cannot touch, whatever the force (no clash).
* **Engagement** (event ``engage``): once ``|w| <= w_sync`` and ``F >= F_block`` (the
  force that turns the blocker ring back and passes its chamfers, Simscape's detent peak
  force), the sleeve passes and the dog engages: the dog's event function and window test
  (:func:`.dog_clutch.dog_window`, :func:`.dog_clutch.dog_may_engage`) with the blocker's
  window as its speed window and no angular window (the blocker ring indexes the teeth).
  The plant locks the element with the angular momentum of what it joins conserved; the
  kinetic energy of the slip left (``J_eq·w²/2 <= J_eq·w_sync²/2``) is booked in
  ``W_sync``.  The time to synchronism from a slip ``Δω`` between two inertias is
  ``t = J_eq·(|Δω| − w_sync)/T``, ``J_eq = J_a·J_b/(J_a + J_b)``.
* **Engaged** (``mode`` 0, ``engaged`` 1, locked): rigid teeth that hold any torque while
  the sleeve force is positive (a shift actuator holds the gear in); when it falls to 0
  (below ``1e-9·F_block``) the sleeve is withdrawn (event ``release``) and the element
  slides again with no force.
* **Cone stuck** (``mode`` 0, ``engaged`` 0, locked): the slip reached zero with
  ``F < F_block`` (the sleeve waits at the blocker): the cone holds up to ``μ_s·F·R_m/sin α``
  and breaks away above it (event ``release``); a force rising past ``F_block`` engages
  the dog (event ``engage``).

The three events are ``stop`` (the cone's slip reaches zero: the dog engages there if the
force passes the blocker, else the cone sticks or slides on), ``release`` (the locked
element frees: sleeve withdrawn, or the cone breaking away) and ``engage``.  The blocker's
window and force are required: without them nothing keeps the dog from engaging above
synchronism.

**Double-sided** (one sleeve between two gears): two synchronisers on the sleeve's shaft
(flange ``b`` of both), one per gear, reading the same sleeve force with ``side`` +1 and
-1: a positive force presses the first side's cone (the second reads 0: open), a negative
one the second's, and no force is the neutral position.  The force's sign choosing the
side, the sleeve cannot be in both gears: reversing the force withdraws it from one side
(``release`` as the force passes 0) before it presses the other.

References
----------
Naunheimer H., Bertsche B., Ryborz J., Novak W., *Automotive Transmissions*, 2nd ed.,
Springer, 2011, §8.3.2 (locking synchroniser: the blocker ring holds the sleeve while the
cone's friction torque exceeds the indexing torque, i.e. until synchronism; synchronising
time ``t = J·Δω/T_cone``); Razzacki S.T., Hottenstein J.E., Synchronizer Design and
Development for Dual Clutch Transmission (DCT), SAE 2007-01-0114; MathWorks Simscape
Driveline, Synchronizer block (a cone clutch, a dog clutch and a detent whose peak force
the sleeve must exceed before the dog engages).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..._jit import jit
from ...core._borrow import local_empty
from ...friction import CoulombRobust
from ...friction._common import FREE_SCALE, NO_EVENT, sgn
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
from ...friction.coulomb_robust import (
    coulomb_robust_events,
    coulomb_robust_force,
    coulomb_robust_jacobian,
    coulomb_robust_reset,
)
from ..spec import Param
from .cone_clutch import ConeClutch
from .dog_clutch import dog_may_engage, dog_window

#: the sleeve force below which an engaged sleeve is withdrawn, over ``F_block``
RELEASE_FRACTION = 1e-9
#: the blocker window's tolerance at a located engagement, over ``w_sync``
LOCATE_TOL = 1e-6
#: the dog's angular window term: always aligned (the blocker ring indexes the teeth)
ALIGNED = -1.0


@dataclass(frozen=True)
class SyncLaw(ElementLaw):
    """The switching law of :class:`Synchronizer` (states: the cone's mode -1/0/+1 and
    ``engaged`` 0/1).  Packs the cone's coulomb-robust levels (read as ``μ``), then the
    blocker window and the scales at which the sleeve passes the blocker and is withdrawn
    (forces times ``R_m/sin α``: the scale the element hands its law is ``F·R_m/sin α``)."""

    w_sync: float
    block_scale: float
    F_c: float
    F_s: float
    v_s: float = 0.0
    delta: float = 2.0
    sigma2: float = 0.0

    name: ClassVar[str] = "synchronizer"
    code: ClassVar[int] = -6
    passive: ClassVar[bool] = True
    citation: ClassVar[str] = ("Naunheimer et al., Automotive Transmissions, 2nd ed., "
                               "Springer 2011, §8.3.2.")
    # the cone's parameters as coulomb-robust declares them
    parameter_info, parameter_rules = parameters(
        w_sync=("velocity", "blocker window: largest slip at which the sleeve passes", "> 0"),
        block_scale=("force", "scale at which the sleeve passes the blocker", "> 0"),
        **{p: (*CoulombRobust.parameter_info[p], rule)
           for p, rule in CoulombRobust.parameter_rules.items()})
    event_spec: ClassVar[tuple[tuple[str, int], ...]] = (
        ("stop", -1), ("release", -1), ("engage", -1))

    @property
    def cone(self) -> CoulombRobust:
        """The cone's law (its levels read as ``μ``)."""
        return CoulombRobust(F_c=self.F_c, F_s=self.F_s, v_s=self.v_s, delta=self.delta,
                             sigma2=self.sigma2)

    def static_capacity(self) -> float:
        """The cone's static coefficient ``μ_s`` (the engaged dog holds any torque)."""
        return self.F_s

    def typical_scales(self) -> Scales:
        return Scales(self.F_c, self.w_sync, (1.0, 1.0))

    def _pack(self) -> list[float]:
        return [*self.cone.pack(), self.w_sync, self.block_scale,
                RELEASE_FRACTION * self.block_scale]

    def _state_spec(self) -> tuple[tuple[str, str], ...]:
        return (("mode", "1"), ("engaged", "1"))

    def _steady(self, v: np.ndarray) -> np.ndarray:
        return self.cone.steady_state_force(v)

    def _sliding_state(self, v: float) -> list[float]:
        return [float(np.sign(v)), 0.0]


@jit
def synchronizer_force(p, z, v, F_e, scale, dz):
    dz[1] = 0.0
    if z[1] != 0.0:         # the dog is in: rigid teeth, any torque
        dz[0] = 0.0
        return F_e
    return coulomb_robust_force(p, z[0:1], v, F_e, scale, dz[0:1])


@jit
def synchronizer_jacobian(p, z, v, F_e, scale, dz, Jz, dF):
    """Force and partials (see :mod:`clutchsim.friction.base`): both states are discrete;
    the engaged dog passes the stick force through, the cone's partials are its
    coulomb-robust kernel's."""
    for i in range(2):
        for j in range(3):
            Jz[i, j] = 0.0
    for j in range(5):
        dF[j] = 0.0
    if z[1] != 0.0:
        dF[3] = 1.0
        return synchronizer_force(p, z, v, F_e, scale, dz)
    Jc = local_empty((1, 2))
    dFc = local_empty(4)
    dz[1] = 0.0
    F = coulomb_robust_jacobian(p, z[0:1], v, F_e, scale, dz[0:1], Jc, dFc)
    dF[2], dF[3], dF[4] = dFc[1], dFc[2], dFc[3]
    return F


@jit
def synchronizer_events(p, z, v, F_e, scale, g):
    if z[1] != 0.0:         # engaged: only the sleeve's withdrawal
        g[0], g[2] = NO_EVENT, NO_EVENT
        g[1] = scale - p[7]
        return
    coulomb_robust_events(p, z[0:1], v, F_e, scale, g[0:2])
    if z[0] != 0.0 and scale <= FREE_SCALE:
        # no sleeve force: the cone turns free and its mode follows nothing (its slip may
        # pass zero any number of times: a stop each time would be chatter, a lock a
        # wrong one); when the sleeve pushes it, a mode against the slip is a crossing
        # here, and the reset turns the mode to the slip (the grip)
        g[0] = NO_EVENT
    # the blocker: the dog's window with w_sync as its speed window, pushed from F_block;
    # while the cone slides in direction mode, mode·w falls through w_sync (|w| has a
    # kink at zero: a step that carries the slip through zero sees |w| − w_sync positive
    # at both its ends and would pass the window over); a mode against the slip (a free
    # cone's, until the grip) reads the window through |w|
    if z[0] != 0.0 and z[0] * v >= 0.0:
        g[2] = max(p[6] - scale, z[0] * v - p[5])
    else:
        g[2] = dog_window(p[6] - scale, v, p[5], ALIGNED)


@jit
def synchronizer_reset(p, z, v, F_e, scale, k):
    if z[1] != 0.0:
        if k == 1 and scale < p[7]:     # the sleeve is withdrawn
            z[1] = 0.0
            z[0] = sgn(F_e) if F_e != 0.0 else (sgn(v) if v != 0.0 else 1.0)
            return RESET_RELEASED
        return RESET_NONE
    if k == 2:
        # the crossing of the blocker's window, located to the event tolerance: the dog
        # goes in (the window checked again, to a millionth of it)
        if dog_window(p[6] - scale, v, p[5], ALIGNED) <= LOCATE_TOL * p[5]:
            z[0] = 0.0
            z[1] = 1.0
            return RESET_STUCK
        return RESET_NONE
    if k == 0 and z[0] * v < 0.0 and abs(v) > p[5]:
        # the grip: the sleeve pushed a free cone whose mode is not its slip's (a stop is
        # located at zero slip, far inside the blocker's window): the cone takes the
        # direction of its slip
        z[0] = sgn(v)
        return RESET_CHANGED
    if k == 0 and dog_may_engage(p[6] - scale, v, p[5], ALIGNED) > 0.5:
        z[0] = 0.0          # the cone stops inside the window, the force past the blocker
        z[1] = 1.0
        return RESET_STUCK
    return coulomb_robust_reset(p, z[0:1], v, F_e, scale, k)


SyncLaw.kernels = FrictionKernels(force=synchronizer_force, jacobian=synchronizer_jacobian,
                                  events=synchronizer_events, reset=synchronizer_reset)


class Synchronizer(ConeClutch):
    """A single-sided synchroniser between flanges a and b (see the module docstring)."""

    kind = "synchronizer"
    title = ("synchroniser (cone μ·F·R_m/sin α until the blocker's window, then the dog "
             "engages)")
    lockable = True
    params = (*ConeClutch.params,
              Param("w_sync", "rad/s", "blocker window: the largest slip |omega_b - omega_a| "
                    "at which the blocker ring lets the sleeve through to the dog teeth",
                    low=0.0, strict=True, high=1e3),
              Param("F_block", "N", "blocker force: the sleeve force that passes the "
                    "blocker ring once synchronised (the dog engages from it)", low=0.0,
                    strict=True, high=1e6),
              Param("engaged0", "-", "1: the dog starts engaged (locked), 0 open",
                    default=0.0, low=0.0, high=1.0),
              Param("side", "-", "its side of a double-sided synchroniser: +1 pressed by a "
                    "positive sleeve force, -1 by a negative one (a single-sided one: +1)",
                    default=1.0, low=-1.0, high=1.0))

    def __init__(self, name, model, command, heat=(), **values):
        if not isinstance(model, CoulombRobust):
            err = ValueError(f"synchronizer {name!r}: friction model "
                             f"{getattr(model, 'name', model)!r} must be coulomb-robust: the "
                             "cone must hold the synchronised speeds until the dog engages "
                             "(give its mu as F_c, F_s)")
            err.key = "friction"
            raise err
        self.cone_model = model
        # the cone's checks (geometry, mu) first, with the cone's own law
        super().__init__(name, model, command, heat=heat, **values)
        if self.engaged0 not in (0.0, 1.0):
            raise ValueError(f"{self.label}: engaged0 = {self.engaged0:g} must be 0 or 1")
        if self.side not in (-1.0, 1.0):
            err = ValueError(f"{self.label}: side = {self.side:g} must be +1 or -1 (the sign "
                             "of the sleeve force that presses this side's cone)")
            err.key = "side"
            raise err
        self.model = SyncLaw(w_sync=self.w_sync, block_scale=self.F_block * self.wedge,
                             F_c=model.F_c, F_s=model.F_s, v_s=model.v_s,
                             delta=model.delta, sigma2=model.sigma2)

    def with_values(self, **changes):
        ConeClutch.with_values(self, **changes)             # the changes, checked
        return type(self)(self.name, self.cone_model, self.command,
                          heat=self.heat, **{**self.values, **changes})

    def options(self):
        return ("synchronizer", self.side) + super().options()[1:]

    def _command(self, e) -> str:
        """The force on this side's cone: the sleeve force times ``side`` (the other
        side's force, of the other sign, reads as 0 here)."""
        u = e.u(self.command)
        return u if self.side > 0.0 else f"(-{u})"

    def _command_slope(self, e) -> str:
        return "1.0" if self.side > 0.0 else "-1.0"

    def state_layout(self):
        return [("z0", f"{self.name}.mode", "-"), ("z1", f"{self.name}.engaged", "-"),
                ("locked", f"{self.name}.locked", "-")]

    def _free0(self, ctx) -> bool:
        """No sleeve force on this side at the start (an idle gear's synchroniser)."""
        u = ctx.input0.get(self.command)
        return u is not None and self.side * u <= 0.0

    def _locked0(self, ctx) -> bool:
        return self.engaged0 == 1.0 or (self._slip0(ctx) == 0.0 and not self._free0(ctx))

    def initial_state(self, ctx):
        if self.engaged0 == 1.0:
            return [0.0, 1.0, 1.0]
        w = self._slip0(ctx)
        if w == 0.0 and self._free0(ctx):
            # free at zero slip: not stuck (a free cone holds nothing; several stuck in
            # parallel at rest would share a stick torque of round-off when the car moves)
            # and its mode the grip sets when the sleeve pushes it
            return [1.0, 0.0, 0.0]
        return [float(np.sign(w)), 0.0, 1.0 if w == 0.0 else 0.0]
