"""Model (6)'s pre-sliding damping c_ps: kernels, drift and reset policies, stick-slip.

The seed's drift and reset-policy tests (tests/friction/test_mykhailevych.py) run here on
the damped set ``mykhailevych2020_translational_damped`` (k_v = 0.4, c_ps = 100 N·s/m).
"""

import importlib.util
import math
from pathlib import Path

import numpy as np
import pytest

from clutchsim.benchmarks.stick_slip import run_stick_slip
from clutchsim.friction import make_model
from clutchsim.friction.mykhailevych2020 import (
    mykhailevych2020_force,
    mykhailevych2020_jacobian,
)

_spec = importlib.util.spec_from_file_location(
    "_friction_conftest", Path(__file__).resolve().parents[1] / "friction" / "conftest.py")
_conftest = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_conftest)
simulate_mass = _conftest._simulate_mass


@pytest.fixture
def damped():
    return make_model("mykhailevych2020", "mykhailevych2020_translational_damped")


def _m2(t):
    return 0.5 + 0.4 * math.sin(2 * math.pi * t)


def test_default_is_the_seed_model_and_the_term_vanishes_in_sliding(damped):
    seed = make_model("mykhailevych2020", k_v=0.4)
    assert seed.c_ps == 0.0
    dz = np.zeros(1)
    for phi in (0.0, 0.5e-5, 3e-5):
        for v in (-0.02, 1e-4, 0.3):
            z = np.array([phi])
            f0 = mykhailevych2020_force(seed.pack(), z, v, 0.0, 1.0, dz)
            f1 = mykhailevych2020_force(damped.pack(), z, v, 0.0, 1.0, dz)
            sech2 = 1.0 / math.cosh(phi / damped.phi0) ** 2
            assert f1 - f0 == pytest.approx(100.0 * v * sech2, rel=1e-9, abs=1e-12)
    z = np.array([50 * damped.phi0])                  # gross sliding
    assert mykhailevych2020_force(damped.pack(), z, 0.3, 0.0, 1.0, dz) == \
        mykhailevych2020_force(seed.pack(), z, 0.3, 0.0, 1.0, dz)
    with pytest.raises(ValueError, match="c_ps"):
        make_model("mykhailevych2020", c_ps=-1.0)


@pytest.mark.parametrize(("phi", "v", "scale"), [(0.3e-5, 2e-3, 1.0), (-2e-5, -0.03, 0.7),
                                                 (1e-5, 0.0, 1.3)])
def test_jacobian_kernel_matches_differences(damped, phi, v, scale):
    p = damped.pack()
    dz, Jz, dF = np.zeros(1), np.zeros((1, 2)), np.zeros(4)
    F = mykhailevych2020_jacobian(p, np.array([phi]), v, 0.0, scale, dz, Jz, dF)

    def f(ph, vv, sc):
        return mykhailevych2020_force(p, np.array([ph]), vv, 0.0, sc, np.zeros(1))
    assert F == f(phi, v, scale)
    h_phi, h_v, h_s = 1e-10, 1e-7, 1e-6
    assert dF[0] == pytest.approx((f(phi + h_phi, v, scale) - f(phi - h_phi, v, scale))
                                  / (2 * h_phi), rel=1e-5)
    assert dF[1] == pytest.approx((f(phi, v + h_v, scale) - f(phi, v - h_v, scale))
                                  / (2 * h_v), rel=1e-5)
    assert dF[3] == pytest.approx((f(phi, v, scale + h_s) - f(phi, v, scale - h_s))
                                  / (2 * h_s), rel=1e-6)


def test_clamp_reset_does_not_drift(damped):
    states, n_events = simulate_mass(damped, _m2, [3.0, 4.0, 5.0])
    x3, x4, x5 = states[:, 0]
    assert n_events >= 4
    assert abs(x5 - x4) < 1e-9 and abs(x4 - x3) < 1e-9
    assert 0.0 < x4 < 2 * damped.phi0


def test_undamped_small_k_v_drifts():
    """The same set without c_ps: the contact rings and ratchets (the reason for c_ps).
    One period from t = 1 s at rtol 1e-6, as the literal policies below: 459 µm, the same
    to four digits at rtol 1e-9 (measured; 382 µm from 3 to 4 s), in a quarter of the time."""
    states, _ = simulate_mass(make_model("mykhailevych2020", k_v=0.4), _m2, [1.0, 2.0],
                              rtol=1e-6, atol=1e-10)
    assert states[1, 0] - states[0, 0] > 100e-6


def test_presliding_equilibrium_and_none_reset(damped):
    states, _ = simulate_mass(damped, lambda t: 0.5, [1.0])
    x, v, _ = states[0]
    assert x == pytest.approx(damped.phi0 * math.atanh(0.5 / damped.T_stat), rel=1e-3)
    assert abs(v) < 1e-9
    states, _ = simulate_mass(damped.with_(reset="none"), lambda t: 0.5, [0.5])
    assert states[0, 0] == pytest.approx(damped.phi0 * math.atanh(1 / 3), rel=1e-3)


@pytest.mark.parametrize(("policy", "sign"), [("zero", 1.0), ("plus_phi0", -1.0)])
def test_literal_reset_policies_still_ratchet(damped, policy, sign):
    states, _ = simulate_mass(damped.with_(reset=policy), _m2, [1.0, 2.0], rtol=1e-6,
                              atol=1e-10)
    assert sign * (states[1, 0] - states[0, 0]) > 100e-6


def test_damped_set_shows_stick_slip_and_the_stribeck_drop(damped):
    m = run_stick_slip([damped]).metrics["mykhailevych2020"]
    assert m["period_s"] == pytest.approx(6.68, rel=0.01)
    assert m["force_max_N"] == pytest.approx(1.55, rel=0.01)
    assert m["force_min_N"] < 0.75                    # falls below T_din = 1 N after slip
