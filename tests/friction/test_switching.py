"""Switching models: naive Coulomb chatter, robust hybrid stick/slip, Karnopp."""

from __future__ import annotations

import numpy as np
import pytest

from clutchsim.friction import friction_events, friction_reset, make_model


def test_coulomb_naive_force_law(force):
    model = make_model("coulomb-naive")
    assert force(model, [], 0.3, F_e=5.0, scale=2.0)[0] == 2.0 * model.F_c
    assert force(model, [], -1e-300, F_e=5.0)[0] == -model.F_c
    assert force(model, [], 0.0, F_e=0.7)[0] == 0.7  # stick: balances the load
    assert force(model, [], 0.0, F_e=-5.0, scale=0.5)[0] == -0.5 * model.F_s  # clipped


def test_coulomb_naive_declares_monitoring_event_only():
    model = make_model("coulomb-naive")
    assert model.n_events == 1 and model.event_directions().tolist() == [0]
    g = np.zeros(1)
    friction_events(model.code, model.pack(), np.zeros(0), -0.25, 0.0, 1.0, g)
    assert g[0] == -0.25
    assert friction_reset(model.code, model.pack(), np.zeros(0), 0.0, 0.0, 1.0, 0) == 0


def test_coulomb_naive_chatters_at_lock_up(force):
    """The seed's complaint: a sliding mass that should lock up chatters instead.

    1 kg, load 0.5 N < F_s, initial 0.1 m/s: it stops at t = 0.2 s and should
    stay. Stepping the naive law, v flips sign at (almost) every step afterwards:
    the zero crossings the core's chatter detection counts.
    """
    model = make_model("coulomb-naive")
    dt, u, v = 1e-4, 0.5, 0.1
    crossings = 0
    for i in range(5000):  # 0.5 s
        F = force(model, [], v, F_e=u)[0]
        v_new = v + dt * (u - F)
        if i * dt > 0.25 and v_new * v < 0.0:
            crossings += 1
        v = v_new
    assert crossings > 1000  # ~ one per step after lock-up
    assert abs(v) < 1e-3  # it does not escape, it only chatters


def test_coulomb_robust_slides_to_a_stop_and_sticks(simulate_mass):
    """1 kg at 1 m/s, load 0.5 N, F_c = 1 N: stops at t = 2 s after 1 m, stays stuck."""
    model = make_model("coulomb-robust")
    states, n_events = simulate_mass(model, lambda t: 0.5, [1.0, 3.0], y0=[0.0, 1.0, 1.0])
    _x1, v1, mode1 = states[0]
    x3, v3, mode3 = states[1]
    assert mode1 == 1.0 and v1 == pytest.approx(0.5, rel=1e-9)
    assert mode3 == 0.0 and v3 == 0.0
    assert x3 == pytest.approx(1.0, rel=1e-9)
    assert n_events == 1


def test_coulomb_robust_breaks_away_at_static_level(simulate_mass):
    """Ramp u = t from stuck: break-away at u = F_s = 1.5 N, then a = (t - F_c)/m."""
    model = make_model("coulomb-robust")
    states, n_events = simulate_mass(model, lambda t: t, [1.4, 2.5])
    assert states[0].tolist() == [0.0, 0.0, 0.0]  # still stuck at 1.4 N
    _x, v, mode = states[1]
    assert mode == 1.0 and n_events == 1
    assert v == pytest.approx(2.5**2 / 2 - 2.5 + 0.375, rel=1e-7)  # = 1.0


def test_coulomb_robust_reverses_when_load_exceeds_capacity(simulate_mass):
    """Sliding forward at 1 m/s against u = -2 N (> F_s): stop at 1/3 s, then slide back."""
    model = make_model("coulomb-robust")
    states, n_events = simulate_mass(model, lambda t: -2.0, [4 / 3], y0=[0.0, 1.0, 1.0])
    _x, v, mode = states[0]
    assert mode == -1.0 and n_events == 1
    assert v == pytest.approx(-1.0, rel=1e-7)


def test_coulomb_robust_events_only_fire_in_their_mode():
    model = make_model("coulomb-robust")
    p, g = model.pack(), np.zeros(2)
    friction_events(model.code, p, np.array([0.0]), 0.0, 2.0, 1.0, g)  # stuck, overloaded
    assert g[0] == 1.0 and g[1] == pytest.approx(1.5 - 2.0)
    friction_events(model.code, p, np.array([-1.0]), -0.2, 0.0, 1.0, g)  # sliding backward
    assert g[0] == pytest.approx(0.2) and g[1] == 1.0
    z = np.array([0.0])
    assert friction_reset(model.code, p, z, 0.0, -2.0, 1.0, 1) == 3 and z[0] == -1.0
    z = np.array([1.0])
    assert friction_reset(model.code, p, z, 0.0, 1.0, 1.0, 0) == 2 and z[0] == 0.0
    z = np.array([1.0])
    assert friction_reset(model.code, p, z, 0.0, -3.0, 1.0, 0) == 1 and z[0] == -1.0
    # capacity follows scale: at scale 0.5 a 1 N load breaks away (0.75 N capacity)
    friction_events(model.code, p, np.array([0.0]), 0.0, 1.0, 0.5, g)
    assert g[1] < 0.0


def test_coulomb_robust_stuck_force_is_the_stick_force(force):
    model = make_model("coulomb-robust")
    assert force(model, [0.0], 0.0, F_e=1.2)[0] == 1.2
    assert force(model, [0.0], 0.0, F_e=-1.2, scale=0.5)[0] == -0.75  # clipped to capacity
    assert force(model, [1.0], -1e-6, F_e=0.0)[0] == pytest.approx(1.0)  # mode rules, not v


def test_karnopp_window(force):
    model = make_model("karnopp")
    DV = model.DV
    assert force(model, [], 0.5 * DV, F_e=0.9)[0] == 0.9
    assert force(model, [], -0.5 * DV, F_e=4.0, scale=2.0)[0] == 2.0 * model.F_s
    F, _ = force(model, [], -DV, F_e=0.9)
    assert F == pytest.approx(-model.F_c - model.sigma2 * DV)


def test_karnopp_holds_a_mass_without_chatter(force):
    """Same lock-up as the naive test: Karnopp keeps v inside its window for good."""
    model = make_model("karnopp")
    dt, u, v = 1e-4, 0.5, 0.1
    history = []
    for _ in range(5000):
        F = force(model, [], v, F_e=u)[0]
        v = v + dt * (u - F)  # inside the window F = F_e = u, so a = 0 exactly
        history.append(v)
    tail = np.array(history[3000:])
    assert np.all(np.abs(tail) < model.DV)
    assert np.ptp(tail) == 0.0
