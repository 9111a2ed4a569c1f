"""The compiled integrators and scipy's solve_ivp integrate the same system alike."""

import numpy as np
import pytest

from clutchsim.core import Sine, SolverOptions, Step, simulate
from clutchsim.core.reference_problems import ball, oscillator


@pytest.mark.parametrize("reference", ["scipy-radau", "scipy-lsoda", "scipy-rk45"])
@pytest.mark.parametrize("solver", ["dopri5", "rodas4", "ros34pw2"])
def test_forced_oscillator_agrees_with_scipy(solver, reference):
    sysm = oscillator(omega=3.0, zeta=0.1, x0=0.2, v0=0.0)
    inputs = {"F": Sine(1.0, 0.7) + Step(1.5, height=0.5)}
    opts = SolverOptions(rtol=1e-9, atol=1e-11, dt_out=0.05)
    a = simulate(sysm, (0.0, 4.0), inputs, solver=solver, options=opts)
    b = simulate(sysm, (0.0, 4.0), inputs, solver=reference, options=opts)
    assert a.status == b.status == "completed"
    grid = np.round(np.arange(0.0, 4.0 + 1e-9, 0.05), 12)
    xa = a["x"][np.isin(np.round(a.t, 12), grid)]
    xb = b["x"][np.isin(np.round(b.t, 12), grid)]
    assert xa.shape == xb.shape == grid.shape
    assert np.abs(xa - xb).max() < 1e-6


@pytest.mark.parametrize("solver", ["dopri5", "rodas4", "ros34pw2"])
def test_event_times_agree_with_scipy(solver):
    opts = SolverOptions(rtol=1e-10, atol=1e-12)
    a = simulate(ball(), (0.0, 2.5), solver=solver, options=opts)
    b = simulate(ball(), (0.0, 2.5), solver="scipy-radau", options=opts)
    ta = np.array([e.t for e in a.events])
    tb = np.array([e.t for e in b.events])
    assert ta.shape == tb.shape
    assert np.abs(ta - tb).max() < 1e-7
