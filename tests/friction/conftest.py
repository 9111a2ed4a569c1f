"""Shared fixtures and small simulation harnesses for the friction tests."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from clutchsim._jit import jit
from clutchsim.friction import MODELS, friction_events, friction_force, friction_reset, make_model

ALL_MODELS = tuple(MODELS)


@pytest.fixture(params=ALL_MODELS)
def model_name(request) -> str:
    return request.param


@pytest.fixture
def default_model(model_name):
    return make_model(model_name)


def _force(model, z, v, F_e=0.0, scale=1.0):
    """Compiled force and state derivative of ``model`` (always the same numba types)."""
    z = np.ascontiguousarray(z, dtype=np.float64).reshape(model.n_states)
    dz = np.zeros(model.n_states)
    F = friction_force(model.code, model.pack(), z, float(v), float(F_e), float(scale), dz)
    return F, dz


@jit
def drive_velocity(code, p, z0, v, dt, scale, reset_on_reversal):
    """Explicit Euler under an imposed velocity history ``v`` (sampled every ``dt``).

    Returns the force and the states after each step. With ``reset_on_reversal``
    the model's event 0 reset is applied whenever ``v`` changes sign.
    """
    n = v.shape[0]
    m = z0.shape[0]
    z = z0.copy()
    dz = np.zeros(m)
    F = np.empty(n)
    Z = np.empty((n, m))
    for i in range(n):
        if reset_on_reversal and i > 0 and v[i] * v[i - 1] <= 0.0 and v[i] != v[i - 1]:
            friction_reset(code, p, z, v[i], 0.0, scale, 0)
        F[i] = friction_force(code, p, z, v[i], 0.0, scale, dz)
        for j in range(m):
            z[j] += dt * dz[j]
            Z[i, j] = z[j]
    return F, Z


def _drive(model, v, dt, z0=None, scale=1.0, reset_on_reversal=False):
    z0 = model.initial_state() if z0 is None else np.asarray(z0, dtype=np.float64)
    return drive_velocity(
        model.code, model.pack(), z0, np.ascontiguousarray(v, dtype=np.float64), float(dt),
        float(scale), bool(reset_on_reversal),
    )  # fmt: skip


def _simulate_mass(model, u, t_stops, m=1.0, rtol=1e-9, atol=1e-13, max_step=1e-2,
                   max_events=5000, v_eps=1e-10, y0=None):  # fmt: skip
    """Test rig: mass ``m`` pushed by ``u(t)`` against ``model`` (from rest, or
    from ``y0 = [x, v, z...]``); the stick force is ``F_e = u``.

    States ``[x, v, z...]``; scipy Radau with the model's events located by
    scipy (terminal) and the compiled reset applied before restarting.
    Returns the states at the times ``t_stops`` and the number of located events.
    After a restart on an event's zero the event is inert until ``|v| >= v_eps``
    in the direction of the acceleration (a dead band against Zeno restarts on
    numerical noise once the body has settled).
    """
    code, p = model.code, model.pack()
    ns = model.n_states
    dz = np.zeros(ns)
    g = np.zeros(max(model.n_events, 1))
    directions = model.event_directions()

    def rhs(t, y):
        ut = float(u(t))
        F = friction_force(code, p, np.ascontiguousarray(y[2:]), float(y[1]), ut, 1.0, dz)
        out = np.empty_like(y)
        out[0] = y[1]
        out[1] = (ut - F) / m
        out[2:] = dz
        return out

    guard = {"k": -1, "s": 1.0, "armed": True}

    def make_event(k):
        def event(t, y):
            v = float(y[1])
            if guard["k"] == k and not guard["armed"]:
                # dead band after a restart on this event's zero: inert until the
                # velocity has left zero (|v| >= v_eps) on the side it is heading to
                if guard["s"] * v < v_eps:
                    return guard["s"] * v_eps
                guard["armed"] = True
            friction_events(code, p, np.ascontiguousarray(y[2:]), v, float(u(t)), 1.0, g)
            return g[k]

        event.terminal = True
        event.direction = float(directions[k])
        return event

    events = [make_event(k) for k in range(model.n_events)] or None
    if y0 is None:
        y = np.concatenate(([0.0, 0.0], model.initial_state()))
    else:
        y = np.array(y0, dtype=np.float64)
    t = 0.0
    out = []
    n_events = 0
    for t_stop in t_stops:
        while t < t_stop:
            sol = solve_ivp(rhs, (t, t_stop), y, method="Radau", rtol=rtol, atol=atol,
                            max_step=max_step, events=events)  # fmt: skip
            assert sol.status >= 0, sol.message
            if sol.status == 1:
                k = next(i for i, te in enumerate(sol.t_events) if len(te))
                t = float(sol.t_events[k][0])
                y = sol.y_events[k][0].copy()
                z = np.ascontiguousarray(y[2:])
                ret = friction_reset(code, p, z, float(y[1]), float(u(t)), 1.0, k)
                y[2:] = z
                if ret == 2:  # stuck: the plant sets the relative velocity to zero
                    y[1] = 0.0
                a = rhs(t, y)[1]
                guard.update(k=k, s=1.0 if a >= 0.0 else -1.0, armed=False)
                n_events += 1
                assert n_events < max_events, "too many events"
            else:
                t = float(sol.t[-1])
                y = sol.y[:, -1].copy()
        out.append(y.copy())
    return np.array(out), n_events


@pytest.fixture(scope="session")
def force():
    """``force(model, z, v, F_e=0, scale=1) -> (F, dz)`` through the compiled dispatcher."""
    return _force


@pytest.fixture(scope="session")
def drive():
    """``drive(model, v, dt, z0=None, scale=1, reset_on_reversal=False) -> (F, Z)``."""
    return _drive


@pytest.fixture(scope="session")
def simulate_mass():
    """``simulate_mass(model, u, t_stops, ...) -> (states at t_stops, n_events)``."""
    return _simulate_mass
