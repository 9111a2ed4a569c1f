"""Chain components: immutable, validated on construction, SI units.

The parts of a chain file (``[[inertia]]``/``[[coupling]]``): :class:`Chain` holds them in
series and translates them into the network components that simulate them
(:meth:`Chain.network`, :mod:`clutchsim.network.components`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..friction.base import FrictionModel
from ..friction.coulomb_robust import CoulombRobust
from ..network.components.friction import TABLE_LOW
from ..network.components.lossy_gear import LOSS_COLUMNS, check_loss_table
from ..network.spec import check_table

__all__ = [
    "ONE_WAY_EPS0",
    "Brake",
    "Engine",
    "FrictionElement",
    "Gear",
    "Gearbox",
    "Inertia",
    "LossyGear",
    "OneWayClutch",
    "SpringDamper",
    "ThermalNode",
    "Vehicle",
    "has_losses",
]

#: relative hysteresis of the one-way clutch (Modelica's ``eps0``): with the clutch open the
#: freewheel releases once the stick torque exceeds ``ONE_WAY_EPS0·T_slide``
ONE_WAY_EPS0 = 1.0e-4


def _num(owner: str, name: str, value, *, low=None, high=None, strict=False, unit=""):
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)):
        # contract: every bad parameter raises ValueError (as for the friction models)
        raise ValueError(f"{owner}: {name} = {value!r} must be a number")  # noqa: TRY004
    x = float(value)
    u = f" {unit}" if unit else ""
    if not math.isfinite(x):
        raise ValueError(f"{owner}: {name} = {x}{u} must be finite")
    if low is not None and (x <= low if strict else x < low):
        raise ValueError(f"{owner}: {name} = {x:g}{u} must be {'>' if strict else '>='} "
                         f"{low:g}{u}")
    if high is not None and x > high:
        raise ValueError(f"{owner}: {name} = {x:g}{u} must be <= {high:g}{u}")
    return x


def _table(owner: str, name: str, xs, ys):
    if xs is None and ys is None:
        return None
    return check_table(owner, name, xs, ys, low=TABLE_LOW.get(name))


def _heat_shares(o, heat):
    """Validated ``((thermal node, share of the friction power), ...)`` of an element [-]."""
    heat = tuple((str(n), _num(o, "heat share", s, low=0.0, high=1.0)) for n, s in heat)
    if len(heat) > 2:
        raise ValueError(f"{o}: heat goes to at most 2 thermal nodes")
    if sum(s for _, s in heat) > 1.0 + 1e-12:
        raise ValueError(f"{o}: heat shares sum to {sum(s for _, s in heat):g} > 1")
    return heat


@dataclass(frozen=True)
class Inertia:
    """A rotating inertia (a node of the chain).

    Parameters
    ----------
    name : str
        Unique name; its speed state is ``omega_<name>`` [rad/s].
    J : float
        Inertia [kg·m²] (> 0).
    omega0 : float
        Initial speed [rad/s].
    bearing_damping : float
        Viscous bearing loss to ground [N·m·s/rad] (>= 0).
    load : str, optional
        Name of an input signal applied as a torque on this inertia [N·m].
    """

    name: str
    J: float
    omega0: float = 0.0
    bearing_damping: float = 0.0
    load: str | None = None

    def __post_init__(self):
        o = f"inertia {self.name!r}"
        object.__setattr__(self, "J", _num(o, "J", self.J, low=0.0, strict=True, unit="kg·m²"))
        object.__setattr__(self, "omega0", _num(o, "omega0", self.omega0, unit="rad/s"))
        object.__setattr__(self, "bearing_damping",
                           _num(o, "bearing_damping", self.bearing_damping, low=0.0,
                                unit="N·m·s/rad"))


@dataclass(frozen=True)
class Gear:
    """Ideal rigid gear between two inertias: ``omega_b = omega_a / ratio``.

    Parameters
    ----------
    name : str
    ratio : float
        Speed ratio [-] (non-zero); the downstream inertia is reflected as ``J·ratio²``.
    """

    name: str
    ratio: float = 1.0

    def __post_init__(self):
        r = _num(f"gear {self.name!r}", "ratio", self.ratio)
        if r == 0.0:
            raise ValueError(f"gear {self.name!r}: ratio must be non-zero")
        object.__setattr__(self, "ratio", r)


@dataclass(frozen=True)
class Gearbox:
    """A rigid gearbox with selectable ratios, final drive and mesh losses.

    The gearbox is rigid, ``omega_out = omega_in / ratio``.  With an efficiency below 1 (or
    a drag torque) it takes a loss torque ``L`` [N·m], referred to its input shaft, out of
    the torque it transmits, with the power-flow-dependent law of :class:`LossyGear`
    (Pelchen et al. 2002): driving (power from the engine side to the wheels) ``L = (1 -
    efficiency)·T_in + drag_torque``; driven back (engine braking, tip-out) ``L = (1 -
    1/efficiency_reverse)·T_in + drag_torque``.  At standstill it sticks while the torque it
    must hold stays inside those laws' limits (Modelica ``LossyGear``).  The loss power is
    booked in ``W_friction``; the loss acts at the gearbox input, whatever gear is engaged.

    Parameters
    ----------
    name : str
    ratios : tuple of float
        Gear ratios [-], gear 1 first.
    gear : int
        Selected gear at the start (1-based).
    final_drive : float
        Final drive ratio [-] multiplied into every gear.
    shifts : tuple of (float, int)
        ``(time [s], new gear)``: at each time the ratio changes; an ideal synchroniser
        brings the input side to the new speed (the kinetic energy it removes is booked
        as ``W_sync``).  Open the clutch around a shift.
    efficiency : float
        Mesh efficiency [-] in (0, 1] with power flowing from input to output (gearbox and
        final drive together; the same in every gear).  1: no mesh loss (default).
    efficiency_reverse : float or None
        Mesh efficiency [-] in (0, 1] with power flowing from the output back to the input
        (engine braking).  ``None``: equal to ``efficiency``.
    drag_torque : float
        Speed-independent bearing and churning drag [N·m] (>= 0) referred to the input
        shaft.  Default 0.

    References
    ----------
    Pelchen C., Schweiger C., Otter M., "Modeling and simulating the efficiency of gearboxes
    and of planetary gearboxes", 2nd International Modelica Conference, 2002, pp. 257-266.
    """

    name: str
    ratios: tuple
    gear: int = 1
    final_drive: float = 1.0
    shifts: tuple = ()
    efficiency: float = 1.0
    efficiency_reverse: float | None = None
    drag_torque: float = 0.0

    def __post_init__(self):
        o = f"gearbox {self.name!r}"
        rs = tuple(_num(o, "ratios", r, low=0.0, strict=True) for r in self.ratios)
        if not rs:
            raise ValueError(f"{o}: ratios must list at least one gear")
        object.__setattr__(self, "ratios", rs)
        object.__setattr__(self, "final_drive",
                           _num(o, "final_drive", self.final_drive, low=0.0, strict=True))
        self._check_gear(self.gear, "gear")
        sh = []
        for t, g in self.shifts:
            self._check_gear(g, "shifts")
            sh.append((_num(o, "shift time", t, low=0.0, strict=True, unit="s"), int(g)))
        object.__setattr__(self, "shifts", tuple(sorted(sh)))
        eta = _efficiency(o, "efficiency", self.efficiency)
        object.__setattr__(self, "efficiency", eta)
        rev = eta if self.efficiency_reverse is None else \
            _efficiency(o, "efficiency_reverse", self.efficiency_reverse)
        object.__setattr__(self, "efficiency_reverse", rev)
        object.__setattr__(self, "drag_torque",
                           _num(o, "drag_torque", self.drag_torque, low=0.0, unit="N·m"))

    def _check_gear(self, g, key):
        if isinstance(g, bool) or not isinstance(g, (int, np.integer)) or \
                not 1 <= g <= len(self.ratios):
            raise ValueError(f"gearbox {self.name!r}: {key}: gear {g!r} does not exist; "
                             f"this gearbox has {len(self.ratios)} gears "
                             f"(1..{len(self.ratios)})")

    def ratio(self, gear: int) -> float:
        """Overall ratio of ``gear`` including the final drive [-]."""
        return self.ratios[gear - 1] * self.final_drive

    @property
    def ideal(self) -> bool:
        """True without losses (both efficiencies 1, no drag torque)."""
        return self.efficiency == 1.0 and self.efficiency_reverse == 1.0 and \
            self.drag_torque == 0.0

    def columns(self) -> tuple[tuple[float, ...], ...]:
        """The losses as a one-row :class:`LossyGear` table, in five columns (speed,
        eta_mf1, eta_mf2, tau_bf1, tau_bf2)."""
        return ((0.0,), (self.efficiency,), (self.efficiency_reverse,), (self.drag_torque,),
                (self.drag_torque,))


def has_losses(c) -> bool:
    """Is ``c`` a gear with losses (a :class:`LossyGear` or :class:`Gearbox` that is not
    ideal)?  A chain holds at most one: its loss is solved in closed form."""
    return isinstance(c, (LossyGear, Gearbox)) and not c.ideal


def _efficiency(owner: str, name: str, value) -> float:
    x = _num(owner, name, value)
    if not 0.0 < x <= 1.0:
        raise ValueError(f"{owner}: {name} = {x:g} must be in (0, 1] (an efficiency of 0 "
                         "cannot transmit power)")
    return x




@dataclass(frozen=True)
class LossyGear:
    """Gear with mesh efficiency and bearing friction that can stick (Modelica ``LossyGear``).

    The gear is rigid, ``omega_b = omega_a / ratio``.  Inside it a loss torque ``L``
    [N·m], referred to flange a, is taken out of the transmitted torque: flange a takes
    ``T_a`` from inertia a and flange b delivers ``ratio·(T_a - L)`` to inertia b, so that
    ``(J_a + J_b/ratio²)·dω_a/dt = τ_a + τ_b/ratio - L``.  While the gear rolls
    (``ω_a ≠ 0``) the loss depends on the direction of the power flow, decided by the sign
    of ``T_a ∓ τ_bf,a`` (Pelchen et al. 2002)::

        forward  (ω_a > 0):  L = (1 - η1)·T_a + τ_bf1    if T_a - τ_bf,a >= 0 (a drives b)
                              L = (1 - 1/η2)·T_a + τ_bf2  otherwise            (b drives a)
        backward (ω_a < 0):  L = (1 - 1/η2)·T_a - τ_bf2  if T_a + τ_bf,a >= 0
                              L = (1 - η1)·T_a - τ_bf1    otherwise

    with ``τ_bf,a = (τ_bf1 - τ_bf2)/(η1 - 1/η2)`` (``τ_bf1/2`` if both efficiencies are
    1), which makes ``L`` continuous in ``T_a``.  ``η1``, ``η2``, ``τ_bf1``, ``τ_bf2`` are
    interpolated in ``|ω_a|`` in ``loss_table``.  At ``ω_a = 0`` the gear *sticks* (the
    whole rigid cluster stands still) while the torque it must hold stays between the
    backward and forward values of the laws above at ``|ω_a| = 0`` (Modelica's
    ``tauLossMin_m``/``tauLossMax_p``); beyond them it starts rolling.  Low efficiencies
    widen that range, so a loaded gear can stay at rest although it is driven.  The loss
    power ``L·ω_a >= 0`` is booked in ``W_friction``.

    Parameters
    ----------
    name : str
    ratio : float
        ``ω_a/ω_b`` [-] (non-zero).
    loss_table : sequence of rows (speed, eta_mf1, eta_mf2, tau_bf1, tau_bf2)
        ``|ω_a|`` [rad/s] (first row >= 0, strictly increasing), mesh efficiency with power
        flowing a -> b ``η1`` [-] and b -> a ``η2`` [-] (both in (0, 1]), bearing friction
        torques [N·m] (>= 0) for the two power-flow directions.  Held constant outside the
        speed range.  The ideal table ``[(0, 1, 1, 0, 0)]`` makes an ideal gear.

    References
    ----------
    Pelchen C., Schweiger C., Otter M., "Modeling and simulating the efficiency of gearboxes
    and of planetary gearboxes", 2nd International Modelica Conference, 2002, pp. 257-266;
    Modelica Standard Library 4.x, ``Modelica.Mechanics.Rotational.Components.LossyGear``.
    """

    name: str
    ratio: float
    loss_table: tuple = ((0.0, 1.0, 1.0, 0.0, 0.0),)

    def __post_init__(self):
        o = f"lossy gear {self.name!r}"
        r = _num(o, "ratio", self.ratio)
        if r == 0.0:
            raise ValueError(f"{o}: ratio = 0 is not allowed: the ratio omega_a/omega_b must "
                             "be non-zero")
        object.__setattr__(self, "ratio", r)
        for i, row in enumerate(self.loss_table):
            for c, v in zip(LOSS_COLUMNS, tuple(row)):
                _num(o, f"loss_table[{i}].{c}", v)
        cols = check_loss_table(o, self.loss_table)
        rows = tuple(zip(*cols))
        object.__setattr__(self, "loss_table", rows)

    @property
    def ideal(self) -> bool:
        """True when the table has no losses (efficiency 1, no bearing friction)."""
        return all(r[1:] == (1.0, 1.0, 0.0, 0.0) for r in self.loss_table)

    def columns(self) -> tuple[tuple[float, ...], ...]:
        """The table as five columns (speed, eta_mf1, eta_mf2, tau_bf1, tau_bf2)."""
        return tuple(tuple(r[c] for r in self.loss_table) for c in range(5))


@dataclass(frozen=True)
class SpringDamper:
    """Torsional spring-damper (optionally two-stage), e.g. a disc damper or a driveshaft.

    Parameters
    ----------
    name : str
    c : float
        Stiffness [N·m/rad] (> 0) of the first stage.
    d : float
        Viscous damping [N·m·s/rad] (>= 0).
    knee : float
        Twist [rad] where the second stage starts (0: single stage).
    c2 : float
        Second-stage stiffness [N·m/rad].
    phi0 : float
        Initial twist [rad].
    ratio : float
        Ideal ratio on its input side [-].
    """

    name: str
    c: float
    d: float = 0.0
    knee: float = 0.0
    c2: float = 0.0
    phi0: float = 0.0
    ratio: float = 1.0

    def __post_init__(self):
        o = f"spring-damper {self.name!r}"
        object.__setattr__(self, "c", _num(o, "c", self.c, low=0.0, strict=True,
                                           unit="N·m/rad"))
        object.__setattr__(self, "d", _num(o, "d", self.d, low=0.0, unit="N·m·s/rad"))
        object.__setattr__(self, "knee", _num(o, "knee", self.knee, low=0.0, unit="rad"))
        object.__setattr__(self, "c2", _num(o, "c2", self.c2, low=0.0, unit="N·m/rad"))
        object.__setattr__(self, "phi0", _num(o, "phi0", self.phi0, unit="rad"))
        object.__setattr__(self, "ratio", _num(o, "ratio", self.ratio))
        if self.knee > 0 and self.c2 <= 0:
            raise ValueError(f"{o}: a two-stage spring (knee > 0) needs c2 > 0")


@dataclass(frozen=True)
class FrictionElement:
    """A friction element between two inertias (clutch) - any friction model.

    The model's force parameters are the capacity at full actuation (``scale = 1``).
    ``scale`` = actuation × mu(theta)/mu_ref × mu(|w|)/mu_ref, where the actuation is the
    input signal ``command`` (COM in [0, 1], seed eqs. 1-2) or, with ``clamp_table``, the
    normalised clamp force F_n(x)/F_n,ref of a diaphragm-spring characteristic at the
    pedal/actuator position ``x`` given by the input.

    Parameters
    ----------
    name : str
    model : FrictionModel
    command : str
        Name of the actuation input signal.
    clamp_table : (positions, normalised forces), optional
        Diaphragm-spring characteristic F_n/F_n,ref [-] against position [-].
    mu_temperature : (theta [°C], factor [-]), optional
        mu(theta)/mu_ref read at the first thermal node's temperature.
    mu_slip : (|w| [rad/s], factor [-]), optional
        mu(slip)/mu_ref.
    heat : tuple of (node name, share)
        Where the friction power |tau·w| goes (shares in [0, 1], sum <= 1).
    wear : WearLaw, optional
        Lining wear law (:mod:`clutchsim.network.wear`); adds the state ``wear_<name>``.
    drag : float
        Drag torque of the open element [N·m] (``drag·tanh(w / 1 rad/s)``).
    ratio : float
        Ideal ratio on its input side [-].
    locked0 : bool, optional
        Start locked (switching models only); default: locked if the slip is zero.
    runout : (amplitude [-], order [-]), optional
        Clamp-load oscillation of pressure-plate runout: the capacity is multiplied by
        ``1 + amplitude·sin(order·φ_b)``, ``φ_b`` the angle of side b (the input shaft).
    """

    name: str
    model: FrictionModel
    command: str
    clamp_table: tuple | None = None
    mu_temperature: tuple | None = None
    mu_slip: tuple | None = None
    heat: tuple = ()
    drag: float = 0.0
    ratio: float = 1.0
    locked0: bool | None = None
    z0: tuple | None = field(default=None)
    runout: tuple | None = None
    wear: object = None

    def __post_init__(self):
        o = f"friction element {self.name!r}"
        if not isinstance(self.model, FrictionModel):
            raise TypeError(f"{o}: model must be a clutchsim friction model")
        for key in ("clamp_table", "mu_temperature", "mu_slip"):
            tab = getattr(self, key)
            if tab is not None:
                object.__setattr__(self, key, _table(o, key, tab[0], tab[1]))
        object.__setattr__(self, "drag", _num(o, "drag", self.drag, low=0.0, unit="N·m"))
        object.__setattr__(self, "ratio", _num(o, "ratio", self.ratio))
        object.__setattr__(self, "heat", _heat_shares(o, self.heat))


@dataclass(frozen=True)
class Brake(FrictionElement):
    """A friction element from an inertia to ground (``node`` = inertia name).

    Parameters are those of :class:`FrictionElement`, plus ``node``.
    """

    node: str = ""


@dataclass(frozen=True)
class OneWayClutch:
    """A freewheel in parallel with a friction clutch (Modelica ``OneWayClutch``).

    Coupling between two inertias with the relative speed ``w = omega_b - omega_a/ratio``.
    The freewheel lets ``w`` be positive only: while ``w > 0`` the element slides and the
    clutch transmits ``command·T_slide`` (0 when the command is <= 0); when ``w`` reaches 0
    it locks and then holds any torque in the blocking direction (``T <= 0``, flange a
    drives flange b) and up to ``command·peak·T_slide`` in the other; beyond that it slides
    forward again.  With the clutch open the freewheel releases once the stick torque
    exceeds ``ONE_WAY_EPS0·T_slide`` (Modelica's ``tau0_max_low``).  One constraint torque
    covers both parts, which is why it is one element.

    Internally the clutch part is a :class:`~clutchsim.friction.CoulombRobust` model with
    ``F_c = T_slide`` and ``F_s = max(peak, 1 + ONE_WAY_EPS0)·T_slide``; its ``mode`` state
    is +1 (sliding) or 0 (locked).

    Parameters
    ----------
    name : str
    command : str
        Normalised clamp force input ``f_normalized`` [-] (0 open .. 1 full).
    T_slide : float
        Sliding torque of the clutch at full command, ``mu·cgeo·fn_max`` [N·m] (>= 0).
    peak : float
        Ratio of the static to the sliding torque [-] (>= 1).
    heat : tuple of (node name, share)
        Where the friction power goes (as for :class:`FrictionElement`).
    mu_temperature : (theta [°C], factor [-]), optional
        mu(theta)/mu_ref at the first heat node.
    ratio : float
        Ideal ratio on its input side [-].
    locked0 : bool, optional
        Start locked (default: locked when the initial relative speed is 0).

    References
    ----------
    Modelica Standard Library 4.x, ``Modelica.Mechanics.Rotational.Components.OneWayClutch``;
    Otter M., Elmqvist H., Mattsson S.E., "Hybrid modeling in Modelica based on the
    synchronous data flow principle", CACSD'99, 1999.
    """

    name: str
    command: str
    T_slide: float
    peak: float = 1.0
    heat: tuple = ()
    mu_temperature: tuple | None = None
    ratio: float = 1.0
    locked0: bool | None = None
    model: FrictionModel = field(init=False, repr=False, compare=False)

    #: attributes shared with :class:`FrictionElement` (not settable here)
    clamp_table = None
    mu_slip = None
    drag = 0.0
    z0 = None

    def __post_init__(self):
        o = f"one-way clutch {self.name!r}"
        t_slide = _num(o, "T_slide", self.T_slide, low=0.0, unit="N·m")
        peak = _num(o, "peak", self.peak, low=1.0)
        object.__setattr__(self, "T_slide", t_slide)
        object.__setattr__(self, "peak", peak)
        object.__setattr__(self, "ratio", _num(o, "ratio", self.ratio))
        if self.ratio == 0.0:
            raise ValueError(f"{o}: ratio must be non-zero")
        if self.mu_temperature is not None:
            object.__setattr__(self, "mu_temperature",
                               _table(o, "mu_temperature", *self.mu_temperature))
        object.__setattr__(self, "heat", _heat_shares(o, self.heat))
        peak2 = max(peak, 1.0 + ONE_WAY_EPS0)
        object.__setattr__(self, "model", CoulombRobust(F_c=t_slide, F_s=peak2 * t_slide))

    @property
    def free_threshold(self) -> float:
        """Stick torque [N·m] above which the open freewheel releases (``eps0·T_slide``)."""
        return ONE_WAY_EPS0 * self.T_slide


@dataclass(frozen=True)
class Engine:
    """Combustion engine torque source on an inertia.

    ``T = x·T_max(omega) - (drag0·tanh(omega/1 rad/s) + drag1·omega)``, where
    ``x = clip(throttle + clip(kp·e + ki·I, 0, 1 - throttle), 0, 1)``, ``e = omega_idle -
    omega``, ``dI/dt = e + (gov - raw)/(ki·0.1 s)`` (back-calculation anti-windup, which
    keeps the right-hand side continuous).  The PI idle governor
    is therefore limited by the available torque ``T_max(omega)``.  The engine stalls
    (the run fails and says so) when its speed falls below ``stall_speed``.

    Parameters
    ----------
    node : str
        Inertia the engine drives (crankshaft + flywheel).
    speeds, torques : sequence of float
        Full-load curve T_max [N·m] against speed [rad/s].
    throttle : str
        Name of the throttle input signal [-], 0..1.
    drag0 : float
        Friction torque [N·m]; ``drag1``: pumping loss coefficient [N·m·s/rad].
    idle_speed : float
        Idle target [rad/s] (0 disables the governor).
    kp, ki : float
        Governor gains [1/(rad/s)], [1/rad].
    stall_speed : float
        Stall threshold [rad/s].
    """

    node: str
    speeds: tuple
    torques: tuple
    throttle: str = "throttle"
    drag0: float = 0.0
    drag1: float = 0.0
    idle_speed: float = 0.0
    kp: float = 0.0
    ki: float = 0.0
    stall_speed: float = 0.0

    def __post_init__(self):
        o = "engine"
        tab = _table(o, "full-load curve (speeds, torques)", self.speeds, self.torques)
        object.__setattr__(self, "speeds", tab[0])
        object.__setattr__(self, "torques", tab[1])
        from ..network.components.engine import Engine as _NetworkEngine
        from ..network.spec import check_value
        for spec in _NetworkEngine.params:      # the ranges are declared there, once
            object.__setattr__(self, spec.name, check_value(o, spec,
                                                            getattr(self, spec.name)))
        if self.idle_speed and self.stall_speed >= self.idle_speed:
            raise ValueError(f"engine: stall_speed = {self.stall_speed:g} rad/s must be below "
                             f"idle_speed = {self.idle_speed:g} rad/s")


@dataclass(frozen=True)
class Vehicle:
    """Vehicle on the last inertia (the wheels): mass, tyre, grade, road load.

    The vehicle mass appears at the wheels as the inertia ``m·r²``; the road load
    ``[m·g·(f_r·cos(a)·tanh(v/v_eps) + sin(a)) + ½·rho·c_d·A·v·|v|]·r`` brakes the wheels.

    Parameters
    ----------
    mass : float
        [kg] (> 0).
    tyre_radius : float
        Dynamic rolling radius [m] (> 0).
    grade : float
        Road grade [%] (rise/run·100; positive uphill).
    rolling : float
        Rolling-resistance coefficient f_r [-].
    cd_area : float
        Drag area c_d·A [m²].
    air_density : float
        [kg/m³].
    v_eps : float
        Speed [m/s] over which rolling resistance builds up (regularisation at rest).
    """

    mass: float
    tyre_radius: float
    grade: float = 0.0
    rolling: float = 0.0
    cd_area: float = 0.0
    air_density: float = 1.2
    v_eps: float = 0.05
    gravity: float = 9.81

    def __post_init__(self):
        o = "vehicle"
        object.__setattr__(self, "mass", _num(o, "mass", self.mass, low=0.0, strict=True,
                                              unit="kg"))
        object.__setattr__(self, "tyre_radius", _num(o, "tyre_radius", self.tyre_radius,
                                                     low=0.0, strict=True, unit="m"))
        object.__setattr__(self, "grade", _num(o, "grade", self.grade, low=-100, high=100,
                                               unit="%"))
        object.__setattr__(self, "rolling", _num(o, "rolling", self.rolling, low=0.0, high=0.5))
        object.__setattr__(self, "cd_area", _num(o, "cd_area", self.cd_area, low=0.0,
                                                 unit="m²"))
        object.__setattr__(self, "air_density", _num(o, "air_density", self.air_density,
                                                     low=0.0, unit="kg/m³"))
        object.__setattr__(self, "v_eps", _num(o, "v_eps", self.v_eps, low=0.0, strict=True,
                                               unit="m/s"))

    @property
    def equivalent_inertia(self) -> float:
        """``m·r²`` [kg·m²]."""
        return self.mass * self.tyre_radius ** 2


@dataclass(frozen=True)
class ThermalNode:
    """Lumped thermal node (e.g. pressure plate, flywheel).

    ``C·dtheta/dt = sum(share·|tau·w|) - hA·(theta - ambient) - G·(theta - theta_link)``

    Parameters
    ----------
    name : str
    capacity : float
        Heat capacity C = m·c_p [J/K] (> 0).
    conductance : float
        Convection hA to ambient [W/K] (>= 0; 0: adiabatic).
    ambient : float
        Ambient temperature [°C].
    theta0 : float
        Initial temperature [°C].
    link : str, optional
        Another thermal node this one conducts heat to (e.g. a friction-surface layer to
        the bulk of its plate): ``q = link_conductance·(theta - theta_link)`` leaves this
        node and enters the other.  Declare each link once, on one of the two nodes.
    link_conductance : float
        Conductance of the link [W/K] (> 0 with a link).
    """

    name: str
    capacity: float
    conductance: float = 0.0
    ambient: float = 20.0
    theta0: float = 20.0
    link: str | None = None
    link_conductance: float = 0.0

    def __post_init__(self):
        o = f"thermal node {self.name!r}"
        object.__setattr__(self, "capacity", _num(o, "capacity", self.capacity, low=0.0,
                                                  strict=True, unit="J/K"))
        object.__setattr__(self, "conductance", _num(o, "conductance", self.conductance,
                                                     low=0.0, unit="W/K"))
        object.__setattr__(self, "ambient", _num(o, "ambient", self.ambient, low=-273.15,
                                                 unit="°C"))
        object.__setattr__(self, "theta0", _num(o, "theta0", self.theta0, low=-273.15,
                                                unit="°C"))
        object.__setattr__(self, "link_conductance",
                           _num(o, "link_conductance", self.link_conductance, low=0.0,
                                unit="W/K"))
        if self.link is not None and not isinstance(self.link, str):
            raise ValueError(f"{o}: link = {self.link!r} must be the name of a thermal node")
        if self.link is not None and self.link_conductance <= 0.0:
            raise ValueError(f"{o}: link to {self.link!r} needs link_conductance > 0 W/K")
        if self.link is None and self.link_conductance > 0.0:
            raise ValueError(f"{o}: link_conductance = {self.link_conductance:g} W/K needs a "
                             "link (the name of the node it conducts to)")
        if self.link == self.name:
            raise ValueError(f"{o}: link must name another node, not the node itself")
