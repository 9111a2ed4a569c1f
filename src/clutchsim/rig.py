"""The friction test rig: a mass (or an inertia) on a friction contact.

The body is driven either by a force/torque input ``F_app(t)`` or by an imposed velocity
``v(t)``.  In the force-driven rig it can also be tied by a spring ``k`` to a point that
moves at ``pull_speed`` (the classic stick-slip set-up: ``y(t) = y0 + V·t``)::

    m·dv/dt = F_app(t) + k·(y(t) − x) − F,      dx/dt = v

where ``F`` is the friction force of any model of :mod:`clutchsim.friction` (the contact
transmits ``F`` in the direction of the slip ``v``; the body sees ``−F``).  The rotational
twin is the same equations with an inertia, a torque and angles.

The rig is a *plant*; the benchmark protocols of :mod:`clutchsim.benchmarks` are input
signals applied to it.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ._jit import jit
from .core import Signal, SolverOptions, System, register_system, simulate
from .core.status import Action
from .friction import (
    MODELS,
    domain_problem,
    friction_events,
    friction_force,
    friction_jacobian,
    friction_reset,
    smooth_at_events,
)
from .friction.base import RESET_NONE, RESET_STUCK, FrictionModel

__all__ = ["RIG_HEADER", "make_rig", "run_rig"]

# parameter-vector layout
_DRIVE, _MASS, _K, _V_PULL, _Y0, _CODE, _NZ, _NEV = range(8)
RIG_HEADER = 8
_FORCE, _VELOCITY = 0.0, 1.0
_CONTINUE, _STATE_CHANGED = int(Action.CONTINUE), int(Action.STATE_CHANGED)
_PASS = int(Action.PASS)


class FrictionRig(NamedTuple):
    """Tag type of the rig plant; :data:`RIG_TAGS` holds one subtype per friction model."""

    k: int = 0


@jit(inline="always")
def _rig_forces(t, y, u, p, dz, code, Jz=None, dF=None):
    """Friction force F, external force F_ext and spring force; writes dz.

    Inlined (like ``_rig_rhs``) so that the right-hand side is one function: every call
    with array arguments would cost two atomic reference-count operations per array.

    ``code`` is the friction model's code, a compile-time constant (see RIG_TAGS). With
    arrays ``Jz`` and ``dF`` (``_rig_jac``) the model's partial derivatives are written too
    (:func:`~clutchsim.friction.friction_jacobian`); the right-hand side passes None, and
    the compiler drops that branch (its machine code is the same as without it)."""
    nz = int(p[_NZ])
    pf = p[RIG_HEADER:]
    scale = u[1]
    if p[_DRIVE] == _FORCE:
        x, v, z = y[0], y[1], y[2:2 + nz]
        spring = p[_K] * (p[_Y0] + p[_V_PULL] * t - x) if p[_K] != 0.0 else 0.0
        f_ext = u[0] + spring
    else:
        x, v, z = y[0], u[0], y[1:1 + nz]
        spring = 0.0
        f_ext = 0.0
    if Jz is None:
        f = friction_force(code, pf, z, v, f_ext, scale, dz)
    else:
        f = friction_jacobian(code, pf, z, v, f_ext, scale, dz, Jz, dF)
    return f, f_ext, spring


@jit(inline="always")
def _rig_rhs(t, y, u, p, dy, code):
    nz = int(p[_NZ])
    if p[_DRIVE] == _FORCE:
        f, f_ext, _ = _rig_forces(t, y, u, p, dy[2:2 + nz], code)
        dy[0] = y[1]
        dy[1] = (f_ext - f) / p[_MASS]
    else:
        _rig_forces(t, y, u, p, dy[1:1 + nz], code)
        dy[0] = u[0]


@jit
def _rig_jac(t, y, u, p, J, code):
    """Exact Jacobian ``J[i, j] = d dy_i/d y_j`` at fixed inputs, from the model's partials.

    Force drive (``y = [x, v, z...]``): ``F_ext = u_0 + k·(y_0 + V·t - x)`` is the stick
    force of the switching models, so ``d dv/dx = -k·(1 - dF/dF_ext)/m``; ``d dv/dv =
    -(dF/dv)/m``, ``d dv/dz = -(dF/dz)/m``, and the state rows are the model's ``Jz``.
    Velocity drive (``y = [x, z...]``): ``v`` is an input, only the state block remains."""
    nz = int(p[_NZ])
    dz = np.empty(nz)
    Jz = np.empty((nz, nz + 1))
    dF = np.empty(nz + 3)
    _rig_forces(t, y, u, p, dz, code, Jz, dF)
    J[:, :] = 0.0
    if p[_DRIVE] == _FORCE:
        m = p[_MASS]
        J[0, 1] = 1.0
        J[1, 0] = -p[_K] * (1.0 - dF[nz + 1]) / m
        J[1, 1] = -dF[nz] / m
        for i in range(nz):
            J[1, 2 + i] = -dF[i] / m
            J[2 + i, 1] = Jz[i, nz]
            J[2 + i, 2:] = Jz[i, :nz]
    else:
        for i in range(nz):
            J[1 + i, 1:] = Jz[i, :nz]


@jit
def _rig_events(t, y, u, p, g, code):
    nz = int(p[_NZ])
    pf = p[RIG_HEADER:]
    if p[_DRIVE] == _FORCE:
        spring = p[_K] * (p[_Y0] + p[_V_PULL] * t - y[0]) if p[_K] != 0.0 else 0.0
        friction_events(code, pf, y[2:2 + nz], y[1], u[0] + spring, u[1], g)
    else:
        friction_events(code, pf, y[1:1 + nz], u[0], 0.0, u[1], g)


@jit
def _rig_reset(t, y, u, p, k, code):
    nz = int(p[_NZ])
    pf = p[RIG_HEADER:]
    if p[_DRIVE] == _FORCE:
        spring = p[_K] * (p[_Y0] + p[_V_PULL] * t - y[0]) if p[_K] != 0.0 else 0.0
        action = friction_reset(code, pf, y[2:2 + nz], y[1], u[0] + spring, u[1], k)
        if action == RESET_STUCK:
            y[1] = 0.0   # stuck: the body's slip velocity is exactly zero
    else:
        action = friction_reset(code, pf, y[1:1 + nz], u[0], 0.0, u[1], k)
    if action != RESET_NONE:
        return _STATE_CHANGED
    return _PASS if smooth_at_events(code) else _CONTINUE


@jit
def _rig_outputs(t, y, u, p, out, code):
    # the rates of the friction states are outputs too, so the model writes its dz into
    # them (an allocation per output row cost ~0.1 µs, 10 % of a LuGre run at dt_out 10 ms)
    nz = int(p[_NZ])
    f, f_ext, spring = _rig_forces(t, y, u, p, out[4:4 + nz], code)
    v = y[1] if p[_DRIVE] == _FORCE else u[0]
    out[0] = f
    out[1] = f_ext
    out[2] = spring
    out[3] = f * v


def _model_kernels(code: int, label: str) -> dict:
    """The rig's five compiled functions for friction model ``code``, with the code folded.

    Each is a closure over the constant ``code`` compiled under its own name, so that the
    compiler folds the friction dispatch into it (the right-hand side inlines the model's
    kernel) and numba's cache keeps one entry per model (the cache is keyed by the
    function's qualified name).  The integrators receive them as function values and are
    compiled once for every model (they used to be compiled once per model, ~30 s each)."""
    def rhs(t, y, u, p, dy):
        _rig_rhs(t, y, u, p, dy, code)

    def events(t, y, u, p, g):
        _rig_events(t, y, u, p, g, code)

    def reset(t, y, u, p, k):
        return _rig_reset(t, y, u, p, k, code)

    def outputs(t, y, u, p, out):
        _rig_outputs(t, y, u, p, out, code)

    def jac(t, y, u, p, J):
        _rig_jac(t, y, u, p, J, code)

    out = {}
    for kind, fn in (("rhs", rhs), ("events", events), ("reset", reset),
                     ("outputs", outputs), ("jac", jac)):
        fn.__name__ = fn.__qualname__ = f"rig_{kind}_{label}"
        out[kind] = jit(fn)
    return out


def _register_rig_tags() -> dict[int, type]:
    """One tag type per friction model, registered with that model's own compiled
    functions (:func:`_model_kernels`, the exact Jacobian ``_rig_jac`` among them).

    The classes live in this module under their own names so that numba's cache can
    refer to them."""
    tags = {}
    for cls in MODELS.values():
        label = cls.name.replace("-", "_")
        name = f"FrictionRig_{label}"
        tag = type(name, (FrictionRig,), {"__module__": __name__, "__qualname__": name})
        globals()[name] = tag
        register_system(tag, **_model_kernels(int(cls.code), label))
        tags[int(cls.code)] = tag
    return tags


#: tag type of the rig for each friction model code
RIG_TAGS = _register_rig_tags()

_UNITS = {
    "translational": {"x": ("x", "m"), "v": ("v", "m/s"), "F": ("F", "N"), "m": "kg",
                      "power": "W", "k": "N/m"},
    "rotational": {"x": ("theta", "rad"), "v": ("omega", "rad/s"), "F": ("T", "N·m"),
                   "m": "kg·m²", "power": "W", "k": "N·m/rad"},
}


def _rate_unit(unit: str) -> str:
    """Unit of the rate of a state in ``unit``."""
    return "1/s" if unit in ("-", "") else f"{unit}/s"


def make_rig(model: FrictionModel, *, domain: str = "translational", drive: str = "force",
             mass: float = 1.0, spring: float = 0.0, pull_speed: float = 0.0,
             spring_offset: float = 0.0, x0: float = 0.0, v0: float = 0.0,
             z0=None) -> System:
    """Build the rig plant around a friction model.

    Parameters
    ----------
    model : FrictionModel
        Any model of :mod:`clutchsim.friction`.  One built by
        :func:`~clutchsim.friction.make_model` from a parameter set of the other domain
        (e.g. the translational LuGre set on a rotational rig) is refused (ValueError).
    domain : {"translational", "rotational"}
        Units of the signals (m, m/s, N or rad, rad/s, N·m).
    drive : {"force", "velocity"}
        Force/torque input ``force`` [N or N·m], or imposed velocity input ``v``.
    mass : float
        Mass [kg] or inertia [kg·m²] (> 0; force drive only).
    spring : float
        Spring stiffness k [N/m or N·m/rad] to the moving point (>= 0; 0: no spring).
    pull_speed : float
        Speed V of the spring's free end [m/s or rad/s].
    spring_offset : float
        Position y0 of the spring's free end at t = 0 [m or rad].
    x0, v0 : float
        Initial position and velocity (v0 only for the force drive).
    z0 : array_like, optional
        Initial friction states.  Default: the model's ``initial_state()`` (at rest,
        unloaded; a switching model stuck) when ``v0 = 0``, and its steady sliding state
        ``sliding_state(v0)`` when the force-driven body starts moving (a switching model
        then starts in the sliding mode of the direction of ``v0``).

    Returns
    -------
    System
        Inputs ``force`` (or ``v``) and ``scale`` (capacity multiplier, usually 1);
        outputs the friction force, the external force, the spring force, the
        friction power and the rate ``d<state>/dt`` of each friction state.
    """
    if not isinstance(model, FrictionModel):
        raise TypeError(f"model must be a clutchsim friction model, got {type(model).__name__}")
    if domain not in _UNITS:
        raise ValueError(f"domain = {domain!r} must be 'translational' or 'rotational'")
    if drive not in ("force", "velocity"):
        raise ValueError(f"drive = {drive!r} must be 'force' or 'velocity'")
    problem = domain_problem(model, domain, f"the {domain} rig",
                             choose_set="--params SET (or run the rig in the set's domain, "
                             "--domain / domain=)", give_params="--set KEY=VALUE")
    if problem:
        raise ValueError(problem)
    for name, value in (("mass", mass), ("spring", spring), ("pull_speed", pull_speed),
                        ("spring_offset", spring_offset), ("x0", x0), ("v0", v0)):
        if not np.isfinite(value):
            raise ValueError(f"rig: {name} = {value!r} must be finite")
    if mass <= 0:
        raise ValueError(f"rig: mass = {mass!r} {_UNITS[domain]['m']} must be > 0")
    if spring < 0:
        raise ValueError(f"rig: spring = {spring!r} {_UNITS[domain]['k']} must be >= 0")
    if drive == "velocity" and (spring or pull_speed):
        raise ValueError("rig: a spring is only available with the force drive")
    units = _UNITS[domain]
    if z0 is not None:
        z_init = np.asarray(z0, dtype=float).ravel()
    elif drive == "force" and v0 != 0.0:
        # a body that starts moving starts sliding: a switching model's mode (and any
        # other model's states) follow the initial velocity, not the stuck rest state
        z_init = model.sliding_state(v0)
    else:
        z_init = model.initial_state()
    if z_init.size != model.n_states:
        raise ValueError(f"rig: z0 has {z_init.size} entries; {model.name} has "
                         f"{model.n_states} states ({', '.join(model.state_names())})")
    header = np.zeros(RIG_HEADER)
    header[_DRIVE] = _FORCE if drive == "force" else _VELOCITY
    header[[_MASS, _K, _V_PULL, _Y0]] = mass, spring, pull_speed, spring_offset
    header[[_CODE, _NZ, _NEV]] = model.code, model.n_states, model.n_events
    p = np.concatenate([header, model.pack()])
    x_name, x_unit = units["x"]
    v_name, v_unit = units["v"]
    f_name, f_unit = units["F"]
    z_names = tuple(model.state_names())
    z_units = tuple(model.state_units(domain))
    if drive == "force":
        states = (x_name, v_name) + z_names
        sunits = (x_unit, v_unit) + z_units
        y0 = np.concatenate([[x0, v0], z_init])
        inputs, iunits = ("force" if domain == "translational" else "torque", "scale"), \
            (f_unit, "-")
    else:
        states = (x_name,) + z_names
        sunits = (x_unit,) + z_units
        y0 = np.concatenate([[x0], z_init])
        inputs, iunits = (v_name, "scale"), (v_unit, "-")
    return System(
        RIG_TAGS[model.code](), p, y0, states, sunits, input_names=inputs, input_units=iunits,
        output_names=(f_name, f"{f_name}_ext", f"{f_name}_spring", "friction power")
        + tuple(f"d{z}/dt" for z in z_names),
        output_units=(f_unit, f_unit, f_unit, units["power"])
        + tuple(_rate_unit(zu) for zu in z_units),
        event_names=tuple(f"{model.name}: {e}" for e in model.event_names()),
        event_directions=tuple(int(d) for d in model.event_directions()),
        name=f"{domain} rig with {model.name}",
        metadata={"model": model.name, "domain": domain, "drive": drive, "mass": mass,
                  "spring": spring, "pull_speed": pull_speed},
    )


def run_rig(model: FrictionModel, t_end: float, *, force: Signal | float | None = None,
            velocity: Signal | float | None = None, scale: Signal | float = 1.0,
            domain: str = "translational", mass: float = 1.0, spring: float = 0.0,
            pull_speed: float = 0.0, solver: str = "rodas4",
            options: SolverOptions | None = None, **rig_kw):
    """Build the rig for ``model`` and simulate it from 0 to ``t_end`` [s].

    Give exactly one of ``force`` (force/torque drive; 0 is allowed with a spring) or
    ``velocity`` (imposed velocity).  Returns a :class:`~clutchsim.core.Result`.
    """
    if (force is None) == (velocity is None):
        raise ValueError("run_rig: give exactly one of force= or velocity=")
    drive = "force" if force is not None else "velocity"
    system = make_rig(model, domain=domain, drive=drive, mass=mass, spring=spring,
                      pull_speed=pull_speed, **rig_kw)
    signal = force if force is not None else velocity
    return simulate(system, (0.0, t_end), {system.input_names[0]: signal, "scale": scale},
                    solver=solver, options=options)
