"""The seed's single-state clutch friction model, system (6) (Mykhailevych 2020)."""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .._jit import jit
from ._common import sgn
from .base import (
    RESET_CHANGED,
    RESET_NONE,
    FrictionKernels,
    FrictionModel,
    Scales,
    SelfExcitedWarning,
    expect,
    parameters,
    steady_checks_at,
)

__all__ = [
    "RESET_POLICIES",
    "Mykhailevych2020",
    "mykhailevych2020_events",
    "mykhailevych2020_force",
    "mykhailevych2020_jacobian",
    "mykhailevych2020_reset",
]

#: Reset policies of the integrator phi at a zero crossing of v, and their codes.
RESET_POLICIES: dict[str, int] = {
    "clamp": 0,
    "zero": 1,
    "plus_phi0": 2,
    "minus_phi0": 3,
    "none": 4,
    "stop": 5,
}
#: the code of the event-free policy ``stop`` (the stop operator; no event, no reset)
RESET_STOP = RESET_POLICIES["stop"]


@dataclass(frozen=True)
class Mykhailevych2020(FrictionModel):
    """Model (6) of Mykhailevych (2020): elastic tanh term plus Stribeck drop.

    One state, the integrated slip ``phi`` (m or rad)::

        T      = scale·[ T_stat·tanh(phi/phi0) + k_v·v + c_ps·v·sech²(phi/phi0)
                         - sign(v)·(T_stat - T_din)·(1 - exp(-|v/omega0|^p)) ]
        T_din  = k_din·T_stat
        dphi/dt = v

    ``T_stat`` is the capacity at ``scale = 1`` (for a clutch ``F_n·mu·R_f·i``;
    the driveline passes ``scale = F_n(t)·mu·R_f·i/T_stat`` or the command COM).

    Event ``g = v`` (both directions). At each zero crossing of ``v`` the
    integrator state is re-initialised by the policy ``reset``:

    ``clamp`` (default)  ``phi := sign(phi)·min(|phi|, reset_c·phi0)``
    ``zero``             ``phi := 0`` (the seed's words, "zeroing")
    ``plus_phi0``        ``phi := +sign(phi)·phi0``
    ``minus_phi0``       ``phi := -sign(phi)·phi0`` (the seed's formula line)
    ``none``             no change

    The reset returns 1 when ``phi`` changed, else 0.

    ``stop`` realises the clamp continuously, with no event (the model then declares
    none): the stop operator of hysteresis theory, with c = ``reset_c``::

        dphi/dt = 0   while |phi| >= c·phi0 and v·phi > 0,   else dphi/dt = v
        tanh(phi/phi0)  ->  th = tanh(phi/phi0)/tanh(c)   (spring T_stat·th)
        sech²(phi/phi0) ->  1 - th²                        (damper c_ps·v·(1 - th²))

    Between zero crossings of ``v`` phi is monotone, so at each crossing it is
    exactly clamp's value sign(phi)·min(|phi|, c·phi0).  The normalised spring keeps
    the capacity (the force at |phi| = c·phi0) and the steady sliding force exactly
    clamp's; the pre-sliding stiffness is 1/tanh(c) times higher (1.037 for c = 2)
    and a load T is held at ``phi* = phi0·atanh(T·tanh(c)/T_stat)``.  The pre-sliding
    damper vanishes at the bound, where the stop holds phi in sliding (sech²(c) = 0.07
    would leave 7 % of c_ps acting there), and is ``c_ps·(1 - (T/T_stat)²)`` at a load T,
    as with clamp.

    Properties (between resets): the largest force held in stick is
    ``T_stat``; the pre-sliding stiffness at ``phi = 0`` is ``T_stat/phi0``; a
    constant load ``T < T_stat`` is held at ``phi* = phi0·atanh(T/T_stat)``.
    Steady sliding (``|phi| >> phi0``, tanh = sign(v))::

        T_ss(v) = sign(v)·[T_din + (T_stat - T_din)·exp(-|v/omega0|^p)] + k_v·v,

    which is ``T_stat`` as ``v -> 0+`` and ``T_din + k_v·v`` for ``v >> omega0``.

    Small-slip damping. Hold ``phi`` fixed and expand the velocity-dependent
    part ``D(v) = k_v·v - sign(v)·dT·(1 - exp(-|v/omega0|^p))``,
    ``dT = T_stat - T_din``, about ``v = 0``. With ``1 - exp(-x) = x + O(x^2)``:

    * ``p = 1``: ``sign(v)·|v|/omega0 = v/omega0``, so ``D(v) = (k_v -
      dT/omega0)·v + O(v^2)`` and ``c_eff = k_v - (T_stat - T_din)/omega0``;
    * ``p = 2``: ``sign(v)·v^2/omega0^2 = v·|v|/omega0^2`` is second order, so
      ``c_eff = k_v``.

    The locked state is an inertia on the elastic spring ``T_stat/phi0`` with
    the damper ``c_eff`` (scaled by ``scale``, which does not change its
    sign); ``c_eff < 0`` makes it self-excited, and the constructor then
    emits a :class:`~clutchsim.friction.SelfExcitedWarning`.

    Pre-sliding damping (clutchsim's extension, off by default). ``c_ps·v·sech²(phi/phi0)``
    damps the elastic contact where its spring acts (``sech²`` is the spring's own
    shape, ``d tanh/dphi·phi0``) and vanishes in gross sliding (``|phi| >> phi0``:
    ``sech²(5) = 1.8e-4``), so it damps the locked contact without flattening the
    Stribeck drop as a large ``k_v`` does.  It adds no state; ``c_ps = 0`` is the seed's
    model (6) exactly.  The locked contact (``phi`` near ``phi*``) is then a spring
    ``scale·T_stat·sech²(phi*/phi0)/phi0`` with the damper ``scale·(c_eff +
    c_ps·sech²(phi*/phi0))`` (docs/judder.md derives its frequency and damping ratio).

    Parameters
    ----------
    T_stat : float
        Static capacity at scale 1 [N or N·m], > 0.
    k_din : float
        Ratio T_din/T_stat [-], 0 <= k_din <= 1.
    phi0 : float
        Elastic slip scale [m or rad], > 0.
    omega0 : float
        Velocity separating static and dynamic regimes [m/s or rad/s], > 0.
    k_v : float
        Internal (viscous) friction coefficient [N·s/m or N·m·s/rad], >= 0.
    p : float, optional
        Exponent of the Stribeck term, 1 or 2 (default 2).
    reset : str, optional
        Reset policy, one of ``RESET_POLICIES`` (default ``"clamp"``).
    reset_c : float, optional
        Clamp factor c of the ``clamp`` and ``stop`` policies [-], > 0, default 2.
    c_ps : float, optional
        Pre-sliding damping [N·s/m or N·m·s/rad], >= 0, default 0 (off: the seed's
        equations).

    References
    ----------
    Mykhailevych M.G., "Model of friction for dry friction clutch working
    process simulation", Avtomobil i elektronika. Suchasni tekhnolohii 18
    (2020), system (6). Reset policies ``clamp`` and ``stop`` are clutchsim's addition.
    """

    T_stat: float
    k_din: float
    phi0: float
    omega0: float
    k_v: float
    p: float = 2.0
    reset: str = "clamp"
    reset_c: float = 2.0
    c_ps: float = 0.0

    name: ClassVar[str] = "mykhailevych2020"
    citation: ClassVar[str] = (
        "Mykhailevych M.G., Model of friction for dry friction clutch working process "
        "simulation, Avtomobil i elektronika. Suchasni tekhnolohii (Automobile and "
        "Electronics. Modern Technologies), no. 18, 2020, system (6); Kharkiv National "
        "Automobile and Highway University."
    )
    parameter_info, parameter_rules = parameters(
        T_stat=("force", "static capacity at scale 1 (F_n·mu·R_f·i for a clutch)", "> 0"),
        k_din=("1", "ratio of dynamic to static capacity T_din/T_stat (T_din <= T_stat)",
               "in [0, 1]"),
        phi0=("displacement", "slip within which the contact deforms elastically", "> 0"),
        omega0=("velocity", "slip velocity separating static and dynamic regimes", "> 0"),
        k_v=("force/velocity", "internal (viscous) friction coefficient", ">= 0"),
        p=("1", "exponent of the Stribeck term", "1 or 2"),
        reset=("1", "reset policy of phi at v = 0: " + ", ".join(RESET_POLICIES)
               + " (stop: the clamp as the stop operator, continuous: no event)", ""),
        reset_c=("1", "clamp factor c of the clamp and stop policies (|phi| <= c·phi0)", "> 0"),
        c_ps=("force/velocity",
              "pre-sliding damping c_ps·v·sech²(phi/phi0), 0 in sliding (0 = off)", ">= 0"))
    phenomena = expect(stiction="yes (capacity T_stat)", stribeck="yes",
                       presliding="yes (tanh spring)", lag="depends: via k_v only",
                       varying_breakaway="no", no_drift="depends: only with a clamp-type reset")
    #: F_ss(v) at STEADY_CHECK_SPEEDS written out from the formula with the default set
    steady_checks: ClassVar[tuple[tuple[float, float], ...]] = steady_checks_at(
        -7.329157819444367, 1.65675156119873, 2.1123947195761614, 95.8)
    default_parameter_set: ClassVar[str] = "mykhailevych2020_translational"
    #: at v = 0 the sliding term sign(v)·(1 − exp(−|v/ω0|^p)) is zero from both sides
    smooth_at_events: ClassVar[bool] = True

    @property
    def T_din(self) -> float:
        """Dynamic capacity ``k_din·T_stat`` at scale 1 [N or N·m]."""
        return self.k_din * self.T_stat

    @property
    def c_eff(self) -> float:
        """Linearised small-slip damping at v = 0 and scale 1 [N·s/m or N·m·s/rad]."""
        if self.p == 1.0:
            return self.k_v - (self.T_stat - self.T_din) / self.omega0
        return self.k_v

    def static_capacity(self) -> float:
        """The static torque ``T_stat`` [N or N·m]."""
        return self.T_stat

    def typical_scales(self) -> Scales:
        return Scales(self.T_stat, self.omega0, (self.phi0,))

    def _check(self) -> None:
        self._require(self.reset in RESET_POLICIES, "reset", "one of " + ", ".join(RESET_POLICIES))
        if self.c_eff < 0.0:
            warnings.warn(
                f"Mykhailevych2020: small-slip damping c_eff = {self.c_eff:g} N·s/m < 0 "
                f"(p = {self.p:g}, k_v = {self.k_v:g}, (T_stat - T_din)/omega0 = "
                f"{(self.T_stat - self.T_din) / self.omega0:g}): the locked state is "
                "self-excited; increase k_v or omega0, or use p = 2",
                SelfExcitedWarning,
                stacklevel=4,
            )

    @property
    def event_spec(self) -> tuple[tuple[str, int], ...]:  # type: ignore[override]
        """The zero crossing of ``v`` (both directions), where the reset acts; none for
        ``stop``, whose integrator never needs a reset."""
        return () if self.reset == "stop" else (("velocity_zero_crossing", 0),)

    def _pack(self) -> list[float]:
        return [
            self.T_stat, self.k_din, self.phi0, self.omega0, self.k_v, self.p,
            float(RESET_POLICIES[self.reset]), self.reset_c, self.c_ps,
        ]  # fmt: skip

    def _state_spec(self) -> tuple[tuple[str, str], ...]:
        return (("phi", "displacement"),)

    def _steady(self, v: np.ndarray) -> np.ndarray:
        drop = (self.T_stat - self.T_din) * np.exp(-(np.abs(v / self.omega0) ** self.p))
        return np.sign(v) * (self.T_din + drop) + self.k_v * v

    def _sliding_state(self, v: float) -> list[float]:
        # In steady sliding phi grows without bound; 50·phi0 already gives
        # tanh(phi/phi0) == sign(v) exactly in double precision.  The stop operator
        # holds it at reset_c·phi0, where the normalised spring term is T_stat.
        if self.reset == "stop":
            return [math.copysign(self.reset_c * self.phi0, v)]
        return [math.copysign(50.0 * self.phi0, v)]


@jit
def mykhailevych2020_force(p, z, v, F_e, scale, dz):
    T_stat = p[0]
    dz[0] = v
    x = abs(v / p[3])
    xp = x * x if p[5] == 2.0 else x        # p is 1 or 2 (checked): no call to pow
    drop = (T_stat - p[1] * T_stat) * (1.0 - math.exp(-xp))
    th = math.tanh(z[0] / p[2])
    if p[6] == RESET_STOP:
        # the stop operator: phi stands still at |phi| >= reset_c·phi0 while v drives it
        # outwards; the spring is normalised by tanh(reset_c) (capacity T_stat)
        if abs(z[0]) >= p[7] * p[2] and v * z[0] > 0.0:
            dz[0] = 0.0
        th /= math.tanh(p[7])
    # c_ps·v·(1 - th²): sech²(phi/phi0), or 0 at the stop's bound: 0 in sliding
    return scale * (T_stat * th + p[4] * v + p[8] * v * (1.0 - th * th) - sgn(v) * drop)


@jit
def mykhailevych2020_jacobian(p, z, v, F_e, scale, dz, Jz, dF):
    """Force and partials (see base). ``sign(v)·(1 - exp(-|v/omega0|^p))`` has the same
    slope ``p·|v/omega0|^(p-1)·exp(-|v/omega0|^p)/omega0`` on both sides of ``v = 0``, so
    the force is continuously differentiable there (for ``p = 1`` too)."""
    F = mykhailevych2020_force(p, z, v, F_e, scale, dz)
    T_stat = p[0]
    x = abs(v / p[3])
    xp, slope = (x * x, 2.0 * x) if p[5] == 2.0 else (x, 1.0)
    k = math.tanh(p[7]) if p[6] == RESET_STOP else 1.0      # the stop's normalisation
    th = math.tanh(z[0] / p[2])
    sech2 = (1.0 - th * th) / k                              # phi0·d(th/k)/dphi
    th /= k
    Jz[0, 0], Jz[0, 1] = 0.0, (1.0 if dz[0] == v else 0.0)   # 0 where the stop holds phi
    # c_ps·v·(1 - th²), th = tanh(u)/k, u = phi/phi0: d/dphi = -2·c_ps·v·th·sech2/phi0
    dF[0] = scale * (T_stat * sech2 - 2.0 * p[8] * v * sech2 * th) / p[2]
    dF[1] = scale * (p[4] + p[8] * (1.0 - th * th)
                     - (T_stat - p[1] * T_stat) * slope * math.exp(-xp) / p[3])
    dF[2] = 0.0
    dF[3] = (T_stat * th + p[4] * v + p[8] * v * (1.0 - th * th)
             - sgn(v) * (T_stat - p[1] * T_stat) * (1.0 - math.exp(-xp)))
    return F


@jit
def mykhailevych2020_events(p, z, v, F_e, scale, g):
    if p[6] != RESET_STOP:      # the stop declares no event (g is empty)
        g[0] = v


@jit
def mykhailevych2020_reset(p, z, v, F_e, scale, k):
    phi = z[0]
    policy = int(p[6])
    phi0 = p[2]
    if policy == 0:
        new = sgn(phi) * min(abs(phi), p[7] * phi0)
    elif policy == 1:
        new = 0.0
    elif policy == 2:
        new = sgn(phi) * phi0
    elif policy == 3:
        new = -sgn(phi) * phi0
    else:
        new = phi
    if new == phi:
        return RESET_NONE
    z[0] = new
    return RESET_CHANGED


#: the kernels Mykhailevych2020 provides (compiled code calls exactly these)
Mykhailevych2020.kernels = FrictionKernels(force=mykhailevych2020_force, jacobian=mykhailevych2020_jacobian, events=mykhailevych2020_events,
                                 reset=mykhailevych2020_reset)
