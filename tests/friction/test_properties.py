"""Hypothesis properties: bounded LuGre bristles, dissipation over closed cycles."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from clutchsim.friction import make_model

PASSIVE = ("tanh", "stribeck", "rotational-friction", "dahl", "lugre", "elastoplastic", "gms",
           "mykhailevych2020")  # fmt: skip


@settings(max_examples=40, deadline=None)
@given(
    pieces=st.lists(st.floats(-0.05, 0.05), min_size=1, max_size=12),
    z0_frac=st.floats(-1.0, 1.0),
    F_s=st.floats(1.0, 3.0),
)
def test_lugre_bristle_stays_bounded(drive, pieces, z0_frac, F_s):
    """|z| <= F_s/sigma0 for all time when it starts inside (explicit Euler, dt·sigma0·|v|/g <= 0.5)."""
    model = make_model("lugre", F_s=F_s)
    bound = model.F_s / model.sigma0
    dt = 1e-4
    v = np.repeat(np.asarray(pieces), 200)
    _, Z = drive(model, v, dt, z0=[z0_frac * bound])
    assert np.max(np.abs(Z)) <= bound * (1.0 + 1e-12)
    # and after a long enough piece the bristle reaches its steady deflection
    if abs(pieces[-1]) > 1e-2:  # >= 20 time constants g/(sigma0·|v|) in the last piece
        assert Z[-1, 0] == pytest.approx(model.sliding_state(pieces[-1])[0], rel=1e-6)


@pytest.mark.parametrize("name", PASSIVE)
@settings(max_examples=8, deadline=None)
@given(amplitude=st.floats(1e-4, 0.05), frequency=st.floats(2.0, 10.0))
def test_dissipation_over_closed_velocity_cycle(drive, name, amplitude, frequency):
    """Imposed v = A·sin(2πft): the work ∮F·v dt over the third cycle is positive."""
    model = make_model(name)
    dt = 2e-5
    n = round(1.0 / (frequency * dt))
    t = np.arange(3 * n) * dt
    v = amplitude * np.sin(2 * np.pi * frequency * t)
    F, _ = drive(model, v, dt, reset_on_reversal=(model.n_events > 0))
    work = float(np.sum(F[2 * n :] * v[2 * n :]) * dt)
    assert work > 0.0
    # scale multiplies every force term: the work scales with it
    F_half, _ = drive(model, v, dt, scale=0.5, reset_on_reversal=(model.n_events > 0))
    assert float(np.sum(F_half[2 * n :] * v[2 * n :]) * dt) == pytest.approx(0.5 * work, rel=1e-9)


def test_lugre_presliding_is_elastic_for_small_motion(drive):
    """Small closed displacement loop (1 % of F_c/sigma0): z follows x, F ≈ sigma0·x."""
    model = make_model("lugre")
    dt, amp = 1e-5, 1e-7
    t = np.arange(20000) * dt
    v = amp * 2 * np.pi * np.cos(2 * np.pi * t)  # x(t) = amp·sin(2πt)
    F, Z = drive(model, v, dt)
    x = np.cumsum(v) * dt
    assert np.max(np.abs(Z[:, 0] - x)) < 0.01 * amp
    assert np.max(np.abs(F - model.sigma0 * x)) < 0.05 * model.sigma0 * amp
