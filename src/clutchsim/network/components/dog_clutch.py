"""A dog clutch: teeth that engage only below a relative speed and inside an angular window.

Two toothed rings, on flanges ``a`` and ``b``, ``teeth`` dogs each (pitch ``2π/teeth``).
The command is the sleeve's engagement command (0 open .. 1 pushed in; engaged from 0.5).
The slip is ``w = ω_b − ω_a`` and the relative angle ``φ`` (state ``phi_<name>`` [rad], from
``phi0``) follows ``dφ/dt = w`` while the dog is open.

* **Open** (``mode`` 1): no torque (the teeth do not touch; ``drag`` adds
  ``drag·tanh(w/1 rad/s)`` as on a clutch).
* **Engagement** (event ``engage``): while the command is at or above 0.5, the slip within
  the speed window ``|w| <= w_max`` and the teeth of one ring in front of the gaps of the
  other, ``cos(teeth·φ) >= cos(teeth·window/2)`` (``φ`` within ``±window/2`` of a multiple
  of the pitch), the dog engages: the plant locks it, as it locks a stuck clutch, with the
  angular momentum of what it joins conserved (the kinetic energy of a slip left at
  engagement is booked in ``W_sync``, as the gearbox's ideal synchroniser books its
  shifts).  The event function is ``max(0.5 − command, |w| − w_max, cos(teeth·window/2) −
  cos(teeth·φ))``: the dog never engages while any of the three is positive.
* **Clash** (event ``clash``): the command reaches 0.5 while ``|w| > w_max``, or ``|w|``
  rises past ``w_max`` with the command held: the teeth ratchet over each other and do not
  engage; the counter ``<name>.clashes`` counts these events.
* **Engaged** (``mode`` 0, locked): rigid teeth that hold any torque, until the command
  falls below 0.5 (event ``release``).

Engaged teeth are rigid: the backlash between the dogs and their contact stiffness are not
modelled.  The window must fit in a tooth pitch (``window <= 2π/teeth``).

References
----------
Naunheimer H., Bertsche B., Ryborz J., Novak W., *Automotive Transmissions*, 2nd ed.,
Springer, 2011, §8.3 (dog clutches and synchronisers: engagement only at synchronism, tooth
clash above it); MathWorks Simscape Driveline, Dog Clutch block (engagement below a relative
velocity threshold, teeth aligned).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..._jit import jit
from ...friction._common import NO_EVENT
from ...friction.base import (
    RESET_CHANGED,
    RESET_NONE,
    RESET_RELEASED,
    RESET_STUCK,
    Expectation,
    FrictionKernels,
    FrictionModel,
    Scales,
)
from ..component import Component
from ..spec import Param
from .friction import Clutch


@dataclass(frozen=True)
class DogLaw(FrictionModel):
    """The switching law of :class:`DogClutch` (states: mode 1 open / 0 engaged, the clash
    count, the relative angle).  Not a registry model: the element's own law."""

    w_max: float
    teeth: float
    window: float

    name: ClassVar[str] = "dog-clutch"
    code: ClassVar[int] = -4
    uses_stick_force: ClassVar[bool] = True
    citation: ClassVar[str] = ("Naunheimer et al., Automotive Transmissions, 2nd ed., "
                               "Springer 2011, §8.3.")
    parameter_info: ClassVar[dict[str, tuple[str, str]]] = {
        "w_max": ("velocity", "largest slip at which the teeth engage"),
        "teeth": ("1", "number of dogs on each ring"),
        "window": ("displacement", "angular window in which the teeth enter the gaps"),
    }
    phenomena: ClassVar[dict[str, Expectation]] = {}
    default_parameter_set: ClassVar[str] = ""
    event_spec: ClassVar[tuple[tuple[str, int], ...]] = (
        ("engage", -1), ("release", -1), ("clash", -1))
    steady_checks: ClassVar[tuple[tuple[float, float], ...]] = ()

    def static_capacity(self) -> float:
        """Engaged teeth hold any torque; 0 is what an open dog transmits."""
        return 0.0

    def typical_scales(self) -> Scales:
        return Scales(1.0, self.w_max, (1.0, 1.0, 2.0 * math.pi / self.teeth))

    def _check(self) -> None:
        self._require(self.w_max > 0.0, "w_max", "> 0")
        self._require(self.teeth >= 1.0, "teeth", ">= 1")
        self._require(0.0 < self.window <= 2.0 * math.pi / self.teeth, "window",
                      f"in (0, 2π/teeth = {2.0 * math.pi / self.teeth:g} rad]")

    def _pack(self) -> list[float]:
        return [self.w_max, self.teeth, math.cos(0.5 * self.teeth * self.window)]

    def _state_spec(self) -> tuple[tuple[str, str], ...]:
        return (("mode", "1"), ("clashes", "1"), ("phi", "displacement"))

    def _steady(self, v: np.ndarray) -> np.ndarray:
        return np.zeros_like(v)

    def _sliding_state(self, v: float) -> list[float]:
        return [1.0, 0.0, 0.0]


@jit
def dog_clutch_force(p, z, v, F_e, scale, dz):
    dz[0] = 0.0
    dz[1] = 0.0
    if z[0] == 0.0:         # engaged: rigid teeth, any torque
        dz[2] = 0.0
        return F_e
    dz[2] = v
    return 0.0


@jit
def dog_clutch_jacobian(p, z, v, F_e, scale, dz, Jz, dF):
    """Force and partials (see :mod:`clutchsim.friction.base`); mode and count are
    discrete; ``d(dφ/dt)/dw = 1`` while open."""
    F = dog_clutch_force(p, z, v, F_e, scale, dz)
    for i in range(3):
        for j in range(4):
            Jz[i, j] = 0.0
    for j in range(6):
        dF[j] = 0.0
    if z[0] == 0.0:
        dF[4] = 1.0
    else:
        Jz[2, 3] = 1.0
    return F


@jit
def dog_window(push, v, w_max, align):
    """The engagement event function of a dog: ``max(push, |v| − w_max, align)``, <= 0
    where the teeth may enter the gaps (``push`` <= 0: the sleeve is pushed in; ``|v| <=
    w_max``: the speed window; ``align`` <= 0: the angular window).  The synchroniser
    (:mod:`.synchronizer`) reads its blocker through it."""
    return max(max(push, abs(v) - w_max), align)


@jit
def dog_may_engage(push, v, w_max, align):
    """Does the dog engage at a located crossing of :func:`dog_window` (the windows checked
    again, to the event's tolerance)?  1.0 yes, 0.0 no (a number: the plant's C printer
    takes conditions as comparisons)."""
    return 1.0 if (push <= 0.0 and abs(v) <= w_max * (1.0 + 1e-9) and align <= 1e-9) else 0.0


@jit
def dog_clutch_events(p, z, v, F_e, scale, g):
    g[0], g[1], g[2] = NO_EVENT, NO_EVENT, NO_EVENT
    if z[0] == 0.0:
        g[1] = scale - 0.5
    else:
        g[0] = dog_window(0.5 - scale, v, p[0], p[2] - math.cos(p[1] * z[2]))
        g[2] = max(0.5 - scale, p[0] - abs(v))


@jit
def dog_clutch_reset(p, z, v, F_e, scale, k):
    if k == 0:          # engage: only in the window of speed and angle, while pushed in
        if z[0] != 0.0 and dog_may_engage(0.5 - scale, v, p[0],
                                          p[2] - math.cos(p[1] * z[2])) > 0.5:
            z[0] = 0.0
            return RESET_STUCK
        return RESET_NONE
    if k == 1:          # release: the sleeve is withdrawn
        if z[0] == 0.0 and scale < 0.5:
            z[0] = 1.0
            return RESET_RELEASED
        return RESET_NONE
    if k == 2 and z[0] != 0.0:      # clash: counted, the teeth stay apart
        z[1] = z[1] + 1.0
        return RESET_CHANGED
    return RESET_NONE


DogLaw.kernels = FrictionKernels(force=dog_clutch_force, jacobian=dog_clutch_jacobian,
                                 events=dog_clutch_events, reset=dog_clutch_reset)


class DogClutch(Clutch):
    """A dog clutch between flanges a and b (see the module docstring)."""

    kind = "dog_clutch"
    title = "dog clutch (engages below a slip and inside an angular window, counts clashes)"
    own_law = True
    lockable = True
    params = (
        Param("w_max", "rad/s", "largest slip |omega_b - omega_a| at which the teeth engage",
              low=0.0, strict=True, high=1e3),
        Param("teeth", "-", "number of dogs on each ring (pitch 2π/teeth)", low=1.0,
              high=200.0),
        Param("window", "rad", "angular window in which the teeth enter the gaps (at most a "
              "tooth pitch 2π/teeth; a pitch: any angle)", low=0.0, strict=True,
              high=2.0 * math.pi),
        Param("phi0", "rad", "initial relative angle phi_b - phi_a (0: teeth in front of "
              "the gaps)", default=0.0),
        Param("engaged0", "-", "1: the dog starts engaged (locked), 0 open", default=0.0,
              low=0.0, high=1.0),
        Param("drag", "N·m", "drag torque of the open dog, drag·tanh(w/1 rad/s)",
              default=0.0, low=0.0, high=1e6),
    )

    def __init__(self, name, command, **values):
        Component.__init__(self, name, **values)          # the values, checked
        if self.teeth != round(self.teeth):
            raise ValueError(f"{self.label}: teeth = {self.teeth:g} must be a whole number")
        pitch = 2.0 * math.pi / self.teeth
        if self.window > pitch * (1.0 + 1e-12):
            err = ValueError(f"{self.label}: window = {self.window:g} rad must be <= the tooth "
                             f"pitch 2π/teeth = {pitch:g} rad (teeth = {self.teeth:g}): a "
                             "window wider than a pitch would overlap the next tooth")
            err.key = "window"
            raise err
        if self.engaged0 not in (0.0, 1.0):
            raise ValueError(f"{self.label}: engaged0 = {self.engaged0:g} must be 0 or 1")
        law = DogLaw(w_max=self.w_max, teeth=self.teeth, window=self.window)
        super().__init__(name, law, command, **values)

    def with_values(self, **changes):
        Component.with_values(self, **changes)            # the changes, checked
        return type(self)(self.name, self.command, **{**self.values, **changes})

    def input_ranges(self):
        return {self.command: (-1.0, 1.0, "-", "its sleeve command (engaged from 0.5)")}

    def options(self):
        return ("dog",) + super().options()[1:]

    def pack(self):
        d = super().pack()
        d["capacity"] = 0.0
        return d

    def state_layout(self):
        return [("z0", f"{self.name}.mode", "-"), ("z1", f"{self.name}.clashes", "-"),
                ("z2", f"phi_{self.name}", "rad"), ("locked", f"{self.name}.locked", "-")]

    def initial_state(self, ctx):
        engaged = self.engaged0 == 1.0
        return [0.0 if engaged else 1.0, 0.0, self.phi0, 1.0 if engaged else 0.0]

    def _locked0(self, ctx) -> bool:
        return self.engaged0 == 1.0
