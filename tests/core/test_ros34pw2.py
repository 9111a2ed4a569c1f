"""ROS34PW2 (Rang & Angermann 2005): its coefficients, its order, and Jacobian reuse."""

import numpy as np
import pytest
from _vdp_reference import radau_van_der_pol

from clutchsim.core import SolverOptions, simulate
from clutchsim.core import _ros34pw2 as ros
from clutchsim.core.reference_problems import van_der_pol


def _published():
    A = np.zeros((4, 4))
    G = np.diag([ros.GAM] * 4)
    A[:, :3] = ros.ALPHA
    G[:, :3] += ros.GAMMA
    return A, G, np.array(ros.B), np.array(ros.B_HAT)


def test_transformed_coefficients_follow_from_the_published_table():
    A, G, b, bh = _published()
    Gi = np.linalg.inv(G)
    a = A @ Gi
    c = np.diag(1.0 / np.diag(G)) - Gi
    m = b @ Gi
    e = (b - bh) @ Gi
    assert np.allclose([a[1, 0], a[2, 0], a[2, 1], a[3, 0], a[3, 1], a[3, 2]],
                       [ros.A21, ros.A31, ros.A32, ros.A41, ros.A42, ros.A43], rtol=1e-13)
    assert np.allclose([c[1, 0], c[2, 0], c[2, 1], c[3, 0], c[3, 1], c[3, 2]],
                       [ros.C21, ros.C31, ros.C32, ros.C41, ros.C42, ros.C43], rtol=1e-13)
    # stiffly accurate: the solution is the last stage argument plus the last increment
    assert np.allclose(m, [ros.A41, ros.A42, ros.A43, 1.0], rtol=1e-13)
    assert np.allclose(e, [ros.E1, ros.E2, ros.E3, ros.E4], rtol=1e-13)
    assert np.allclose(A.sum(1), [0.0, ros.C2, ros.C3, 1.0], rtol=1e-13)
    assert np.allclose(G.sum(1), [ros.D1, ros.D2, ros.D3, 0.0], atol=1e-15)


def test_rosenbrock_order_conditions_up_to_three():
    A, G, b, bh = _published()
    g = ros.GAM
    alpha = A.sum(1)
    beta = (A + G - np.diag(np.diag(G))).sum(1)       # beta'_i = sum_{j<i} (a + g)_ij
    B = A + G - np.diag(np.diag(G))
    assert b.sum() == pytest.approx(1.0, abs=1e-14)
    assert b @ beta == pytest.approx(0.5 - g, abs=1e-14)
    assert b @ alpha ** 2 == pytest.approx(1.0 / 3.0, abs=1e-14)
    assert b @ (B @ beta) == pytest.approx(1.0 / 6.0 - g + g * g, abs=1e-14)
    # the embedded solution is of order two
    assert bh.sum() == pytest.approx(1.0, abs=1e-14)
    assert bh @ beta == pytest.approx(0.5 - g, abs=1e-14)


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
