"""The method family: tableaus as data, their order conditions, and the W-method's reuse."""

import dataclasses

import numpy as np
import pytest
from _vdp_reference import radau_van_der_pol

from clutchsim.core import SolverOptions, simulate
from clutchsim.core.controllers import JacobianPolicy, StepController
from clutchsim.core.methods import (
    METHODS,
    RosenbrockTableau,
    get_method,
    register_method,
)
from clutchsim.core.methods._order import order_residuals, rooted_trees
from clutchsim.core.reference_problems import oscillator, riccati, van_der_pol


def test_rooted_trees_are_counted_as_in_oeis_a000081():
    assert [len(rooted_trees(n)) for n in range(1, 8)] == [1, 1, 2, 4, 9, 20, 48]


@pytest.mark.parametrize("name", sorted(METHODS))
def test_every_method_satisfies_its_order_conditions_and_not_one_more(name):
    m = get_method(name)
    if isinstance(m, RosenbrockTableau):
        A, G, b, bh = m.published()
    else:
        s = m.stages
        A = np.zeros((s, s))
        for i, row in enumerate(m.A):
            A[i + 1, :len(row)] = row
        G, b, bh = None, np.array(m.b), np.array(m.b_hat)
    worst = max(abs(r) for _, r in order_residuals(b, A, m.order, G))
    assert worst < 1e-12
    assert max(abs(r) for _, r in order_residuals(bh, A, m.embedded_order, G)) < 1e-12
    # the orders are sharp: the next order's conditions fail (the embedded pair differs)
    nxt = [r for t, r in order_residuals(bh, A, m.embedded_order + 1, G)
           if len(str(t)) and abs(r) > 1e-8]
    assert nxt, "the embedded solution would be of higher order than declared"


def test_ros34pw2_transformed_coefficients_are_those_of_the_published_table():
    m = get_method("ros34pw2")
    a, _, c, d, mm, e = m.transformed()
    # stiffly accurate: the solution is the last stage argument plus the last increment
    np.testing.assert_allclose(mm[:3], a[3, :3], rtol=1e-13)
    assert mm[3] == pytest.approx(1.0, abs=1e-13)
    np.testing.assert_allclose(c, [0.0, 0.871733043016918, 0.7315799577888524, 1.0],
                               rtol=1e-13)
    np.testing.assert_allclose(d, [0.435866521508459, -0.435866521508459,
                                   -0.4133333762338865, 0.0], atol=1e-13)
    np.testing.assert_allclose(e, [0.277749947647969, -1.4032398951759988,
                                   1.7726301276675507, 0.5], rtol=1e-12)


@pytest.mark.parametrize("name", ["rodas4", "rodas5p"])
def test_rodas_methods_are_stiffly_accurate_and_l_stable(name):
    m = get_method(name)
    A, G, b, _ = m.published()
    # stiffly accurate: b is the last row of alpha + Gamma
    np.testing.assert_allclose(b, (A + G)[-1], atol=1e-10)
    # L-stable: the stability function R(z) = 1 + z b (I - z(A + G))^-1 1 vanishes at infinity
    s = len(b)
    for z in (-1e9, -1e12):
        R = 1.0 + z * b @ np.linalg.solve(np.eye(s) - z * (A + G), np.ones(s))
        assert abs(R) < 1e-6


def test_a_tableau_that_fails_its_order_conditions_cannot_be_registered():
    good = get_method("ros34pw2")
    b = list(good.b)
    b[2] += 1e-6
    bad = dataclasses.replace(good, name="ros34pw2-broken", b=tuple(b))
    with pytest.raises(ValueError, match="does not have order 3"):
        register_method(bad)
    assert "ros34pw2-broken" not in METHODS


def test_unknown_method_names_the_closest():
    with pytest.raises(ValueError, match="did you mean 'rodas5p'"):
        get_method("rodas5")
    with pytest.raises(ValueError, match="did you mean 'rodas5p'"):
        simulate(riccati(), (0.0, 1.0), solver="rodas5")


def test_rodas5p_is_the_most_accurate_at_tight_tolerance():
    """At rtol 1e-10 the fifth-order method needs the fewest steps for the same accuracy."""
    steps = {}
    for solver in ("rodas4", "rodas5p"):
        res = simulate(oscillator(omega=2.0), (0.0, 10.0), {"F": 0.0}, solver=solver,
                       options=SolverOptions(rtol=1e-10, atol=1e-12))
        assert np.abs(res["x"] - np.cos(2.0 * res.t)).max() < 1e-8
        steps[solver] = res.stats.steps
    assert steps["rodas5p"] * 2 < steps["rodas4"]


@pytest.mark.parametrize("kind", ["I", "predictive", "pid"])
def test_every_controller_meets_the_tolerance(kind):
    ctrl = StepController(kind=kind)
    res = simulate(oscillator(omega=2.0), (0.0, 10.0), {"F": 0.0}, solver="rodas4",
                   options=SolverOptions(rtol=1e-7, atol=1e-10, controller=ctrl))
    assert res.outcome == "completed"
    assert np.abs(res["x"] - np.cos(2.0 * res.t)).max() < 2e-5


@pytest.mark.parametrize("bad, match", [
    ({"kind": "PI"}, "did you mean"),
    ({"safety": 1.5}, r"safety = 1.5 must be in \(0, 1\]"),
    ({"min_factor": 2.0}, "min_factor"),
    ({"beta": (1.0, 2.0)}, "three finite numbers"),
])
def test_bad_controllers_are_named(bad, match):
    with pytest.raises(ValueError, match=match):
        StepController(**bad)


def test_stiff_van_der_pol_with_a_reused_jacobian_matches_scipy_radau():
    mu, t_end = 100.0, 150.0
    res = simulate(van_der_pol(mu), (0.0, t_end), solver="ros34pw2",
                   options=SolverOptions(rtol=1e-9, atol=1e-9))
    assert res.status == "completed"
    ref = radau_van_der_pol(mu, t_end)
    slow = np.abs(res["y"]) < 1.0
    assert slow.sum() > 100
    assert np.abs(res["x"][slow] - ref.sol(res.t)[0][slow]).max() < 1e-4
    # the point of a W-method: one Jacobian serves many steps
    assert res.stats.jacobians * 4 < res.stats.steps
    # and a step costs four right-hand sides plus a share of the Jacobians (n + 1 = 3 each)
    attempts = res.stats.steps + res.stats.rejected
    assert res.stats.rhs_evals <= 4 * attempts + 3 * res.stats.jacobians + 50


def test_lu_reuse_of_the_w_method_keeps_accuracy_and_factorises_less_per_attempt():
    """The band keeps the W-method's accuracy (any W is allowed) and skips factorisations;
    on stiff van der Pol it costs rejections (measured: docs/performance.md), which is why
    it is off by default."""
    mu, t_end = 100.0, 150.0
    ref = radau_van_der_pol(mu, t_end)
    runs = {}
    for band in (0.0, 0.2):
        res = simulate(van_der_pol(mu), (0.0, t_end), solver="ros34pw2",
                       options=SolverOptions(rtol=1e-9, atol=1e-9,
                                             jacobian=JacobianPolicy(lu_reuse=band)))
        assert res.status == "completed"
        slow = np.abs(res["y"]) < 1.0
        assert np.abs(res["x"][slow] - ref.sol(res.t)[0][slow]).max() < 1e-4
        runs[band] = res.stats
    def per_attempt(st):
        return st.lu_decompositions / (st.steps + st.rejected)
    assert per_attempt(runs[0.2]) < 0.8 * per_attempt(runs[0.0])
    assert per_attempt(runs[0.0]) > 0.9


def test_bad_jacobian_policy_is_named():
    with pytest.raises(ValueError, match="lu_reuse = 1.5 must be in"):
        JacobianPolicy(lu_reuse=1.5)
    with pytest.raises(ValueError, match="max_age = 0 must be an integer >= 1"):
        JacobianPolicy(max_age=0)


