"""Compiled integrators against problems with exact or trusted reference solutions."""

import math

import numpy as np
import pytest
from _vdp_reference import radau_van_der_pol

from clutchsim.core import Sine, SolverOptions, simulate
from clutchsim.core.reference_problems import oscillator, riccati, van_der_pol

TIGHT = SolverOptions(rtol=1e-10, atol=1e-12)


@pytest.mark.parametrize("solver", ["dopri5", "rodas4", "ros34pw2"])
def test_harmonic_oscillator_matches_cosine(solver):
    res = simulate(oscillator(omega=2.0), (0.0, 10.0), {"F": 0.0}, solver=solver, options=TIGHT)
    assert res.status == "completed"
    err = np.abs(res["x"] - np.cos(2.0 * res.t)).max()
    assert err < 1e-8
    # energy of the undamped oscillator is conserved along the whole trajectory
    energy = 0.5 * res["v"] ** 2 + 0.5 * 4.0 * res["x"] ** 2
    assert np.ptp(energy) < 1e-8


@pytest.mark.parametrize("solver", ["dopri5", "rodas4", "ros34pw2"])
def test_damped_oscillator_forced_by_sine_against_closed_form(solver):
    # x'' + 2ζω x' + ω² x = A sin(Ω t) from rest: compare with the exact solution computed
    # by superposing the particular solution and the free response.
    w, z, A, W = 3.0, 0.2, 1.5, 1.7
    sysm = oscillator(omega=w, zeta=z, x0=0.0, v0=0.0)
    res = simulate(sysm, (0.0, 8.0), {"F": Sine(A, W / (2 * math.pi))}, solver=solver,
                   options=TIGHT)
    denom = (w * w - W * W) ** 2 + (2 * z * w * W) ** 2
    a = A * (w * w - W * W) / denom            # x_p = a sin + b cos
    b = -A * 2 * z * w * W / denom
    wd = w * math.sqrt(1 - z * z)
    c1 = -b                                    # x(0) = 0
    c2 = (-(a * W) + z * w * c1) / wd          # x'(0) = 0
    t = res.t
    exact = a * np.sin(W * t) + b * np.cos(W * t) + np.exp(-z * w * t) * (
        c1 * np.cos(wd * t) + c2 * np.sin(wd * t))
    assert np.abs(res["x"] - exact).max() < 1e-8


def test_stiff_van_der_pol_matches_scipy_radau_at_tight_tolerance():
    mu, t_end = 100.0, 150.0
    res = simulate(van_der_pol(mu), (0.0, t_end), solver="rodas4",
                   options=SolverOptions(rtol=1e-10, atol=1e-10))
    assert res.status == "completed"
    ref = radau_van_der_pol(mu, t_end)
    # compare on the slow manifold (away from the fast jumps, where timing errors blow up)
    x_ref = ref.sol(res.t)[0]
    slow = np.abs(res["y"]) < 1.0
    assert slow.sum() > 100
    assert np.abs(res["x"][slow] - x_ref[slow]).max() < 1e-5
    # a stiff problem: the implicit method needs far fewer steps than the explicit one
    explicit = simulate(van_der_pol(mu), (0.0, 20.0), solver="dopri5",
                        options=SolverOptions(rtol=1e-6, atol=1e-8))
    implicit = simulate(van_der_pol(mu), (0.0, 20.0), solver="rodas4",
                        options=SolverOptions(rtol=1e-6, atol=1e-8))
    assert implicit.stats.steps * 5 < explicit.stats.steps


@pytest.mark.parametrize("solver, order", [("dopri5", 5), ("rodas4", 4), ("ros34pw2", 3),
                                           ("rodas5p", 5)])
def test_order_of_convergence(solver, order):
    """Fixed steps (tolerances too loose to reject any step) on y' = -2ty², whose exact
    solution is 1/(1+t²): the global error must fall with the method's order."""
    errors, hs = [], []
    for n in (32, 64, 128, 256):
        h = 4.0 / n
        opts = SolverOptions(rtol=1e3, atol=1e3, h0=h, h_max=h)
        res = simulate(riccati(), (0.0, 4.0), solver=solver, options=opts)
        assert res.stats.steps == n and res.stats.rejected == 0
        errors.append(np.abs(res["y"] - 1.0 / (1.0 + res.t ** 2)).max())
        hs.append(h)
    slope = np.polyfit(np.log(hs), np.log(errors), 1)[0]
    assert abs(slope - order) < 0.5, slope


@pytest.mark.parametrize("solver", ["dopri5", "rodas4", "ros34pw2", "rodas5p"])
def test_dense_output_grid_matches_exact_solution(solver):
    res = simulate(oscillator(omega=2.0), (0.0, 5.0), {"F": 0.0}, solver=solver,
                   options=SolverOptions(rtol=1e-9, atol=1e-12, dt_out=0.01))
    assert np.allclose(np.diff(res.t), 0.01, atol=1e-12)
    assert res.t[-1] == pytest.approx(5.0)
    # the continuous extension is accurate between the steps too
    assert np.abs(res["x"] - np.cos(2.0 * res.t)).max() < 1e-6
