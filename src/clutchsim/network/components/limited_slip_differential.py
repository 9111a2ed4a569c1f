"""A limited-slip differential: an open differential with a preloaded, torque-sensing
clutch pack (the Salisbury type).

The gears are the open differential's (:mod:`.differential`): flanges ``input`` (the
pinion), ``left`` and ``right`` (the side shafts), the rigid relation
``2·ω_input/ratio = ω_left + ω_right``.  Between the case and each side gear sits a clutch
pack of ``n_faces`` friction faces at the mean radius ``R_m``; both packs are pressed by
the same axial force

    F = F_preload + T_case·tan(φ)/r_ramp,    T_case = ratio·|T_input|

the preload of the Belleville springs plus the force of the cross-shaft ramps (ramp angle
``φ`` from the plane normal to the axis, at the radius ``r_ramp``), which push the pressure
rings apart in proportion to the torque the case carries (drive and coast alike: one ramp
angle).  Each pack slips at half the difference of the side speeds, so the two packs act
as one clutch between the side shafts, of torque ``T_p = μ·n_faces·R_m·F`` opposing the
slip ``w = ω_right − ω_left``: the slower side receives ``T_case/2 + T_p``, the faster
``T_case/2 − T_p``, and the packs dissipate ``T_p·|w|``.  The torque bias ratio in slip is

    TBR = (T_case/2 + T_p)/(T_case/2 − T_p)

and with no preload ``(1 + 2k)/(1 − 2k)``, ``k = μ·n_faces·R_m·tan(φ)/r_ramp`` (a ``k`` of
1/2 or more locks the differential under any torque).  Below the preload's capacity the
differential turns as one (the packs stick: located ``stop`` and ``breakaway`` events, the
library's ``coulomb-robust`` law with ``μ`` sliding and ``μ_s`` static).

**The transmitted torque** is the command: the signal of the torque into the ``input``
flange [N·m], e.g. an input torque source's signal or the torque of the propshaft's
compliance.  In a rigid network that torque is an algebraic quantity (the differential's
constraint torque, which depends on the packs' own torque through the accelerations when
the side inertias differ): reading it from a signal computed from the states keeps the
plant explicit (no algebraic loop through the constraint solve) and is exact where the
input flange carries no inertia of its own, as a pinion fed by a shaft: the torque of the
shaft is then the pinion's.

Outputs: the clutch pack's (``T_<name>`` the pack torque on ``left``, ``w_slip_<name>``,
``capacity_<name>`` = ``μ_s·n_faces·R_m·F``, ``P_<name>``) and ``F_clamp_<name>`` [N].

References
----------
Milliken W.F., Milliken D.L., *Race Car Vehicle Dynamics*, SAE 1995 (limited-slip
differentials: the torque bias ratio ``(T_case/2 + T_f)/(T_case/2 − T_f)``, the ramp's
axial force ``T·tan(φ)/r``); MathWorks Simscape Driveline, Limited Slip Differential block (clutch
packs with a preload and a torque-sensing ramp); Genta G., Morello L., *The Automotive
Chassis*, vol. 1, Springer, 2009, §12 (limited-slip differentials).
"""

from __future__ import annotations

import math

from ...friction.coulomb_robust import CoulombRobust
from ..component import Component
from ..spec import Param
from .differential import OpenDifferential
from .friction import Clutch


class LimitedSlipDifferential(Clutch):
    """An open differential with a preloaded, ramp-loaded clutch pack between its side
    shafts (see the module docstring)."""

    kind = "limited_slip_differential"
    title = "limited-slip differential (preloaded clutch packs, ramp force from the torque)"
    own_law = True
    flanges = ("input", "left", "right")
    side_a = "left"
    side_b = "right"
    params = (
        *OpenDifferential.params,         # ratio: the gears are the open differential's
        Param("mu", "-", "sliding friction coefficient of the plates", low=0.0, strict=True,
              high=2.0),
        Param("mu_s", "-", "static friction coefficient of the plates (>= mu; 0: mu)",
              default=0.0, low=0.0, high=2.0),
        Param("n_faces", "-", "friction faces of each of the two clutch packs", low=1.0,
              high=100.0),
        Param("R_m", "m", "mean radius of the friction faces", low=0.0, strict=True,
              high=1.0),
        Param("F_preload", "N", "axial preload of the packs (Belleville springs)",
              default=0.0, low=0.0, high=1e6),
        Param("ramp_angle", "°", "angle of the cross-shaft ramps from the plane normal to "
              "the axis, in (0, 90) (0 < φ: a larger φ, a larger ramp force)", low=0.0,
              strict=True, high=90.0),
        Param("r_ramp", "m", "radius at which the cross shaft bears on the ramps", low=0.0,
              strict=True, high=1.0),
        Param("drag", "N·m", "drag torque of the packs beside their friction (oil shear), "
              "drag·tanh(w/1 rad/s)", default=0.0, low=0.0, high=1e6),
    )

    def __init__(self, name, command, heat=(), locked0=None, **values):
        Component.__init__(self, name, **values)          # the values, checked
        if self.ramp_angle >= 90.0:
            err = ValueError(f"{self.label}: ramp_angle = {self.ramp_angle:g}° must be in "
                             "(0, 90)°: at 90° the ramps' axial force tan(φ)·T/r_ramp is "
                             "unbounded")
            err.key = "ramp_angle"
            raise err
        if 0.0 < self.values["mu_s"] < self.mu:
            err = ValueError(f"{self.label}: mu_s = {self.values['mu_s']:g} must be >= mu = "
                             f"{self.mu:g} (the static coefficient holds at least the "
                             "sliding one; 0: mu)")
            err.key = "mu_s"
            raise err
        if self.n_faces != round(self.n_faces):
            err = ValueError(f"{self.label}: n_faces = {self.n_faces:g} must be a whole "
                             "number")
            err.key = "n_faces"
            raise err
        mu_s = self.values["mu_s"] or self.mu
        super().__init__(name, CoulombRobust(F_c=self.mu, F_s=mu_s), command, heat=heat,
                         locked0=locked0, **values)

    def with_values(self, **changes):
        Component.with_values(self, **changes)            # the changes, checked
        return type(self)(self.name, self.command, heat=self.heat, locked0=self.locked0,
                          **{**self.values, **changes})

    @property
    def reads_force(self) -> bool:
        return True

    @property
    def ramp_gain(self) -> float:
        """``ratio·tan(φ)/r_ramp`` [1/m]: the ramps' axial force per N·m into the input."""
        return self.ratio * math.tan(math.radians(self.ramp_angle)) / self.r_ramp

    def bias_ratio(self, T_input: float) -> float:
        """The torque bias ratio ``(T_case/2 + T_p)/(T_case/2 − T_p)`` in slip at the input
        torque ``T_input`` [N·m] (infinite where the packs hold half the case torque)."""
        T_case = self.ratio * abs(T_input)
        T_p = self.mu * self.n_faces * self.R_m * (self.F_preload
                                                   + self.ramp_gain * abs(T_input))
        return math.inf if T_p >= 0.5 * T_case else (0.5 * T_case + T_p) / (0.5 * T_case - T_p)

    def input_ranges(self):
        return {}

    #: the open differential's gear relation ``2·ω_input/ratio = ω_left + ω_right``
    constraints = OpenDifferential.constraints

    def pack(self):
        d = super().pack()
        # the clamp force over clamp_reference is the law's scale: F·n_faces·R_m
        d["clamp_reference"] = 1.0 / (self.n_faces * self.R_m)
        d["ramp_gain"] = self.ramp_gain
        return d

    def _command(self, e) -> str:
        """The clamp force ``F_preload + ratio·tan(φ)/r_ramp·|T_input|`` [N]."""
        self._clamp = e.let("F_clamp", f"{e.par('F_preload')} + {e.par('ramp_gain')} * "
                                       f"abs({e.u(self.command)})")
        return self._clamp

    def _command_slope(self, e) -> str:
        return (f"({e.par('ramp_gain')} * (1.0 if {e.u(self.command)} >= 0.0 else -1.0))")

    def emit(self, e):
        super().emit(e)
        e.output(f"F_clamp_{self.name}", "N", self._clamp)
        for fl in self.flanges:
            e.output(f"T_gear_{self.name}_{fl}", "N·m", e.constraint_torque(0, fl))
