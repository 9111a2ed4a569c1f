"""A freewheel in parallel with a friction clutch (Modelica ``OneWayClutch``).

The slip ``w = ω_b − ω_a`` may only be positive.  While ``w > 0`` the element slides and
the clutch transmits ``scale·T_slide`` (``scale``: the command, 0 when it is <= 0, times
μ(θ)/μ_ref); when ``w`` reaches 0 it locks and then holds any torque in the blocking
direction (``τ <= 0``: flange a drives flange b) and up to ``scale·F_s`` in the other
(``F_s = max(peak, 1 + ε0)·T_slide``); beyond that it slides forward again.  With the
clutch open the freewheel releases once the stick torque exceeds ``ε0·T_slide`` (Modelica's
``tau0_max_low``, ``ε0 = 1e-4``).  One constraint torque covers both parts, which is why it
is one element.  The generated plant locks and frees it as it does a coulomb-robust clutch.

References
----------
Modelica Standard Library 4.x, ``Modelica.Mechanics.Rotational.Components.OneWayClutch``;
Otter M., Elmqvist H., Mattsson S.E., "Hybrid modeling in Modelica based on the
synchronous data flow principle", CACSD'99, 1999.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..._jit import jit
from ...friction._common import NO_EVENT
from ...friction.base import (
    RESET_NONE,
    RESET_RELEASED,
    RESET_STUCK,
    ElementLaw,
    FrictionKernels,
    Scales,
    parameters,
)
from ..spec import Param, check_value
from .friction import Clutch

#: release torque of the open freewheel, as a fraction of ``T_slide`` [-]
ONE_WAY_EPS0 = 1.0e-4


@dataclass(frozen=True)
class OneWayLaw(ElementLaw):
    """The switching law of :class:`OneWayClutch` (one state ``mode``: 1 sliding, 0 locked).

    Not a friction model of the registry: it is the element's own law and cannot be put on
    another element with ``--model``.
    """

    T_slide: float
    peak: float = 1.0

    name: ClassVar[str] = "one-way-clutch"
    code: ClassVar[int] = -2
    forward_only: ClassVar[bool] = True
    citation: ClassVar[str] = ("Modelica Standard Library 4.x, "
                               "Modelica.Mechanics.Rotational.Components.OneWayClutch.")
    parameter_info, parameter_rules = parameters(
        T_slide=("force", "sliding torque of the clutch at full command", ">= 0"),
        peak=("1", "static over sliding torque", ">= 1"))
    event_spec: ClassVar[tuple[tuple[str, int], ...]] = (("stop", -1), ("breakaway", -1))

    def static_capacity(self) -> float:
        """The largest forward torque the locked freewheel's clutch holds at full command
        (``peak·T_slide``) [N·m]; backwards the freewheel holds any torque."""
        return max(self.peak, 1.0 + ONE_WAY_EPS0) * self.T_slide

    def typical_scales(self) -> Scales:
        return Scales(self.T_slide, 1e-3, (1.0,))

    def _pack(self) -> list[float]:
        t = self.T_slide
        return [t, max(self.peak, 1.0 + ONE_WAY_EPS0) * t, ONE_WAY_EPS0 * t]

    def _state_spec(self) -> tuple[tuple[str, str], ...]:
        return (("mode", "1"),)

    def _steady(self, v: np.ndarray) -> np.ndarray:
        return np.where(v > 0.0, self.T_slide, 0.0)

    def _sliding_state(self, v: float) -> list[float]:
        return [1.0]


@jit(inline="always")
def _limit(p, scale):
    """Largest forward stick torque [N·m] of the locked element."""
    return max(scale * p[1], p[2])


@jit
def one_way_clutch_force(p, z, v, F_e, scale, dz):
    dz[0] = 0.0
    if z[0] == 0.0:
        return min(F_e, _limit(p, scale))
    return scale * p[0]


@jit
def one_way_clutch_jacobian(p, z, v, F_e, scale, dz, Jz, dF):
    """Force and partials (see :mod:`clutchsim.friction.base`); ``mode`` is discrete."""
    F = one_way_clutch_force(p, z, v, F_e, scale, dz)
    Jz[0, 0], Jz[0, 1] = 0.0, 0.0
    dF[0], dF[1], dF[2], dF[3] = 0.0, 0.0, 0.0, 0.0
    if z[0] == 0.0:
        if F_e < _limit(p, scale):
            dF[2] = 1.0
        elif scale * p[1] > p[2]:
            dF[3] = p[1]
    else:
        dF[3] = p[0]
    return F


@jit
def one_way_clutch_events(p, z, v, F_e, scale, g):
    if z[0] == 0.0:
        g[0] = NO_EVENT
        g[1] = _limit(p, scale) - F_e
    else:
        g[0] = v
        g[1] = NO_EVENT


@jit
def one_way_clutch_reset(p, z, v, F_e, scale, k):
    if k == 0:
        # stop: the freewheel blocks.  Its slip came to zero from forward because the stick
        # force did not exceed the clutch's torque, so a stick force beyond the limit here
        # jumped at this instant with a neighbour (as coulomb-robust's stop): it locks, and
        # the plant's lock breaks it away forward if the locked torque is beyond the limit
        z[0] = 0.0
        return RESET_STUCK
    if k == 1:          # break-away: slide forward
        z[0] = 1.0
        return RESET_RELEASED
    return RESET_NONE


OneWayLaw.kernels = FrictionKernels(force=one_way_clutch_force,
                                     jacobian=one_way_clutch_jacobian,
                                     events=one_way_clutch_events, reset=one_way_clutch_reset)


class OneWayClutch(Clutch):
    """Freewheel and friction clutch in parallel between flanges a and b (see the module
    docstring).  ``T_slide`` [N·m] is the clutch's sliding torque at full command
    (``μ·cgeo·fn_max``), ``peak`` [-] its static over sliding torque; ``command`` the
    clutch's normalised clamp force input."""

    kind = "one_way_clutch"
    title = "freewheel in parallel with a friction clutch"
    params = (Param("T_slide", "N·m", "sliding torque of the clutch at full command "
                    "(mu·cgeo·fn_max)", low=0.0, high=1e7),
              Param("peak", "-", "static over sliding torque of the clutch", default=1.0,
                    low=1.0, high=100.0),
              *(p for p in Clutch.params if p.name not in Clutch.fault_keys))
    lockable = True
    fault_keys = ()

    def __init__(self, name, command, heat=(), mu_temperature=None, locked0=None, **values):
        label = f"one way clutch {name!r}"
        spec = {p.name: p for p in self.params}
        if "T_slide" not in values:
            raise ValueError(f"{label}: parameter 'T_slide' [N·m] is required "
                             f"({spec['T_slide'].doc})")
        law = OneWayLaw(T_slide=check_value(label, spec["T_slide"], values["T_slide"]),
                        peak=check_value(label, spec["peak"], values.get("peak", 1.0)))
        super().__init__(name, law, command, mu_temperature=mu_temperature, heat=heat,
                         locked0=locked0, **values)

    def options(self):
        return ("one-way",) + super().options()[1:]

    def pack(self):
        d = super().pack()
        d["capacity"] = self.model.pack()[1]
        return d

    def initial_state(self, ctx):
        w = self._slip0(ctx)
        # speeds given through gear ratios carry round-off: a relative speed within it is 0
        scale = abs(ctx.speed(self.name, self.side_a)) + abs(ctx.speed(self.name, self.side_b))
        if abs(w) <= 1e-12 * (1.0 + scale):
            w = 0.0
        if w < 0.0:
            raise ValueError(f"{self.label}: initial relative speed omega_b - omega_a = {w:g} "
                             "rad/s is negative; the freewheel only allows >= 0")
        locked = bool(self.locked0) if self.locked0 is not None else w == 0.0
        return [0.0 if locked else 1.0, 1.0 if locked else 0.0]

    def _locked0(self, ctx) -> bool:
        return self.initial_state(ctx)[1] == 1.0
