"""The EMPS benchmark plant: a prismatic drive with friction under position control.

Janot, Gautier, Brunot (2019) describe an electro-mechanical positioning system (DC motor,
ball screw, load) run in closed loop.  Its rigid-body model, with the cascade position /
velocity controller of the benchmark, is::

    u      = sat_{±u_max}( kv·(kp·(q_ref − q) − w) ) + u_d      [V]
    M·ddq  = gtau·u + F_d − F(dq) − offset                      [N]
    tau_v·dw/dt = dq − w        (w = dq when tau_v = 0)

with ``q`` the load position [m], ``q_ref`` the reference position (the plant's input),
``u_d`` a measured disturbance added to the controller output [V] and ``F_d`` a measured
disturbance force [N] (both inputs; 0 when the record has none),
``gtau`` the drive gain [N/V] and ``F`` the force of any friction model of
:mod:`clutchsim.friction` (transmitted in the direction of ``dq``).  The benchmark's
controller works on a sampled (1 kHz) position and a difference quotient for the velocity;
here it is continuous.  The velocity the controller uses may lag the true one by a first-order
filter of time constant ``tau_v`` (a stand-in for the sampling and difference-quotient delay
of about 1.5 ms; 0 = none).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .._jit import jit
from ..core import System, register_system
from ..core.status import Action
from ..friction import friction_events, friction_force, friction_reset, smooth_at_events
from ..friction.base import RESET_NONE, RESET_STUCK, FrictionModel

_CONTINUE, _STATE_CHANGED = int(Action.CONTINUE), int(Action.STATE_CHANGED)
_PASS = int(Action.PASS)

__all__ = ["EMPS_HEADER", "EMPS_PARAMS", "EMPSPlant", "make_emps"]

_M, _GTAU, _KP, _KV, _UMAX, _OFFSET, _CODE, _NZ, _NEV, _TAUV = range(10)
EMPS_HEADER = 10
_NS = 3   # states before the friction states: q, dq, w
#: plant parameters that a fit may adjust, with their index in ``p``
EMPS_PARAMS = {"M": _M, "offset": _OFFSET, "gtau": _GTAU, "tau_v": _TAUV}


class EMPSPlant(NamedTuple):
    """Tag type of the EMPS closed-loop plant."""

    k: int = 0


@jit
def _voltage(y, u, p):
    w = y[2] if p[_TAUV] > 0.0 else y[1]
    c = p[_KV] * (p[_KP] * (u[0] - y[0]) - w)
    if c > p[_UMAX]:
        return p[_UMAX] + u[1]
    if c < -p[_UMAX]:
        return -p[_UMAX] + u[1]
    return c + u[1]


@jit
def _emps_rhs(t, y, u, p, dy):
    nz = int(p[_NZ])
    f_e = p[_GTAU] * _voltage(y, u, p) + u[2] - p[_OFFSET]
    f = friction_force(int(p[_CODE]), p[EMPS_HEADER:], y[_NS:_NS + nz], y[1], f_e, 1.0,
                       dy[_NS:_NS + nz])
    dy[0] = y[1]
    dy[1] = (f_e - f) / p[_M]
    dy[2] = (y[1] - y[2]) / p[_TAUV] if p[_TAUV] > 0.0 else 0.0


@jit
def _emps_events(t, y, u, p, g):
    nz = int(p[_NZ])
    f_e = p[_GTAU] * _voltage(y, u, p) + u[2] - p[_OFFSET]
    friction_events(int(p[_CODE]), p[EMPS_HEADER:], y[_NS:_NS + nz], y[1], f_e, 1.0, g)


@jit
def _emps_reset(t, y, u, p, k):
    nz = int(p[_NZ])
    f_e = p[_GTAU] * _voltage(y, u, p) + u[2] - p[_OFFSET]
    code = int(p[_CODE])
    action = friction_reset(code, p[EMPS_HEADER:], y[_NS:_NS + nz], y[1], f_e, 1.0, k)
    if action == RESET_STUCK:
        y[1] = 0.0
        if p[_TAUV] <= 0.0:
            y[2] = 0.0
    if action != RESET_NONE:
        return _STATE_CHANGED
    return _PASS if smooth_at_events(code) else _CONTINUE


@jit
def _emps_outputs(t, y, u, p, out):
    nz = int(p[_NZ])
    dz = np.empty(nz)
    v = _voltage(y, u, p)
    f_e = p[_GTAU] * v + u[2] - p[_OFFSET]
    out[0] = friction_force(int(p[_CODE]), p[EMPS_HEADER:], y[_NS:_NS + nz], y[1], f_e, 1.0, dz)
    out[1] = v
    out[2] = p[_GTAU] * v


register_system(EMPSPlant, rhs=_emps_rhs, events=_emps_events, reset=_emps_reset,
                outputs=_emps_outputs)


def make_emps(model: FrictionModel, *, M: float = 95.11, gtau: float = 35.1507,
              kp: float = 160.18, kv: float = 243.45, u_max: float = 10.0,
              offset: float = 0.0, tau_v: float = 0.0, q0: float = 0.0, dq0: float = 0.0,
              z0=None) -> System:
    """Build the EMPS closed-loop plant around a friction model.

    Parameters
    ----------
    model : FrictionModel
        Friction of the drive (translational units: N, m, m/s).
    M : float
        Moving mass seen at the load [kg], > 0 (benchmark IDIM value 95.11 kg).
    gtau : float
        Drive gain [N/V], > 0 (35.1507 in the data file).
    kp : float
        Position-loop gain [1/s] (160.18 in the data file).
    kv : float
        Velocity-loop gain [V·s/m] (243.45 in the data file).
    u_max : float
        Voltage saturation [V], > 0 (10 V).
    offset : float
        Constant load force [N] (benchmark IDIM value −3.165 N).
    tau_v : float
        Lag of the controller's velocity estimate [s], >= 0 (0: the true velocity).
    q0, dq0 : float
        Initial position [m] and velocity [m/s].
    z0 : array_like, optional
        Initial friction states (default: the model's ``initial_state()`` when ``dq0 = 0``,
        its steady sliding state ``sliding_state(dq0)`` otherwise).

    Returns
    -------
    System
        Input ``q_ref`` [m]; states ``q``, ``dq``, ``w`` (the controller's velocity) and the
        friction states; outputs the
        friction force ``F`` [N], the voltage ``u`` [V] and the motor force ``F_motor`` [N].
    """
    if not isinstance(model, FrictionModel):
        raise TypeError(f"model must be a clutchsim friction model, got {type(model).__name__}")
    for name, value in (("M", M), ("gtau", gtau), ("u_max", u_max)):
        if not (np.isfinite(value) and value > 0):
            raise ValueError(f"EMPS plant: {name} = {value!r} must be finite and > 0")
    if not (np.isfinite(tau_v) and tau_v >= 0):
        raise ValueError(f"EMPS plant: tau_v = {tau_v!r} s must be finite and >= 0")
    for name, value in (("kp", kp), ("kv", kv), ("offset", offset), ("q0", q0), ("dq0", dq0)):
        if not np.isfinite(value):
            raise ValueError(f"EMPS plant: {name} = {value!r} must be finite")
    if z0 is not None:
        z_init = np.asarray(z0, dtype=float).ravel()
    else:   # a drive that starts moving starts sliding (a switching model's mode follows dq0)
        z_init = model.sliding_state(dq0) if dq0 != 0.0 else model.initial_state()
    if z_init.size != model.n_states:
        raise ValueError(f"EMPS plant: z0 has {z_init.size} entries; {model.name} has "
                         f"{model.n_states} states")
    header = np.zeros(EMPS_HEADER)
    header[[_M, _GTAU, _KP, _KV, _UMAX, _OFFSET]] = M, gtau, kp, kv, u_max, offset
    header[[_CODE, _NZ, _NEV, _TAUV]] = model.code, model.n_states, model.n_events, tau_v
    return System(
        EMPSPlant(), np.concatenate([header, model.pack()]),
        np.concatenate([[q0, dq0, dq0], z_init]),
        ("q", "dq", "w") + tuple(model.state_names()),
        ("m", "m/s", "m/s") + tuple(model.state_units("translational")),
        input_names=("q_ref", "u_d", "F_d"), input_units=("m", "V", "N"),
        output_names=("F", "u", "F_motor"), output_units=("N", "V", "N"),
        event_names=tuple(f"{model.name}: {e}" for e in model.event_names()),
        event_directions=tuple(int(d) for d in model.event_directions()),
        name=f"EMPS closed loop with {model.name}",
        metadata={"model": model.name, "plant": "emps", "M": M, "gtau": gtau, "kp": kp,
                  "kv": kv, "u_max": u_max, "offset": offset, "tau_v": tau_v},
    )
