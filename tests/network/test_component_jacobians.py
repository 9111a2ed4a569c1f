"""Every network component's hand-written partial derivatives, against finite differences.

A component writes its equations and, beside them, their exact partial derivatives
(:meth:`~clutchsim.network.component.Component.emit`); the generated plant assembles them
into ``jac``.  This module compares ``jac`` of compiled test networks entry by entry with
finite differences of the same plant's ``rhs``, at many random states, inputs and parameter
values, for every component of the registry
(:data:`clutchsim.network.components.COMPONENTS`) and, for the friction elements, every
friction model of the registry (plus the elements' own laws: one-way clutch, lossy gear,
gearbox, mass with stops).  Every row is checked: accelerations, the components' own
states, friction-model states, the thermal nodes, the lining wear and the energy accounts
(``W_in``, ``W_friction``, ``W_damping``, ``W_road``, ``E_grade``, ``W_sync``).

Adding a component
------------------
``BUILDERS`` maps each registered ``kind`` to a network builder ``builder(rng, model)``
that returns a :class:`Case` (a small network that contains the component, 2-4 inertias,
with random parameter values drawn from ``rng``, and the ranges of its inputs).  A new
component needs one line in ``BUILDERS`` (an existing builder whose network gains the
component, or a new function of a few lines); ``test_every_registered_component_has_a_builder``
fails, naming the component, until it has one.  Components are grouped into few networks
(each distinct network costs one plant compile, about a second of C); the friction
networks are built once per friction model.

The comparison
--------------
State ``j`` has a scale ``S_j`` (a speed: the smallest velocity scale of the friction
models in the network, at most 1; a friction-model state: its steady sliding value; other
states by unit, or the builder's hint), and is moved by ``h_j = 1e-4·S_j`` (the step
actually taken, ``(y + h) − y``, is used).  From ``rhs`` at ``y + {−2, −1, 1, 2}·h_j``:

* central ``C = (8·(f₁ − f₋₁) − (f₂ − f₋₂))/(12·h)`` (error O(h⁴));
* one-sided second-order differences ``D₊ = (−3f₀ + 4f₁ − f₂)/(2h)``,
  ``D₋ = (3f₀ − 4f₋₁ + f₋₂)/(2h)``.

Nonsmooth sets (zero slip, the clip of a stick torque, lash and stop edges, table
breakpoints, ``|τ·w|`` of the heat, mode logic) are handled like this: points are drawn
*near* them (slips down to 1e-2 velocity scales, twists within a few steps of the edges,
commands that put the capacity within 0.1-10 % of the stick torque), never on them by
construction except where the plant itself puts a point on one (a locked element's zero
slip); an entry is compared only where the two one-sided differences agree
(``|D₊ − D₋| <= KINK·(|C| + T_ij)``): where they disagree the stencil straddles a kink or
a jump (the one-sided limits differ), and the exact Jacobian of either side is right.
Such entries are counted: at most ``MAX_SKIPPED`` of the structurally relevant entries of
a network may be skipped (0.5 % at most today), so that the test cannot pass by skipping;
not counted are the entries a locked element puts on its kink by construction (its heat
``|τ·w|`` at ``w = 0``, in its thermal and wear rows).  The columns of
discrete states (modes, lock flags, a mass's stop) are not differenced: they change only
at events, and their Jacobian columns must be exactly 0.

An entry passes when ``|J_ij − C_ij| <= RTOL·(|C_ij| + T_ij) + ρ_ij + NOISE·E_ij`` with
``T_ij = R_i/S_j``, ``R_i = max_k |C_ik|·S_k`` (the largest change of ``f_i`` over one
typical move of any state: an entry is not held to a relative error where it is
negligible against its row), the round-off of the differences ``ρ_ij =
ROUND·eps·max|f_i|/h_j`` (for the accelerations ``max|f_i|`` includes the accelerations
without the locks, which a lock projection cancels to round-off of their size) and
``E_ij = |C(h) − C(2h)|`` of the second-order central differences (round-off and
truncation; O(h²) where ``f`` is smooth).  ``RTOL = 1e-6``: the 55,649 compared entries
at the 1,680 points of the first 28 networks also passed at 1e-7 (a margin of 10; today
48 networks, 2,880 points, 115,061 entries); a partial off
by 1 % fails at dozens of points (checked by mutating partials of the spring-damper,
vehicle, engine governor, μ(slip), torque converter, rate-limited lag and backlash
limiter).

Where a switching element's force *is* its stick torque clipped to the capacity
(coulomb-robust stuck but not locked, karnopp inside its window), the force's partials
include ``∂F/∂F_e·∂F_e/∂y`` (``network/render.py:stick_columns``; missing until this test
found it): ``test_jacobian_where_the_force_is_the_clipped_stick_torque`` draws those
regimes (capacity 0.1-10 % above or below the stick torque); the main test draws the two
laws locked or sliding.  In those regimes an acceleration that the stick force cancels
keeps round-off of the size of the plant's largest value times eps: the floor of the
acceleration rows.

Runtime: 48 networks compared (and one coulomb-naive plant built), one compiled plant
each: C, cached on disk, so that a second run loads them in milliseconds; GMS's kernels
cannot be printed as C, so its two plants are compiled by numba, 15-45 s each the first
time.  Measured on the shared 2-core machine (load ~5): 25 s warm, 133 s cold.
"""

from __future__ import annotations

import math
import zlib
from collections import Counter
from dataclasses import dataclass, field

import numpy as np
import pytest

from clutchsim.core.system import call_jac, call_rhs, has_jacobian
from clutchsim.friction import MODELS, CoulombRobust, make_model
from clutchsim.network import Network
from clutchsim.network.components import (
    COMPONENTS,
    BandBrake,
    Brake,
    Clutch,
    ConeClutch,
    Damper,
    DogClutch,
    Driver,
    DualMassFlywheel,
    ElastoBacklash,
    Engine,
    Force,
    Gearbox,
    HydraulicActuator,
    IdealGear,
    Inertia,
    LaunchController,
    LimitedSlipDifferential,
    LossyGear,
    Mass,
    MassWithStopAndFriction,
    OneWayClutch,
    OpenDifferential,
    Planetary,
    QuadraticSpeedTorque,
    ReleaseSystem,
    ServoActuator,
    SpringDamper,
    SupportFriction,
    Synchronizer,
    ThermalNode,
    TorqueConverter,
    TorquePulsation,
    TorqueSource,
    TorsionalMount,
    TranslationalBrake,
    TranslationalSpringDamper,
    Tyre,
    Vehicle,
    WetClutch,
)
from clutchsim.network.wear import WearLaw

STEP = 1e-4          # h_j = STEP·S_j
RTOL = 1e-6          # pass: |J − C| <= RTOL·(|C| + T) (+ round-off, see the docstring)
KINK = 1e-6          # compare only where |D₊ − D₋| <= KINK·(|C| + T)
ROUND = 16.0         # round-off of a difference: ROUND·eps·max|f_i|/h_j
NOISE = 3.0          # and NOISE times the change of the central difference from h to 2h
MAX_SKIPPED = 0.03   # largest share of relevant entries skipped as kinks, per network
POINTS = 60          # random points per network


@dataclass
class Case:
    """A test network: the network, the ranges ``(lo, hi)`` of its inputs, scales of some
    states by label (the twist of a lash, ...) and samplers of states near their edges
    (``label -> f(rng, y_value) -> value``)."""

    net: Network
    inputs: dict = field(default_factory=dict)
    scales: dict = field(default_factory=dict)
    near: dict = field(default_factory=dict)


def _f(rng, lo, hi):
    return float(rng.uniform(lo, hi))


def _edge(rng, edge, scale):
    """A value near ``±edge`` (either side, 1 to 100 steps away, or further)."""
    side = 1.0 if rng.random() < 0.5 else -1.0
    off = scale * STEP * 10.0 ** rng.uniform(0.5, 3.0) * (1.0 if rng.random() < 0.5 else -1.0)
    return side * edge + off


# ------------------------------------------------------------------ friction models
def _velocity_scale(model) -> float:
    """The smallest velocity on which the model's force changes [rad/s or m/s]."""
    vals = [getattr(model, a) for a in ("v_t", "v_s", "DV", "omega0", "v_brk")
            if getattr(model, a, 0.0)]
    if getattr(model, "fexp", 0.0):
        vals.append(1.0 / model.fexp)
    return min([1.0, *[float(v) for v in vals if v > 0.0]])


def _random_model(name: str, rng, force: float = 1.0):
    """Friction model ``name`` with its force-like parameters (kinds ``force``,
    ``force/...``) scaled by ``force`` and every numeric parameter then by a random factor
    in [0.7, 1.4] (a draw the model refuses is drawn again; coulomb-robust gets a Stribeck
    term and viscous friction)."""
    base = make_model(name)
    if name == "coulomb-robust":
        base = base.with_(v_s=1e-3, sigma2=0.4)
    info = type(base).parameter_info
    scaled = {}
    for k, (kind, _doc) in info.items():
        v = getattr(base, k)
        if not kind.startswith("force") or isinstance(v, str):
            continue
        scaled[k] = tuple(x * force for x in v) if isinstance(v, tuple) else v * force
    base = base.with_(**scaled) if scaled else base
    keys = [k for k, v in vars(base).items() if isinstance(v, float) and v != 0.0
            and k not in ("p", "delta", "alpha", "reset_c")]
    for _ in range(10):
        try:
            return base.with_(**{k: getattr(base, k) * rng.uniform(0.7, 1.4) for k in keys})
        except ValueError:
            continue
    return base


FRICTION_MODELS = sorted(MODELS)
#: models whose plant has no exact Jacobian (the integrators difference it)
NO_JACOBIAN = sorted(n for n in MODELS if MODELS[n].jumps)


# ------------------------------------------------------------------ builders
def _rotational_friction(rng, model):
    """Clutch (μ(θ) and μ(slip) tables, runout, drag, heat to two nodes, wear) between two
    inertias, a brake (clamp table, μ(slip) and μ(θ) tables, runout, heat) and a dual-mass
    flywheel's friction ring (two-stage arc spring with end stop, drag, heat), all with
    ``model``; two linked thermal nodes."""
    cap = 30.0
    m = lambda: _random_model(model, rng, force=cap / 1.5)
    net = Network([
        TorqueSource("drive", input="tau"),
        Inertia("a", J=_f(rng, 0.5, 2.0), bearing_damping=_f(rng, 0.0, 0.1)),
        Clutch("clutch", m(), "com", heat=(("plate", 0.6), ("housing", 0.3)),
               mu_temperature=((20.0, 120.0, 250.0), (1.0, 0.9, 0.7)),
               mu_slip=((0.0, 2.0, 30.0), (1.0, 0.97, 0.85)), runout=(0.03, 1.0),
               drag=_f(rng, 0.01, 0.1),
               wear=WearLaw(k_w=3e-13, area=0.02, reserve=1e-3, lining=3e-3, E_a=25e3,
                            theta_crit=150.0, crit_gain=0.02)),
        Inertia("b", J=_f(rng, 0.5, 2.0)),
        Brake("brake", m(), "com2", clamp_table=((0.0, 0.4, 1.0), (0.0, 0.7, 1.0)),
              heat=(("housing", 0.8),), mu_temperature=((0.0, 100.0, 300.0), (1.1, 1.0, 0.8)),
              mu_slip=((0.0, 5.0, 50.0), (1.0, 0.95, 0.8)), runout=(0.05, 2.0),
              installed_shift=_f(rng, 0.0, 0.1)),
        DualMassFlywheel("dmf", m(), heat=(("housing", 1.0),), J_primary=_f(rng, 0.2, 1.0),
                         J_secondary=_f(rng, 0.2, 1.0), c=_f(rng, 200.0, 400.0),
                         knee=0.2, c2=_f(rng, 600.0, 900.0), stop=0.4,
                         c_stop=_f(rng, 5e3, 1e4), d=_f(rng, 0.1, 1.0),
                         drag=_f(rng, 0.01, 0.1)),
        Inertia("c", J=_f(rng, 0.2, 1.0)),
        # a cone clutch: the model's levels read as mu (~0.15), scaled by F·R_m/sin(alpha)
        ConeClutch("cone", _random_model(model, rng, force=0.15 / make_model(
                   model).static_capacity()), "fcone", heat=(("plate", 0.5),),
                   mu_slip=((0.0, 3.0, 40.0), (1.0, 0.95, 0.9)), R_m=_f(rng, 0.03, 0.08),
                   alpha=_f(rng, 6.0, 20.0), drag=_f(rng, 0.01, 0.1)),
        Inertia("d", J=_f(rng, 0.05, 0.5)),
        ThermalNode("plate", capacity=_f(rng, 2e3, 5e3), conductance=_f(rng, 1.0, 5.0),
                    link="housing", link_conductance=_f(rng, 0.5, 2.0)),
        ThermalNode("housing", capacity=_f(rng, 5e3, 1e4), conductance=_f(rng, 1.0, 5.0)),
    ], [["drive.flange", "a.a"], ["a.b", "clutch.a"], ["clutch.b", "b.a"],
        ["b.b", "brake.flange", "dmf.primary"], ["dmf.secondary", "c.a"],
        ["c.b", "cone.a"], ["cone.b", "d.a"]],
        name=f"jac_rot_{model}")
    return Case(net, {"tau": (-3.0 * cap, 3.0 * cap), "com": (0.0, 1.0),
                      "com2": (0.0, 1.0), "fcone": (-100.0, 1000.0)},
                scales={"phi_dmf": 0.05},
                near={"phi_dmf": lambda r, v: _edge(r, 0.2 if r.random() < 0.5 else 0.4,
                                                    0.05)})


def _wet_clutch(rng, model, open_pack=False):
    """Two wet clutches with ``model`` (its levels read as mu, ~0.13) on three inertias:
    one with its oil film shrinking (a flow small enough that the critical speeds are a
    few rad/s: the sampled slips cross the full, shrinking and emptied film), a mist,
    mu(slip) and mu(theta) tables, the oil node's temperature and heat to the plates and
    the oil; one flooded, at its parameter's temperature.  The pressures are above the
    kiss points (at most 3·10⁵ Pa here): a held coulomb-robust element at zero capacity
    with a speed-dependent torque across it has a wrong Jacobian in the plant (a clutch
    and a damper show it too; reported), so the open packs are :func:`_wet_open`'s."""
    mu = lambda: _random_model(model, rng, force=0.13 / make_model(model).static_capacity())
    flow = (1e-9, 1e-7)
    if open_pack:           # slips of 0.01-3 rad/s (the velocity scale): w_c below and above
        mu, flow = lambda: make_model("tanh").with_(F_c=0.12, v_t=1.0), (1e-10, 2e-8)
    pack = lambda: {"interfaces": float(rng.integers(2, 12)), "r_inner": _f(rng, 0.05, 0.07),
                    "r_outer": _f(rng, 0.08, 0.1), "piston_area": _f(rng, 3e-3, 8e-3),
                    "spring_preload": _f(rng, 300.0, 800.0),
                    "spring_rate": _f(rng, 1e4, 5e4), "stroke": _f(rng, 5e-4, 2e-3),
                    "gap": _f(rng, 1e-4, 3e-4), "drag_factor": _f(rng, 0.5, 2.0)}
    net = Network([
        TorqueSource("drive", input="tau"),
        Inertia("a", J=_f(rng, 0.1, 0.5)),
        WetClutch("wet", mu(), "p", oil="oil", heat=(("plates", 0.7), ("oil", 0.3)),
                  mu_slip=((0.0, 2.0, 30.0), (1.0, 1.05, 1.15)),
                  mu_temperature=((20.0, 120.0, 250.0), (1.0, 0.95, 0.8)),
                  flow=_f(rng, *flow), mist=_f(rng, 0.0, 0.3), **pack()),
        Inertia("b", J=_f(rng, 0.1, 0.5)),
        WetClutch("flooded", mu(), "p2", oil_temperature=_f(rng, 20.0, 120.0), **pack()),
        Inertia("c", J=_f(rng, 0.1, 0.5)),
        ThermalNode("oil", capacity=_f(rng, 2e3, 5e3), conductance=_f(rng, 1.0, 5.0)),
        ThermalNode("plates", capacity=_f(rng, 1e3, 3e3), link="oil",
                    link_conductance=_f(rng, 5.0, 20.0)),
    ], [["drive.flange", "a.a"], ["a.b", "wet.a"], ["wet.b", "b.a"], ["b.b", "flooded.a"],
        ["flooded.b", "c.a"]], name=f"jac_wet_{model}")
    if open_pack:           # below the kiss points: the packs only drag
        return Case(net, {"tau": (-200.0, 200.0), "p": (-1e5, 5e4), "p2": (0.0, 5e4)})
    return Case(net, {"tau": (-200.0, 200.0), "p": (3.1e5, 1.5e6), "p2": (3.1e5, 1e6)})


def _wet_open(rng, _model):
    """:func:`_wet_clutch` with both packs open (drag only) and tanh plates of velocity
    scale 1 rad/s, so that the sampled slips cross the film's critical speeds."""
    return _wet_clutch(rng, "tanh", open_pack=True)


def _translational_friction(rng, model):
    """A translational brake and support friction with ``model`` on two masses joined by
    a two-stage spring; a thermal node (a component of either domain)."""
    m = lambda: _random_model(model, rng)
    net = Network([
        Force("push", input="f"),
        Mass("m1", m=_f(rng, 0.5, 2.0), damping=_f(rng, 0.0, 0.2)),
        TranslationalBrake("tbrake", m(), "fn", heat=(("pad", 1.0),),
                           drag=_f(rng, 0.01, 0.1)),
        TranslationalSpringDamper("spring", c=_f(rng, 1e3, 3e3), d=_f(rng, 0.0, 2.0),
                                  knee=1e-3, c2=_f(rng, 5e3, 1e4)),
        Mass("m2", m=_f(rng, 0.5, 2.0)),
        SupportFriction("sfric", m(), mu_slip=((0.0, 0.01, 0.1), (1.0, 0.9, 0.8))),
        ThermalNode("pad", capacity=_f(rng, 100.0, 500.0), conductance=_f(rng, 0.1, 1.0)),
    ], [["push.flange", "m1.a"], ["m1.b", "tbrake.flange", "spring.a"],
        ["spring.b", "m2.a", "sfric.flange"]], name=f"jac_trans_{model}")
    return Case(net, {"f": (-4.0, 4.0), "fn": (0.0, 1.0)},
                scales={"stretch_spring": 1e-3},
                near={"stretch_spring": lambda r, v: _edge(r, 1e-3, 1e-3)})


def _springs(rng, model=None):
    """Torque source, pulsation, two-stage spring-damper, elasto-backlash and a quadratic
    load on three inertias."""
    b = _f(rng, 0.01, 0.05)
    net = Network([
        TorqueSource("drive", input="tau"),
        TorquePulsation("pulse", order=2.0, phase=_f(rng, 0.0, 1.0),
                        amplitude_table=((10.0, 50.0, 100.0), (5.0, 20.0, 8.0))),
        Inertia("a", J=_f(rng, 0.1, 1.0), bearing_damping=_f(rng, 0.01, 0.1)),
        SpringDamper("damper", c=_f(rng, 500.0, 1e3), d=_f(rng, 0.5, 2.0), knee=0.05,
                     c2=_f(rng, 2e3, 4e3)),
        Inertia("b", J=_f(rng, 0.1, 1.0)),
        ElastoBacklash("lash", b=b, c=_f(rng, 1e4, 3e4), d=_f(rng, 5.0, 50.0),
                       phi_rel0=_f(rng, -0.01, 0.01)),
        Inertia("c", J=_f(rng, 0.5, 2.0)),
        QuadraticSpeedTorque("load", tau_nominal=_f(rng, -50.0, -10.0),
                             w_nominal=_f(rng, 50.0, 150.0), signed=1.0),
    ], [["drive.flange", "pulse.flange", "a.a"], ["a.b", "damper.a"], ["damper.b", "b.a"],
        ["b.b", "lash.a"], ["lash.b", "c.a"], ["c.b", "load.flange"]], name="jac_springs")
    hb = 0.5 * b
    rel0 = net.component("lash").phi_rel0
    return Case(net, {"tau": (-100.0, 100.0)},
                scales={"phi_damper": 0.05, "phi_lash": 0.01, "angle_pulse": 1.0},
                near={"phi_damper": lambda r, v: _edge(r, 0.05, 0.05),
                      "phi_lash": lambda r, v: rel0 + _edge(r, hb, 0.01)})


def _gears(rng, model=None):
    """An ideal gear with a moving support, a planetary set, a lossy gear without losses
    and a vehicle; angle states."""
    net = Network([
        TorqueSource("drive", input="tau"),
        Inertia("a", J=_f(rng, 0.1, 1.0)),
        IdealGear("gear", ratio=_f(rng, 2.0, 4.0)),
        Inertia("housing", J=_f(rng, 1.0, 3.0)),
        SpringDamper("mount", c=_f(rng, 1e3, 2e3), d=_f(rng, 1.0, 5.0)),
        Planetary("pg", ratio=_f(rng, 1.5, 3.0)),
        LossyGear("ideal", ratio=_f(rng, 0.5, 2.0)),     # no losses: an ideal gear
        Inertia("ring", J=_f(rng, 0.1, 1.0)),
        Vehicle("car", mass=_f(rng, 800.0, 1500.0), tyre_radius=_f(rng, 0.25, 0.35),
                grade=_f(rng, -10.0, 10.0), rolling=_f(rng, 0.005, 0.02),
                cd_area=_f(rng, 0.5, 0.8), v_eps=_f(rng, 0.03, 0.1)),
    ], [["drive.flange", "a.a"], ["a.b", "gear.a"], ["gear.support", "housing.a"],
        ["housing.b", "mount.a"], ["mount.b", "ground"], ["gear.b", "pg.sun"],
        ["pg.ring", "ideal.a"], ["ideal.b", "ring.a"], ["pg.carrier", "car.flange"]],
        name="jac_gears", angles=True)
    return Case(net, {"tau": (-300.0, 300.0)}, scales={"phi_mount": 1e-2})


def _drive(rng, model=None):
    """Engine (governed, throttle from a driver model), torque converter, a launch
    controller fed forward by the engine's torque."""
    net = Network([
        Engine("engine", speeds=(0.0, 100.0, 300.0, 600.0),
               torques=(50.0, 150.0, 200.0, 120.0), throttle="driver.throttle",
               drag0=_f(rng, 1.0, 10.0), drag1=_f(rng, 0.01, 0.05), idle_speed=80.0,
               kp=_f(rng, 0.01, 0.05), ki=_f(rng, 0.05, 0.2), stall_speed=10.0),
        Inertia("eng", J=_f(rng, 0.1, 0.3)),
        TorqueConverter("conv", speed_ratio=(0.0, 0.5, 0.85), K=(12.0, 13.0, 16.0),
                        torque_ratio=(2.0, 1.5, 1.0)),
        Inertia("tur", J=_f(rng, 0.05, 0.2)),
        Vehicle("car", mass=_f(rng, 800.0, 1500.0), tyre_radius=_f(rng, 0.25, 0.35),
                rolling=0.01),
        IdealGear("fd", ratio=_f(rng, 8.0, 12.0)),
        Driver("driver", target="v_ref", kp=_f(rng, 0.1, 0.5), ki=_f(rng, 0.1, 0.5),
               radius=_f(rng, 0.25, 0.35), feedforward="ff"),
        LaunchController("launch", target="slip_ref", feedforward="engine.torque",
                         kp=_f(rng, 0.01, 0.1), ki=_f(rng, 0.1, 1.0),
                         k_ff=_f(rng, 1e-3, 5e-3), offset=_f(rng, 0.0, 0.2)),
    ], [["engine.flange", "eng.a"], ["eng.b", "conv.pump", "launch.a"],
        ["conv.turbine", "tur.a", "fd.a", "launch.b"], ["fd.b", "car.flange", "driver.a"]],
        name="jac_drive")
    return Case(net, {"v_ref": (0.0, 30.0), "ff": (0.0, 0.3), "slip_ref": (0.0, 50.0)},
                scales={"engine.governor_integral": 10.0, "launch.integral": 1.0,
                        "driver.integral": 1.0})


def _actuation(rng, model=None):
    """Signal chains into friction elements: a clutch commanded by a release system
    (with play) whose travel is a servo's position, commanded by a launch controller; a
    brake commanded by a hydraulic actuator's force."""
    net = Network([
        TorqueSource("drive", input="tau"),
        Inertia("a", J=_f(rng, 0.2, 1.0)),
        Clutch("clutch", _random_model("lugre", rng), "release.clamp_force",
               clamp_reference=_f(rng, 3e3, 5e3)),
        Inertia("b", J=_f(rng, 0.2, 1.0)),
        Brake("brake", _random_model("tanh", rng), "hyd.force",
              clamp_reference=_f(rng, 500.0, 1e3)),
        LaunchController("launch", target="slip_ref", kp=_f(rng, 1e-4, 5e-4),
                         ki=_f(rng, 1e-3, 5e-3), u_min=0.0, u_max=0.01, command_unit="m"),
        ServoActuator("servo", command="launch.command", bandwidth=_f(rng, 5.0, 20.0),
                      rate_limit=_f(rng, 0.02, 0.1)),
        ReleaseSystem("release", travel="servo.position", touch_point=1e-3,
                      hysteresis=_f(rng, 1e-4, 3e-4),
                      cushion=((0.0, 5e-4, 1e-3), (0.0, 2e3, 6e3)),
                      spring=((0.0, 2e-3, 4e-3), (0.0, 4e3, 8e3))),
        HydraulicActuator("hyd", command="p_cmd", time_constant=_f(rng, 0.01, 0.05),
                          dead_time=_f(rng, 0.005, 0.02), stages=3.0,
                          rate_limit=_f(rng, 1e6, 5e6), area=1e-3,
                          threshold_pressure=_f(rng, 1e4, 5e4)),
    ], [["drive.flange", "a.a"], ["a.b", "clutch.a", "launch.a"],
        ["clutch.b", "b.a", "launch.b", "brake.flange"]], name="jac_actuation")
    return Case(net, {"tau": (-500.0, 500.0), "slip_ref": (0.0, 5.0),
                      "p_cmd": (0.0, 1e6)},
                scales={"servo.position_state": 1e-3, "release.travel_played": 1e-3,
                        "launch.integral": 1.0, "hyd.delay1": 1e5, "hyd.delay2": 1e5,
                        "hyd.delay3": 1e5, "hyd.pressure_state": 1e5},
                near={"servo.position_state": lambda r, v: _f(r, 0.0, 5e-3),
                      "release.travel_played": lambda r, v: _f(r, 0.0, 5e-3),
                      "hyd.pressure_state": lambda r, v: _f(r, 0.0, 1e6)})


def _options(rng, model=None):
    """The other structural options: an ungoverned engine whose torque signal also drives
    a torque source, a release system without play feeding a clutch through its clamp
    table, an unsigned quadratic load, a constant pulsation, a plain (no-lash) backlash,
    actuators without dead time or rate limits, a launch controller without
    feed-forward."""
    net = Network([
        Engine("engine", speeds=(0.0, 200.0, 500.0), torques=(80.0, 180.0, 100.0),
               throttle="thr", drag0=_f(rng, 1.0, 10.0), drag1=_f(rng, 0.0, 0.05)),
        Inertia("eng", J=_f(rng, 0.1, 0.3)),
        TorqueSource("boost", input="engine.torque"),
        TorquePulsation("pulse", amplitude=_f(rng, 5.0, 20.0), order=_f(rng, 1.0, 3.0)),
        Clutch("clutch", _random_model("stribeck", rng), "release.clamp_force",
               clamp_reference=_f(rng, 3e3, 5e3),
               clamp_table=((0.0, 0.5, 1.2), (0.0, 0.8, 1.0))),
        Inertia("disc", J=_f(rng, 0.02, 0.1)),
        ElastoBacklash("shaft", b=0.0, c=_f(rng, 500.0, 2e3), d=_f(rng, 0.5, 5.0)),
        Inertia("out", J=_f(rng, 0.5, 2.0)),
        QuadraticSpeedTorque("fan", tau_nominal=_f(rng, -20.0, -5.0),
                             w_nominal=_f(rng, 50.0, 100.0)),
        LaunchController("launch", target="slip_ref", kp=_f(rng, 1e-4, 5e-4),
                         ki=_f(rng, 1e-3, 5e-3), u_min=-0.002, u_max=0.01,
                         command_unit="m"),
        ServoActuator("servo", command="launch.command", bandwidth=_f(rng, 5.0, 20.0)),
        ReleaseSystem("release", travel="servo.position", touch_point=1e-3,
                      cushion=((0.0, 5e-4, 1e-3, 2e-3), (0.0, 2e3, 5e3, 6e3))),
        HydraulicActuator("hyd", command="p_cmd", time_constant=_f(rng, 0.01, 0.05),
                          area=1e-3),
        Brake("brake", _random_model("tanh", rng), "hyd.pressure",
              clamp_reference=_f(rng, 1e5, 1e6)),
    ], [["engine.flange", "boost.flange", "pulse.flange", "eng.a"],
        ["eng.b", "clutch.a", "launch.a"], ["clutch.b", "disc.a", "launch.b", "shaft.a"],
        ["shaft.b", "out.a", "fan.flange", "brake.flange"]], name="jac_options")
    return Case(net, {"thr": (-0.1, 1.1), "slip_ref": (0.0, 5.0), "p_cmd": (0.0, 1e6)},
                scales={"servo.position_state": 1e-3, "launch.integral": 1.0,
                        "hyd.pressure_state": 1e5, "phi_shaft": 0.05, "angle_pulse": 1.0},
                near={"servo.position_state": lambda r, v: _f(r, 0.0, 5e-3),
                      "hyd.pressure_state": lambda r, v: _f(r, 0.0, 1e6)})


def _one_way_and_lossy(rng, model=None):
    """A one-way clutch driving a lossy gear (speed-dependent loss table)."""
    net = Network([
        TorqueSource("drive", input="tau"),
        Inertia("a", J=_f(rng, 0.2, 1.0)),
        OneWayClutch("owc", "com", T_slide=_f(rng, 5.0, 20.0), peak=_f(rng, 1.0, 1.5),
                     heat=(("hub", 1.0),),
                     mu_temperature=((20.0, 200.0), (1.0, 0.8))),
        Inertia("b", J=_f(rng, 0.2, 1.0)),
        LossyGear("lg", ratio=_f(rng, 2.0, 4.0),
                  loss_table=((0.0, 0.97, 0.95, 0.5, 0.4), (50.0, 0.95, 0.92, 1.0, 0.8))),
        Inertia("c", J=_f(rng, 0.5, 2.0)),
        TorqueSource("load", input="tl"),
        ThermalNode("hub", capacity=_f(rng, 500.0, 1e3)),
    ], [["drive.flange", "a.a"], ["a.b", "owc.a"], ["owc.b", "b.a"], ["b.b", "lg.a"],
        ["lg.b", "c.a", "load.flange"]], name="jac_oneway_lossy")
    return Case(net, {"tau": (-40.0, 40.0), "com": (0.0, 1.0), "tl": (-40.0, 40.0)})


def _gearbox(rng, model=None):
    """A gearbox with losses and a scheduled shift behind a coulomb-robust clutch."""
    net = Network([
        TorqueSource("drive", input="tau"),
        Inertia("a", J=_f(rng, 0.2, 1.0)),
        Clutch("clutch", _random_model("coulomb-robust", rng), "com"),
        Inertia("b", J=_f(rng, 0.05, 0.2)),
        Gearbox("gbx", ratios=(3.5, 2.1, 1.3), shifts=((5.0, 2),), final_drive=3.9,
                gear=float(rng.integers(1, 4)),
                efficiency=_f(rng, 0.9, 0.98), efficiency_reverse=_f(rng, 0.85, 0.95),
                drag_torque=_f(rng, 0.1, 1.0)),
        Vehicle("car", mass=_f(rng, 800.0, 1500.0), tyre_radius=0.3, rolling=0.01,
                cd_area=0.6),
    ], [["drive.flange", "a.a"], ["a.b", "clutch.a"], ["clutch.b", "b.a"], ["b.b", "gbx.a"],
        ["gbx.b", "car.flange"]], name="jac_gearbox")
    return Case(net, {"tau": (-200.0, 200.0), "com": (0.0, 1.0)})


def _differential(rng, model=None):
    """An open differential driven through an inertia, a band brake (capstan law) on its
    left side shaft, a dog clutch from its right side shaft to a hub."""
    net = Network([
        TorqueSource("drive", input="tau"),
        Inertia("a", J=_f(rng, 0.05, 0.3)),
        OpenDifferential("diff", ratio=_f(rng, 2.5, 4.5)),
        Inertia("left", J=_f(rng, 0.5, 2.0)),
        BandBrake("band", "fa", R=_f(rng, 0.05, 0.15), theta=_f(rng, 3.0, 6.0),
                  mu=_f(rng, 0.1, 0.4), drag=_f(rng, 0.01, 0.1), heat=(("drum", 1.0),)),
        ThermalNode("drum", capacity=_f(rng, 1e3, 3e3), conductance=_f(rng, 0.5, 2.0)),
        Inertia("right", J=_f(rng, 0.5, 2.0)),
        DogClutch("dog", "sleeve", w_max=_f(rng, 0.5, 5.0), teeth=float(rng.integers(8, 30)),
                  window=_f(rng, 0.02, 0.2), drag=_f(rng, 0.01, 0.1)),
        Inertia("hub", J=_f(rng, 0.1, 0.5)),
    ], [["drive.flange", "a.a"], ["a.b", "diff.input"], ["diff.left", "left.a"],
        ["left.b", "band.flange"], ["diff.right", "right.a"], ["right.b", "dog.a"],
        ["dog.b", "hub.a"]], name="jac_differential")
    return Case(net, {"tau": (-300.0, 300.0), "fa": (-50.0, 500.0), "sleeve": (0.0, 1.0)})


def _limited_slip(rng, model=None):
    """A limited-slip differential driven by an engine whose torque signal (a function of
    its speed and throttle) is the ramps' torque: the clamp force's partials chained
    through |T| (the ramp gain times its sign), with a drag and heat from the packs."""
    net = Network([
        Engine("engine", speeds=(0.0, 100.0, 300.0, 600.0),
               torques=(-40.0, 150.0, 200.0, 120.0), throttle="thr",
               drag0=_f(rng, 1.0, 10.0), drag1=_f(rng, 0.01, 0.05)),
        Inertia("eng", J=_f(rng, 0.1, 0.3)),
        LimitedSlipDifferential("lsd", "engine.torque", ratio=_f(rng, 2.5, 4.5),
                                mu=_f(rng, 0.08, 0.12), mu_s=0.13,
                                n_faces=float(rng.integers(2, 8)), R_m=_f(rng, 0.03, 0.06),
                                F_preload=_f(rng, 0.0, 3000.0),
                                ramp_angle=_f(rng, 15.0, 60.0), r_ramp=_f(rng, 0.03, 0.08),
                                drag=_f(rng, 0.01, 0.1), heat=(("pack", 1.0),)),
        ThermalNode("pack", capacity=_f(rng, 1e3, 3e3), conductance=_f(rng, 0.5, 2.0)),
        Inertia("left", J=_f(rng, 0.5, 2.0)),
        Inertia("right", J=_f(rng, 0.5, 2.0)),
    ], [["engine.flange", "eng.a"], ["eng.b", "lsd.input"], ["lsd.left", "left.a"],
        ["lsd.right", "right.a"]], name="jac_limited_slip")
    return Case(net, {"thr": (0.0, 1.0)})


def _synchronizer(rng, model=None):
    """A synchroniser between an idler gear and its shaft (cone, blocker, dog), driven by a
    torque, with a drag and heat into the cone ring."""
    net = Network([
        TorqueSource("drive", input="tau"),
        Inertia("gear", J=_f(rng, 0.01, 0.05)),
        Synchronizer("sync", CoulombRobust(F_c=_f(rng, 0.08, 0.12), F_s=0.13,
                                           sigma2=_f(rng, 0.0, 0.01)), "fsleeve",
                     R_m=_f(rng, 0.03, 0.06), alpha=_f(rng, 6.0, 12.0),
                     w_sync=_f(rng, 0.1, 2.0), F_block=_f(rng, 100.0, 500.0),
                     drag=_f(rng, 0.01, 0.1), heat=(("ring", 1.0),)),
        ThermalNode("ring", capacity=_f(rng, 20.0, 80.0), conductance=_f(rng, 0.5, 2.0)),
        Inertia("shaft", J=_f(rng, 0.02, 0.1)),
    ], [["drive.flange", "gear.a"], ["gear.b", "sync.a"], ["sync.b", "shaft.a"]],
        name="jac_synchronizer")
    return Case(net, {"tau": (-50.0, 50.0), "fsleeve": (-100.0, 1000.0)})


def _dog_teeth(rng, model=None):
    """A dog clutch whose engaged teeth have a free play and a contact stiffness and
    damping (the lash law at the offset from the centre of the tooth gap), between two
    inertias driven by a torque; its relative angle near a flank of some tooth gap."""
    teeth = float(rng.integers(8, 30))
    pitch = 2.0 * math.pi / teeth
    b = _f(rng, 0.005, 0.05)
    net = Network([
        TorqueSource("drive", input="tau"),
        Inertia("a", J=_f(rng, 0.05, 0.3)),
        DogClutch("dog", "sleeve", w_max=_f(rng, 0.5, 5.0), teeth=teeth,
                  window=_f(rng, 0.3, 1.0) * pitch, c_contact=_f(rng, 1e3, 1e5),
                  d_contact=_f(rng, 0.0, 20.0), backlash=b),
        Inertia("b", J=_f(rng, 0.1, 0.5)),
    ], [["drive.flange", "a.a"], ["a.b", "dog.a"], ["dog.b", "b.a"]], name="jac_dog_teeth")
    return Case(net, {"tau": (-100.0, 100.0), "sleeve": (0.0, 1.0)},
                near={"phi_dog": lambda r, v: float(r.integers(-3, 4)) * pitch
                      + _edge(r, 0.5 * b, 1e-2)})


def _mass_stop(rng, model=None):
    """Modelica's MassWithStopAndFriction on a spring, pushed by a force."""
    net = Network([
        Force("push", input="f"),
        Mass("m1", m=_f(rng, 0.5, 2.0)),
        TranslationalSpringDamper("spring", c=_f(rng, 200.0, 500.0), d=_f(rng, 0.0, 1.0)),
        MassWithStopAndFriction("stop", m=_f(rng, 0.5, 2.0), L=0.2, smin=-0.5, smax=0.5,
                                F_prop=_f(rng, 0.5, 2.0), F_Coulomb=_f(rng, 3.0, 6.0),
                                F_Stribeck=_f(rng, 5.0, 12.0), fexp=_f(rng, 1.0, 3.0)),
    ], [["push.flange", "m1.a"], ["m1.b", "spring.a"], ["spring.b", "stop.a"]],
        name="jac_mass_stop", angles=True)
    return Case(net, {"f": (-40.0, 40.0)}, scales={"stretch_spring": 0.05})


def _vehicle_around(rng, model=None):
    """A torque source reacting on a powertrain block on its mounts, a driveshaft, a tyre
    with longitudinal slip (inside its brush curve and saturated) and a vehicle."""
    r = _f(rng, 0.25, 0.35)
    net = Network([
        TorqueSource("drive", input="tau"),
        TorsionalMount("mounts", J=_f(rng, 2.0, 10.0), c=_f(rng, 1e4, 5e4),
                       d=_f(rng, 10.0, 200.0)),
        Inertia("a", J=_f(rng, 0.1, 1.0)),
        SpringDamper("shaft", c=_f(rng, 5e3, 2e4), d=_f(rng, 10.0, 100.0)),
        Tyre("tyre", radius=r, J_wheel=_f(rng, 0.5, 2.0), Fz=_f(rng, 3e3, 8e3),
             mu=_f(rng, 0.5, 1.2), C_kappa=_f(rng, 5e4, 1.5e5), sigma=_f(rng, 0.1, 0.5),
             v_eps=_f(rng, 0.05, 0.5)),
        Vehicle("car", mass=_f(rng, 800.0, 1500.0), tyre_radius=r, rolling=0.01,
                cd_area=_f(rng, 0.5, 0.8)),
    ], [["drive.flange", "a.a"], ["drive.support", "mounts.block"], ["a.b", "shaft.a"],
        ["shaft.b", "tyre.wheel"], ["tyre.body", "car.flange"]], name="jac_vehicle_around")
    return Case(net, {"tau": (-500.0, 500.0)},
                scales={"tyre.kappa": 0.1, "phi_mounts": 0.01, "phi_shaft": 0.05})


def _faults(rng, model=None):
    """Faults struck (phase 1, docs/components.md, faults): a clutch at a fraction of its
    capacity, with drag, a spring-damper losing stiffness and damping (its loss growing in t)."""
    net = Network([
        TorqueSource("drive", input="tau"),
        Inertia("a", J=_f(rng, 0.1, 1.0)),
        Clutch("clutch", _random_model("tanh", rng), "cmd", fault_time=0.0,
               fault_capacity_factor=_f(rng, 0.2, 0.8), drag=_f(rng, 1.0, 3.0),
               fault_drag=_f(rng, 1.0, 5.0)).with_values(fault_phase=1),
        Inertia("b", J=_f(rng, 0.1, 1.0)),
        SpringDamper("spring", c=_f(rng, 500.0, 1e3), d=_f(rng, 0.5, 2.0), knee=0.05,
                     c2=_f(rng, 2e3, 4e3), fault_time=0.0, fault_duration=2.0,
                     fault_stiffness_loss=_f(rng, 0.2, 0.9),
                     fault_damping_loss=_f(rng, 0.2, 0.9)).with_values(fault_phase=1),
        Inertia("c", J=_f(rng, 0.5, 2.0)),
    ], [["drive.flange", "a.a"], ["a.b", "clutch.a"], ["clutch.b", "b.a"],
        ["b.b", "spring.a"], ["spring.b", "c.a"]], name="jac_faults")
    return Case(net, {"tau": (-100.0, 100.0), "cmd": (0.0, 1.0)},
                scales={"phi_spring": 0.05},
                near={"phi_spring": lambda r, v: _edge(r, 0.05, 0.05)})


#: registered component kind -> builder of a test network that contains it.  The friction
#: builders take each friction model of the registry in turn (FRICTION_BUILDERS).
BUILDERS = {
    "inertia": _springs, "torque": _springs, "torque_pulsation": _springs,
    "spring_damper": _springs, "elasto_backlash": _springs,
    "quadratic_speed_torque": _springs,
    "ideal_gear": _gears, "planetary": _gears, "vehicle": _gears,
    "engine": _drive, "torque_converter": _drive, "driver": _drive,
    "launch_controller": _drive,
    "release_system": _actuation, "hydraulic_actuator": _actuation,
    "electromechanical_actuator": _actuation,
    "one_way_clutch": _one_way_and_lossy, "lossy_gear": _one_way_and_lossy,
    "gearbox": _gearbox,
    "clutch": _rotational_friction, "brake": _rotational_friction,
    "dual_mass_flywheel": _rotational_friction, "thermal_node": _rotational_friction,
    "mass": _translational_friction, "translational_spring_damper": _translational_friction,
    "force": _translational_friction, "translational_brake": _translational_friction,
    "support_friction": _translational_friction,
    "mass_with_stop_and_friction": _mass_stop,
    "cone_clutch": _rotational_friction, "band_brake": _differential,
    "open_differential": _differential, "dog_clutch": _differential,
    "tyre": _vehicle_around, "torsional_mount": _vehicle_around,
    "wet_clutch": _wet_clutch,
    "synchronizer": _synchronizer,
    "limited_slip_differential": _limited_slip,
}
#: networks for the other structural options of components that have a builder
EXTRA_NETWORKS = (_options, _faults, _wet_open, _dog_teeth)
#: builders that take a friction model (built once per model of the registry)
FRICTION_BUILDERS = (_rotational_friction, _translational_friction, _wet_clutch)
#: components of either domain (domain None) must appear in a network of each domain
EITHER_DOMAIN = {"thermal_node": (_rotational_friction, _translational_friction)}


def _cases():
    out = []
    for b in dict.fromkeys([*BUILDERS.values(), *EXTRA_NETWORKS]):
        if b in FRICTION_BUILDERS:
            out += [(f"{b.__name__[1:]}[{m}]", b, m) for m in FRICTION_MODELS
                    if m not in NO_JACOBIAN]
        else:
            out.append((b.__name__[1:], b, None))
    return out


CASES = _cases()


# ------------------------------------------------------------------ states
_UNIT_SCALE = {"rad": 0.05, "m": 1e-3, "°C": 30.0, "J": 1.0, "Pa": 1e5, "N": 1e3, "-": 1.0}


def _discrete(plan) -> set:
    """Indices of discrete states (modes, lock flags, a mass's stop, a dog's clashes): what
    each component declares (:meth:`Component.discrete_states`)."""
    return {plan.state_index[(c.name, key)] for c in plan.net.components
            for key in c.discrete_states()}


def _reduced(plan, p):
    """``(N, M⁻¹)`` of the parameter vector ``p`` (node speeds ``w = N·v``)."""
    asm = plan.asm
    nn, nv = asm.n_nodes, asm.n_v
    N = p[plan.off_N:plan.off_N + nn * nv].reshape(nn, nv)
    Minv = p[plan.off_Minv:plan.off_Minv + nv * nv].reshape(nv, nv)
    return N, Minv


def _set_slips(plan, p, v, targets):
    """Move the speeds ``v`` (least change in the metric of M) so that element slips take
    ``targets`` (element name -> slip)."""
    if not targets:
        return v
    N, Minv = _reduced(plan, p)
    B = np.array([plan.slips[name] @ N for name in targets])
    r = np.array(list(targets.values())) - B @ v
    S = B @ Minv @ B.T
    return v + Minv @ B.T @ np.linalg.lstsq(S, r, rcond=None)[0]


def _exact_zero(plan, p, v, names):
    """``v`` with the slips of the elements ``names`` at 0 to the last bit where they are
    differences of independent speeds (a clutch between two inertias, a brake on one):
    each is solved for a speed of its own, in turn until all hold.  The plant's Jacobian
    of a locked element assumes zero slip (a slip of round-off size leaves ``|τ·w|`` of
    the heat rows a slope the plant does not write)."""
    N, _ = _reduced(plan, p)
    pick = {}
    for name in names:
        b = plan.slips[name] @ N
        order = [k for k in np.argsort(-np.abs(b), kind="stable")
                 if b[k] != 0.0 and k not in pick.values()]
        if order:
            pick[name] = order[0]
    for _ in range(len(pick) + 1):      # each solved for its own coordinate, in turn
        for name, k in pick.items():
            b = plan.slips[name] @ N
            rest = sum(b[j] * v[j] for j in range(v.size) if j != k)
            v[k] = -rest / b[k]
    return v


#: friction laws whose force reads the stick torque while the plant does not lock them
#: (coulomb-robust stuck but not locked: "held"; karnopp inside its window)
STICK_LAWS = ("coulomb-robust", "karnopp")


def _sample(plan, system, case, rng, stick=False):
    """A random state and input vector of ``system`` (see the module docstring).

    Regimes of the friction elements: ``locked`` (lockable elements, slip exactly 0),
    ``slide`` (the slip down to 1e-2 velocity scales, either sign; karnopp outside its
    window), and with ``stick`` the regimes whose force is the clipped stick torque:
    ``held`` (coulomb-robust stuck, not locked) and ``window`` (karnopp, |w| < DV)."""
    p = system.params
    y = system.y0.copy()
    nv = plan.asm.n_v
    labels = system.state_names
    units = system.state_units
    own = {c.name: c for c in case.net.components}
    fes = [own[c.name] for c in plan.fes]
    V = min([_velocity_scale(c.model) for c in fes] or [1.0])
    u = np.array([_f(rng, *case.inputs[n]) for n in system.input_names])
    # speeds: a common speed (or rest) and spreads of all sizes
    w0 = rng.uniform(-20.0, 20.0) if rng.random() < 0.8 else 0.0
    v = np.array([w0 + 10.0 ** rng.uniform(-2.0, 1.0) * rng.choice([-1.0, 1.0])
                  for _ in range(nv)])
    for i in range(nv, plan.n):
        lab = labels[i]
        if lab in case.near and rng.random() < 0.5:
            y[i] = case.near[lab](rng, y[i])
        elif lab in case.scales:
            y[i] = case.scales[lab] * rng.uniform(-3.0, 3.0)
        elif units[i] == "°C":
            y[i] = rng.uniform(20.0, 280.0)
        else:
            y[i] = _UNIT_SCALE.get(units[i], 1.0) * rng.uniform(-1.0, 1.0)
    regime, targets = {}, {}
    for c in fes:
        law = c.model.name
        vs = _velocity_scale(c.model)
        sign = 1.0 if law == "one-way-clutch" else rng.choice([-1.0, 1.0])
        r = rng.random()
        if getattr(c, "lockable", False) and r < 0.3:
            regime[c.name] = "locked"
        elif stick and law == "coulomb-robust" and r < 0.7:
            regime[c.name] = "held"
        elif stick and law == "karnopp" and r < 0.7:
            regime[c.name] = "window"
            targets[c.name] = sign * c.model.DV * rng.uniform(0.05, 0.95)
        else:
            regime[c.name] = "slide"
            if law == "karnopp":
                targets[c.name] = sign * c.model.DV * (1.0 + 10.0 ** rng.uniform(-3.0, 1.0))
            elif r < 0.8:
                targets[c.name] = sign * vs * 10.0 ** rng.uniform(-2.0, 0.5)
    N, _ = _reduced(plan, p)
    v0 = v
    for _ in range(len(fes) + 1):
        v = _set_slips(plan, p, v0, targets)
        still = [n for n, r in regime.items() if r in ("locked", "held")]
        v = _set_slips(plan, p, v, dict.fromkeys(still, 0.0))
        v = _exact_zero(plan, p, v, still)
        w = N @ v
        # a freewheel that the projections left turning backwards locks instead
        back = [c.name for c in fes if c.model.name == "one-way-clutch"
                and regime[c.name] == "slide" and plan.slips[c.name] @ w <= 0.0]
        if not back:
            break
        for name in back:
            regime[name] = "locked"
            targets.pop(name, None)
    y[:nv] = v
    for c in fes:
        s = float(plan.slips[c.name] @ w)
        law = c.model.name
        idx = {k: plan.state_index[(c.name, k)] for k, _l, _u in c.state_layout()}
        rg = regime[c.name]
        if "locked" in idx:
            y[idx["locked"]] = 1.0 if rg == "locked" else 0.0
        if law in ("coulomb-robust", "lossy-gear"):
            y[idx["z0"]] = 0.0 if rg in ("locked", "held") else (1.0 if s >= 0.0 else -1.0)
        elif law == "one-way-clutch":
            y[idx["z0"]] = 0.0 if rg == "locked" else 1.0
        elif law == "synchronizer":      # locked: the dog in or the cone stuck
            y[idx["z0"]] = 0.0 if rg == "locked" else (1.0 if s >= 0.0 else -1.0)
            y[idx["z1"]] = float(rng.integers(0, 2)) if rg == "locked" else 0.0
        elif law == "dog-clutch":        # engaged (0) when locked, else open (1)
            y[idx["z0"]] = 0.0 if rg == "locked" else 1.0
            if "locked" not in idx:      # elastic teeth: engaged or open, never locked
                y[idx["z0"]] = float(rng.integers(0, 2))
            y[idx["z1"]] = float(rng.integers(0, 5))
        elif law == "mass-with-stop":
            lo, hi = c.model.s_low, c.model.s_high
            if rg == "locked":
                at = rng.choice([-1.0, 0.0, 1.0])
                y[idx["z0"]], y[idx["z1"]] = 0.0, at
                y[idx["z2"]] = hi if at > 0 else (lo if at < 0 else rng.uniform(lo, hi))
            else:
                y[idx["z0"]], y[idx["z1"]] = (1.0 if s >= 0.0 else -1.0), 0.0
                y[idx["z2"]] = rng.uniform(lo, hi)
        elif c.model.n_states:
            zs = np.abs(c.model.sliding_state(10.0 * _velocity_scale(c.model)))
            for k in range(c.model.n_states):
                y[idx[f"z{k}"]] = zs[k] * rng.uniform(-1.5, 1.5)
    return y, u, regime, V


def _near_clip(plan, system, y, u, regime, rng):
    """For a held element commanded by an external input: the command that puts its
    capacity 0.1-10 % above or below its stick torque (the clip of the stick torque)."""
    out_names = plan.output_names
    outputs = plan.module.FUNCTIONS["outputs"]
    for c in plan.fes:      # (the command's name is structure: the plan's own will do)
        if regime.get(c.name) not in ("held", "window") or c.command not in system.input_names:
            continue
        k = system.input_names.index(c.command)
        eff = plan.domain.effort
        i_fe = out_names.index(f"{eff}_stick_{c.name}")
        i_cap = out_names.index(f"capacity_{c.name}")
        factor = 1.0 + rng.choice([-1.0, 1.0]) * 10.0 ** rng.uniform(-3.0, -1.0)
        for _ in range(4):
            out = np.zeros(len(out_names))
            outputs(0.0, y, u, system.params, out)
            fe, cap = abs(out[i_fe]), out[i_cap]
            if cap <= 0.0 or fe == 0.0:
                break
            u[k] = min(max(u[k] * fe * factor / cap, 1e-3), 1.0)
    return u


# ------------------------------------------------------------------ the comparison
def _scales(plan, system, case, V):
    """The scale ``S_j`` of every state (see the module docstring)."""
    own = {c.name: c for c in case.net.components}
    S = np.empty(plan.n)
    nv = plan.asm.n_v
    S[:nv] = V
    labels, units = system.state_names, system.state_units
    for i in range(nv, plan.n):
        S[i] = case.scales.get(labels[i], _UNIT_SCALE.get(units[i], 1.0))
    for c in (own[c.name] for c in plan.fes):
        if c.model.n_states and c.model.name not in ("coulomb-robust", "one-way-clutch",
                                                      "lossy-gear", "mass-with-stop",
                                                      "dog-clutch", "synchronizer"):
            zs = np.abs(c.model.sliding_state(10.0 * _velocity_scale(c.model)))
            for k in range(c.model.n_states):
                S[plan.state_index[(c.name, f"z{k}")]] = max(zs[k], 1e-12)
        if c.model.name in ("mass-with-stop", "dog-clutch"):
            S[plan.state_index[(c.name, "z2")]] = 1e-2
    return S


def _compare(system, y, u, t, S, discrete, nv):
    """``(J, C, ok, skipped, what)``: the plant's Jacobian, the central differences, the
    mask of entries compared and passed, the mask skipped (kinks), a description."""
    tag, p, n = system.tag, system.params, y.size

    def f(yy):
        dy = np.zeros(n)
        call_rhs(tag, t, yy, u, p, dy)
        return dy

    J = np.full((n, n), np.nan)
    call_jac(tag, t, y.copy(), u, p, J)
    f0 = f(y)
    # the accelerations a lock projection cancels (to round-off of their size)
    free = y.copy()
    free[[j for j in discrete if system.state_names[j].endswith(".locked")]] = 0.0
    a_free = np.max(np.abs(f(free)[:nv]), initial=0.0)
    C, Dp, Dm, E = (np.zeros((n, n)) for _ in range(4))
    hs = np.ones(n)
    fmax = np.abs(f0)
    fmax[:nv] = np.maximum(fmax[:nv], a_free)
    for j in range(n):
        if j in discrete:
            continue
        hj = STEP * S[j]
        h = (y[j] + hj) - y[j]              # the step actually taken
        hs[j] = h
        fk = {}
        for k in (-2, -1, 1, 2):
            yy = y.copy()
            yy[j] = y[j] + k * h
            fk[k] = f(yy)
            fmax = np.maximum(fmax, np.abs(fk[k]))
        c1 = (fk[1] - fk[-1]) / (2.0 * h)
        c2 = (fk[2] - fk[-2]) / (4.0 * h)
        C[:, j] = (4.0 * c1 - c2) / 3.0
        E[:, j] = np.abs(c1 - c2)
        Dp[:, j] = (-3.0 * f0 + 4.0 * fk[1] - fk[2]) / (2.0 * h)
        Dm[:, j] = (3.0 * f0 - 4.0 * fk[-1] + fk[-2]) / (2.0 * h)
    cols = np.array([j not in discrete for j in range(n)])
    R = np.max(np.abs(C) * S[None, :], axis=1)
    # the accelerations share one unit: a row that cancels to nearly 0 (a locked part)
    # keeps the round-off of the others' scale
    R[:nv] = np.maximum(R[:nv], 1e-8 * R[:nv].max(initial=0.0))
    T = R[:, None] / S[None, :]
    rnd = ROUND * np.finfo(float).eps * fmax[:, None] / np.abs(hs)[None, :]
    # an acceleration that a held element's stick force cancels keeps, in the plant's own
    # Jacobian, the round-off of the partials it cancels: at most the size of the plant's
    # largest value (a stiffness, a mass matrix entry) times eps
    rnd[:nv] = np.maximum(rnd[:nv], ROUND * np.finfo(float).eps
                          * float(np.max(np.abs(p), initial=0.0)))
    smooth = (np.abs(Dp - Dm) <= KINK * (np.abs(C) + T) + rnd) & cols[None, :]
    ok = np.abs(J - C) <= RTOL * (np.abs(C) + T) + rnd + NOISE * E
    return J, C, T, ok, smooth


def _on_heat_kink(plan, system, regime):
    """Entries on a kink by construction: the heat ``|τ·w|`` of a locked or held element
    (its slip is 0) in the rows of its thermal nodes and its wear, by the speeds of its
    slip.  Not counted among the skipped."""
    out = np.zeros((plan.n, plan.n), dtype=bool)
    N, _ = _reduced(plan, system.params)
    for c in plan.fes:
        if regime.get(c.name) not in ("locked", "held"):
            continue
        rows = [plan.state_index[(node, "theta")] for node, _share in c.heat]
        if (c.name, "wear") in plan.state_index:
            rows.append(plan.state_index[(c.name, "wear")])
        cols = np.flatnonzero(plan.slips[c.name] @ N)
        out[np.ix_(rows, cols)] = True
    return out


def _check_case(builder, model, points=POINTS, stick=False):
    """Compare the Jacobian at ``points`` random points of the network ``builder`` makes
    with ``model``; ``(stats, failures)``."""
    seed = zlib.crc32(f"{builder.__name__}:{model}:{stick}".encode())
    rng = np.random.default_rng(seed)
    case = builder(rng, model)
    plan = case.net.compile()
    discrete = _discrete(plan)
    stats = {"points": 0, "entries": 0, "skipped": 0, "where": Counter()}
    fails = []
    for k in range(points):
        case = builder(rng, model) if k else case
        system = plan.system(case.net.components, name=case.net.name)
        assert has_jacobian(system.tag)
        y, u, regime, V = _sample(plan, system, case, rng, stick=stick)
        if rng.random() < 0.5:
            u = _near_clip(plan, system, y, u, regime, rng)
        S = _scales(plan, system, case, V)
        t = float(rng.uniform(0.0, 1.0))
        J, C, T, ok, smooth = _compare(system, y, u, t, S, discrete, plan.asm.n_v)
        assert np.all(np.isfinite(J)), f"{case.net.name}: non-finite Jacobian at y={y}"
        dy = np.zeros(len(y))
        call_rhs(system.tag, t, y, u, system.params, dy)
        for j in discrete:
            # a discrete state changes only at events: its derivative and its row are 0
            assert dy[j] == 0.0 and not np.any(J[j] != 0.0), (
                f"{case.net.name}: discrete state {system.state_names[j]} moves between "
                f"events (derivative {dy[j]:g})")
            bad = np.flatnonzero(J[:, j] != 0.0)
            assert not bad.size, (f"{case.net.name}: column of discrete state "
                                  f"{system.state_names[j]} is not 0 in rows "
                                  f"{[system.state_names[i] for i in bad]}")
        relevant = (np.abs(J) + np.abs(C) > 0.0) & ~np.isin(np.arange(J.shape[1]),
                                                            list(discrete))[None, :]
        relevant &= ~_on_heat_kink(plan, system, regime)
        stats["points"] += 1
        stats["entries"] += int(relevant.sum())
        stats["skipped"] += int((relevant & ~smooth).sum())
        for i, j in np.argwhere(relevant & ~smooth):
            stats["where"][(system.state_names[i], system.state_names[j])] += 1
        bad = np.argwhere(smooth & ~ok)
        for i, j in bad:
            fails.append(f"d {system.state_names[i]} / d {system.state_names[j]}: jac "
                         f"{J[i, j]:.9g}, differences {C[i, j]:.9g} (typical {T[i, j]:.3g}); "
                         f"point {k}, regimes {regime}, u {dict(zip(system.input_names, u))}")
    return stats, fails


@pytest.mark.parametrize(("label", "builder", "model"), CASES, ids=[c[0] for c in CASES])
def test_generated_jacobian_matches_finite_differences(label, builder, model):
    """Every entry of ``jac`` (accelerations, component and friction states, thermal
    nodes, wear, energy accounts) against differences of ``rhs`` at POINTS random points
    (see the module docstring); discrete states' columns exactly 0; few kinks skipped."""
    stats, fails = _check_case(builder, model)
    assert not fails, f"{label}: {len(fails)} wrong entries:\n" + "\n".join(fails[:20])
    share = stats["skipped"] / max(stats["entries"], 1)
    assert share <= MAX_SKIPPED, (f"{label}: {share:.1%} of {stats['entries']} entries "
                                  "straddle a kink (more than allowed): the points are drawn "
                                  "too close to the nonsmooth sets")


STICK_CASES = [(f"{b.__name__[1:]}[{m}]", b, m) for b in FRICTION_BUILDERS for m in STICK_LAWS]


@pytest.mark.parametrize(("label", "builder", "model"), STICK_CASES,
                         ids=[c[0] for c in STICK_CASES])
def test_jacobian_where_the_force_is_the_clipped_stick_torque(label, builder, model):
    """The regimes whose force is the stick torque, clipped to the capacity (points drawn
    with the capacity 0.1-10 % above or below it), for the two laws that have them."""
    _stats, fails = _check_case(builder, model, stick=True)
    assert not fails, f"{label}: {len(fails)} wrong entries:\n" + "\n".join(fails[:20])


def _held_without_capacity(rng, model):
    """Two clutches in series, the first in parallel with a damper (a speed-dependent
    torque across it), both commands often at or below 0: held (stuck, not locked) at zero
    capacity, where the force, the stick torque clipped to ±0, is 0 whatever the stick
    torque (found by the wet clutch's builder: the partial d F / d F_e was 1 there)."""
    m = lambda: _random_model(model, rng, force=20.0)
    net = Network([TorqueSource("drive", input="tau"), Inertia("a", J=_f(rng, 0.5, 2.0)),
                   Clutch("clutch", m(), "com"), Damper("damp", d=_f(rng, 0.5, 2.0)),
                   Inertia("b", J=_f(rng, 0.5, 2.0)), Clutch("c2", m(), "com2"),
                   Inertia("c", J=_f(rng, 0.5, 2.0))],
                  [["drive.flange", "a.a"], ["a.b", "clutch.a", "damp.a"],
                   ["clutch.b", "damp.b", "b.a"], ["b.b", "c2.a"], ["c2.b", "c.a"]],
                  name=f"jac_held_{model}")
    return Case(net, {"tau": (-60.0, 60.0), "com": (-1.0, 1.0), "com2": (-1.0, 0.3)})


@pytest.mark.parametrize("model", STICK_LAWS)
def test_jacobian_of_elements_held_without_capacity(model):
    """The clipped stick torque at zero capacity (the clip's interval [-0, 0]): its partial
    by the stick torque is 0.  Before: 36 wrong entries at 30 points (coulomb-robust),
    d omega_c / d omega_a 0.46 where the differences give 0."""
    _stats, fails = _check_case(_held_without_capacity, model, stick=True)
    assert not fails, f"{len(fails)} wrong entries:\n" + "\n".join(fails[:20])


def test_every_registered_component_has_a_builder():
    """A component registered in COMPONENTS without a test network here fails, by name."""
    # the sources, dampers, speed laws, eddy brakes, gap and gearbox with lash of issue 34
    # have their networks in test_elements.py, walked there with the same kind of check
    from test_elements import BUILDERS as ELEMENT_BUILDERS
    elsewhere = {k.split(" ")[0] for k in ELEMENT_BUILDERS}
    missing = sorted(set(COMPONENTS) - set(BUILDERS) - elsewhere)
    assert not missing, (
        f"registered network component(s) {', '.join(missing)} have no Jacobian test "
        "network: add each to BUILDERS in tests/network/test_component_jacobians.py (an "
        "existing builder whose network gains the component, or a new one; see the module "
        "docstring)")
    stale = sorted(set(BUILDERS) - set(COMPONENTS))
    assert not stale, f"BUILDERS lists kinds that are not registered: {', '.join(stale)}"


@pytest.mark.parametrize("kind", sorted(BUILDERS))
def test_each_builder_network_holds_its_component(kind):
    """The network a builder makes holds the component it is listed for (in each domain
    for a component of either domain), with 2 to 4 nodes that carry inertia."""
    builders = EITHER_DOMAIN.get(kind, (BUILDERS[kind],))
    domains = set()
    for b in builders:
        model = FRICTION_MODELS[0] if b in FRICTION_BUILDERS else None
        net = b(np.random.default_rng(0), model).net
        assert kind in {c.kind for c in net.components}, (kind, b.__name__)
        domains.add(net.domain.name)
        asm = net.assemble()
        bodies = sum(1 for owners in asm.J_owner if owners)
        assert 2 <= bodies <= 4, (b.__name__, bodies)
    if COMPONENTS[kind].domain is None:
        assert domains == {"rotational", "translational"}, (kind, domains)


@pytest.mark.parametrize("model", NO_JACOBIAN)
def test_models_without_a_jacobian_register_none(model):
    """coulomb-naive's force jumps at zero slip: its plants register no exact Jacobian
    (the integrators difference them), so there is nothing to compare."""
    case = _rotational_friction(np.random.default_rng(0), model)
    assert not has_jacobian(case.net.build().tag)
