"""Steady sliding curves: literature values, signs, scale and kernel consistency."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from clutchsim.friction import LuGre, RotationalFriction, make_model

# friction-models.md T1 (exact algebra of F_ss = g(v) + sigma2·v, Table I)
T1 = [
    (1e-4, 1.495065),
    (5e-4, 1.389600),
    (1e-3, 1.184340),
    (2e-3, 1.009958),
    (1e-2, 1.004000),
    (0.1, 1.040000),
]

VELOCITIES = (-0.3, -0.02, -2e-3, -5e-4, 5e-4, 2e-3, 0.02, 0.3)


@pytest.mark.parametrize(("v", "expected"), T1)
def test_lugre_steady_state_matches_T1(v, expected):
    model = LuGre.from_parameters("lugre_canudas1995")
    assert model.steady_state_force(v) == pytest.approx(expected, abs=1e-6)
    assert model.steady_state_force(-v) == pytest.approx(-expected, abs=1e-6)


def test_lugre_steady_state_minimum():
    model = LuGre.from_parameters("lugre_canudas1995")
    res = minimize_scalar(lambda v: float(model.steady_state_force(v)), bounds=(1e-3, 1e-2),
                          method="bounded", options={"xatol": 1e-10})  # fmt: skip
    assert res.fun == pytest.approx(1.001261, abs=5e-7)
    assert res.x == pytest.approx(2.986e-3, abs=5e-7)
    assert model.steady_state_force(1e-9) == pytest.approx(1.5, abs=1e-8)  # -> F_s as v -> 0+


@pytest.mark.parametrize("v", VELOCITIES)
def test_steady_force_sign_and_scale(default_model, v):
    F = float(default_model.steady_state_force(v))
    assert math.copysign(1.0, F) == math.copysign(1.0, v) and F != 0.0
    assert float(default_model.steady_state_force(v, scale=0.37)) == pytest.approx(0.37 * F)


def test_steady_force_matches_the_formula_written_out(default_model):
    """The model's declared ``steady_checks`` (forces written out independently of its
    code, with its default set) on both sides of zero: F_ss is odd."""
    checks = type(default_model).steady_checks
    assert len(checks) >= 3 and {math.copysign(1.0, v) for v, _ in checks} == {-1.0, 1.0}
    for v, expected in checks:
        assert float(default_model.steady_state_force(v)) == pytest.approx(expected, rel=1e-12)
        assert float(default_model.steady_state_force(-v)) == pytest.approx(-expected,
                                                                            rel=1e-12)


@pytest.mark.parametrize("v", VELOCITIES)
def test_kernel_matches_python_steady_state(default_model, v, force):
    """Compiled force at the steady sliding state equals steady_state_force(v)."""
    z = default_model.sliding_state(v)
    for scale in (1.0, 0.25):
        F, dz = force(default_model, z, v, F_e=0.0, scale=scale)
        assert F == pytest.approx(float(default_model.steady_state_force(v, scale)), rel=1e-12)
    if default_model.name == "mykhailevych2020":
        assert dz[0] == v  # the integrator keeps integrating the slip
    else:
        assert np.all(np.abs(dz) <= 1e-12 * abs(v))


def test_coulomb_robust_stribeck_option(force):
    model = make_model("coulomb-robust", v_s=1e-3, sigma2=0.4)
    lugre = LuGre.from_parameters("lugre_canudas1995")
    v = np.array([-0.05, -1e-3, 2e-4, 3e-3])
    np.testing.assert_allclose(model.steady_state_force(v), lugre.steady_state_force(v), rtol=1e-13)
    for vi in v:
        F, _ = force(model, [np.sign(vi)], vi)
        assert F == pytest.approx(float(lugre.steady_state_force(vi)), rel=1e-12)


def test_steady_state_is_vectorised(default_model):
    v = np.linspace(-0.1, 0.1, 7)
    F = default_model.steady_state_force(v)
    assert F.shape == v.shape
    assert F[3] == 0.0  # v = 0


@pytest.mark.parametrize("v", (-0.7, -1e-3, 0.0, 1e-6, 2.0))
def test_scale_zero_is_free_for_any_state(default_model, v, force):
    rng = np.random.default_rng(7)
    for _ in range(20):
        z = rng.normal(scale=1e-3, size=default_model.n_states)
        if default_model.lockable:
            z = rng.integers(-1, 2, size=1).astype(float)
        F_e = float(rng.normal(scale=10.0))
        F, dz = force(default_model, z, v, F_e=F_e, scale=0.0)
        assert F == 0.0
        assert np.all(np.isfinite(dz))


def test_forces_proportional_to_scale_in_dynamic_states(default_model, force):
    rng = np.random.default_rng(3)
    for _ in range(10):
        z = rng.normal(scale=5e-6, size=default_model.n_states)
        if default_model.lockable:
            z = np.array([1.0])
        v = float(rng.normal(scale=0.01))
        F1, dz1 = force(default_model, z, v, scale=1.0)
        F3, dz3 = force(default_model, z, v, scale=3.0)
        assert F3 == pytest.approx(3.0 * F1, rel=1e-12, abs=1e-300)
        np.testing.assert_array_equal(dz1, dz3)  # state dynamics do not depend on scale


def test_rotational_friction_peak():
    model = RotationalFriction.from_parameters("rotational_friction")
    P = model
    # exact: F(v_brk) = F_brk + f·v_brk - F_c·(1 - tanh 10)
    exact = P.F_brk + P.f * P.v_brk - P.F_c * (1.0 - math.tanh(10.0))
    assert float(model.steady_state_force(P.v_brk)) == pytest.approx(exact, rel=1e-14)
    res = minimize_scalar(lambda v: -float(model.steady_state_force(v)),
                          bounds=(0.5 * P.v_brk, 1.5 * P.v_brk), method="bounded",
                          options={"xatol": 1e-12})  # fmt: skip
    assert res.x == pytest.approx(P.v_brk, rel=1e-4)
    assert -res.fun == pytest.approx(P.F_brk + P.f * P.v_brk, rel=1e-8)
    # far out: Coulomb + viscous
    assert float(model.steady_state_force(10.0)) == pytest.approx(P.F_c + 10.0 * P.f, rel=1e-12)
    assert model.unit_of("F_brk", "rotational") == "N·m"


def test_gms_sliding_state_saturates_every_element():
    model = make_model("gms")
    v = 0.02
    z = model.sliding_state(v)
    k = np.array(model.k)
    s = float(model.steady_state_force(v)) - model.sigma2 * v
    np.testing.assert_allclose(k * z, np.array(model.alpha) * s, rtol=1e-13)
