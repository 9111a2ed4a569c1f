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

Engaged teeth are rigid by default.  With a contact stiffness ``c_contact`` > 0 they have
a free play ``backlash`` (the gap ``[−backlash/2, backlash/2]`` around the centre of the
tooth space they entered) and a contact damping ``d_contact``: the engagement does not lock
the element, the slip carries the teeth across the gap, and the flanks touch through the
lash law of :mod:`.backlash` (``T = c·(s ∓ backlash/2) + d·w`` in contact, the damping
limited so that the contact never pulls), at the offset ``s = (φ + pitch/2) mod pitch − pitch/2``
from the centre of the gap.  Their torque is ``T_teeth_<name>``, ``contact_<name>`` the
flank in contact (±1, 0 in the gap); the spring's energy is in ``E_spring``, the damping's
work in ``W_damping``.  The window must fit in a tooth pitch (``window <= 2π/teeth``).

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
    ElementLaw,
    FrictionKernels,
    Scales,
    parameters,
)
from ..component import Component
from ..spec import Param
from .backlash import lash_law
from .friction import Clutch


@dataclass(frozen=True)
class DogLaw(ElementLaw):
    """The switching law of :class:`DogClutch` (states: mode 1 open / 0 engaged, the clash
    count, the relative angle).  Not a registry model: the element's own law."""

    w_max: float
    teeth: float
    window: float
    elastic: float = 0.0

    name: ClassVar[str] = "dog-clutch"
    code: ClassVar[int] = -4
    citation: ClassVar[str] = ("Naunheimer et al., Automotive Transmissions, 2nd ed., "
                               "Springer 2011, §8.3.")
    parameter_info, parameter_rules = parameters(
        w_max=("velocity", "largest slip at which the teeth engage", "> 0"),
        teeth=("1", "number of dogs on each ring", ">= 1"),
        window=("displacement", "angular window in which the teeth enter the gaps (<= 2π/teeth)",
                ""),
        elastic=("1", "1: engaged teeth with backlash and contact stiffness, 0 rigid", ""))
    event_spec: ClassVar[tuple[tuple[str, int], ...]] = (
        ("engage", -1), ("release", -1), ("clash", -1))

    def static_capacity(self) -> float:
        """Engaged teeth hold any torque; 0 is what an open dog transmits."""
        return 0.0

    def typical_scales(self) -> Scales:
        return Scales(1.0, self.w_max, (1.0, 1.0, 2.0 * math.pi / self.teeth))

    def _check(self) -> None:
        self._require(0.0 < self.window <= 2.0 * math.pi / self.teeth, "window",
                      f"in (0, 2π/teeth = {2.0 * math.pi / self.teeth:g} rad]")

    def _pack(self) -> list[float]:
        return [self.w_max, self.teeth, math.cos(0.5 * self.teeth * self.window),
                self.elastic]

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
    if z[0] == 0.0 and p[3] == 0.0:     # engaged: rigid teeth, any torque
        dz[2] = 0.0
        return F_e
    dz[2] = v       # open, or elastic teeth (their torque is the element's lash law)
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
    if z[0] == 0.0 and p[3] == 0.0:
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
            z[0] = 0.0     # rigid teeth lock; elastic ones enter the gaps with the slip
            return RESET_CHANGED if p[3] > 0.0 else RESET_STUCK
        return RESET_NONE
    if k == 1:          # release: the sleeve is withdrawn
        if z[0] == 0.0 and scale < 0.5:
            z[0] = 1.0
            return RESET_CHANGED if p[3] > 0.0 else RESET_RELEASED
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
        Param("c_contact", "N·m/rad", "contact stiffness of the engaged teeth (0: rigid "
              "teeth, locked when engaged)", default=0.0, low=0.0, high=1e9),
        Param("d_contact", "N·m·s/rad", "contact damping of the engaged teeth (with "
              "c_contact)", default=0.0, low=0.0, high=1e7),
        Param("backlash", "rad", "free play of the engaged teeth, the gap "
              "[-backlash/2, backlash/2] (with c_contact; less than a tooth pitch)",
              default=0.0, low=0.0, high=2.0 * math.pi),
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
        for key in ("backlash", "d_contact"):
            if self.values[key] > 0.0 and self.c_contact == 0.0:
                err = ValueError(f"{self.label}: {key} = {self.values[key]:g} needs a contact "
                                 "stiffness c_contact > 0 N·m/rad (rigid teeth, c_contact = "
                                 "0, have neither free play nor damping)")
                err.key = key
                raise err
        if self.backlash >= pitch:
            err = ValueError(f"{self.label}: backlash = {self.backlash:g} rad must be < the "
                             f"tooth pitch 2π/teeth = {pitch:g} rad (teeth = "
                             f"{self.teeth:g}): the gap lies between two teeth")
            err.key = "backlash"
            raise err
        law = DogLaw(w_max=self.w_max, teeth=self.teeth, window=self.window,
                     elastic=1.0 if self.elastic else 0.0)
        super().__init__(name, law, command, **values)

    def with_values(self, **changes):
        Component.with_values(self, **changes)            # the changes, checked
        return type(self)(self.name, self.command, **{**self.values, **changes})

    @property
    def elastic(self) -> bool:
        """Do the engaged teeth have a contact stiffness (and a free play)?"""
        return self.values["c_contact"] > 0.0

    @property
    def lockable(self) -> bool:
        """Rigid teeth lock when engaged; elastic ones touch through their lash law."""
        return not self.elastic

    def input_ranges(self):
        return {self.command: (-1.0, 1.0, "-", "its sleeve command (engaged from 0.5)")}

    def options(self):
        return ("dog", self.elastic) + super().options()[1:]

    def pack(self):
        d = super().pack()
        d["capacity"] = 0.0
        d["pitch"] = 2.0 * math.pi / self.teeth
        return d

    def state_layout(self):
        out = [("z0", f"{self.name}.mode", "-"), ("z1", f"{self.name}.clashes", "-"),
               ("z2", f"phi_{self.name}", "rad")]
        return out if self.elastic else [*out, ("locked", f"{self.name}.locked", "-")]

    def initial_state(self, ctx):
        engaged = self.engaged0 == 1.0
        z = [0.0 if engaged else 1.0, 0.0, self.phi0]
        return z if self.elastic else [*z, 1.0 if engaged else 0.0]

    def _locked0(self, ctx) -> bool:
        return self.engaged0 == 1.0 and not self.elastic

    def emit(self, e):
        super().emit(e)
        if self.elastic:
            self.emit_teeth(e)

    def emit_teeth(self, e) -> None:
        """The engaged elastic teeth: the lash law at the offset from the centre of the
        tooth gap, ``+T`` on a and ``−T`` on b (``φ = φ_b − φ_a``), 0 while open."""
        phi, pitch = e.x("z2"), e.par("pitch")
        w = e.let("wr", f"{e.w('b')} - {e.w('a')}")
        eng = e.let("eng", f"{e.x('z0')} == 0.0")
        s = e.let("s", f"({phi} + 0.5 * {pitch}) % {pitch} - 0.5 * {pitch}")
        tau, tc, kc, kp, kw, sg, hb, _plain = lash_law(
            e, s, w, e.par("backlash"), e.par("c_contact"), e.par("d_contact"))
        tg, tcg, kcg, kpg, kwg = (e.let(n, f"{x} if {eng} else 0.0") for n, x in (
            ("tg", tau), ("tcg", tc), ("kcg", kc), ("kpg", kp), ("kwg", kw)))
        e.torque_pair("a", "b", tg, ((e.kx("z2"), kpg, False), (e.kw("b"), kwg, False),
                                     (e.kw("a"), kwg, True)))
        # damping power (τ − τ_c)·w: everything the contact spring does not store
        e.power("damp", f"({tg} - {tcg}) * {w}")
        e.dpower("damp", e.kx("z2"), f"({kpg} - {kcg}) * {w}")
        dpw = e.let("dpw", f"{tg} - {tcg} + {kwg} * {w}")
        e.dpower("damp", e.kw("b"), dpw)
        e.dpower("damp", e.kw("a"), f"-{dpw}")
        e.spring_energy(f"(0.5 * {tcg} * {tcg} / {e.par('c_contact')})")
        e.output(f"T_teeth_{self.name}", "N·m", tg)
        e.output(f"contact_{self.name}", "-", f"{sg} if {eng} else 0.0")
        # the flanks: the torque's slope jumps there (while open: on the gap's side)
        for side, edge, open_ in (("+", f"{s} - {hb}", "-1.0"), ("-", f"{s} + {hb}", "1.0")):
            e.event(f"{self.name}: flank {side}backlash/2", 0, f"{edge} if {eng} else {open_}",
                    "continue")
