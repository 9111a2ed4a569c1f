"""The straight-line elimination of the iteration matrix generated per topology
(clutchsim.network.elimination): it solves ``(c·I − J)·x = b`` as the dense inverse does,
refuses the matrices its static order cannot factor safely, and the network plants' factors
hold along real runs of every kind of driveline."""

from pathlib import Path
from typing import NamedTuple

import numba
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from clutchsim.core import SolverOptions, register_system, simulate
from clutchsim.core.system import (
    System,
    call_factor,
    call_jac,
    call_solve,
    factor_size,
)
from clutchsim.network.elimination import elimination_order, elimination_source

EXAMPLES_DIR = Path(__file__).resolve().parents[2] / "examples"
EXAMPLES = ["launch.toml", "launch_dmf.toml", "converter_launch.toml", "dct_upshift.toml",
            "coupled_clutches.toml", "lossy_gear_demo1.toml", "one_way_clutch.toml",
            "shift_1_2.toml", "launch_wear.toml"]


def _functions(pattern, n, as_python=True):
    """``factor`` and ``solve`` of ``pattern``, as plain Python (fast for hypothesis) or
    compiled."""
    el = elimination_source(pattern, n, max_flops=10**6)
    ns = {"jit": (lambda f: f) if as_python else numba.njit}
    exec("\n".join(el.lines), ns)       # noqa: S102 (our own generated source)
    return ns["factor"], ns["solve"], el


def _dense_solve(c, J, nd, b):
    """The iteration matrix of the integrators, quadrature block ``c·I``, solved by LAPACK."""
    M = c * np.eye(J.shape[0]) - J
    M[nd:, nd:] = c * np.eye(J.shape[0] - nd)
    return np.linalg.solve(M, b)


@st.composite
def _systems(draw):
    n = draw(st.integers(1, 12))
    nd = draw(st.integers(1, n))
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    pattern = rng.random((n, nd)) < draw(st.floats(0.0, 0.7))
    J = np.where(pattern, rng.normal(size=(n, nd)), 0.0)
    return pattern, np.hstack([J, np.zeros((n, n - nd))]), rng


@settings(max_examples=300, deadline=None)
@given(sys=_systems(), c_scale=st.floats(0.5, 1e6))
def test_factor_and_solve_agree_with_lapack(sys, c_scale):
    pattern, J, rng = sys
    n, nd = pattern.shape
    # a diagonally dominant M (c larger than any row of J): the static order must take it
    c = c_scale * (1.0 + np.abs(J).sum(axis=1).max())
    factor, solve, el = _functions(pattern, n)
    F = np.full(el.size, np.nan)
    assert factor(c, J, F) == 1
    X = np.zeros((3, n))
    b = rng.normal(size=n)
    solve(F, b, X, 1)
    want = _dense_solve(c, J, nd, b)
    assert np.allclose(X[1], want, rtol=1e-12, atol=1e-14 * np.abs(want).max())
    assert not X[0].any() and not X[2].any()      # only row r is written


@settings(max_examples=100, deadline=None)
@given(sys=_systems())
def test_any_matrix_it_accepts_it_solves(sys):
    # c of either sign and any size: what factor accepts (its pivots kept their digits, no
    # growth) is solved to a small residual
    pattern, J, rng = sys
    n, nd = pattern.shape
    c = float(rng.normal() * 3.0)
    factor, solve, el = _functions(pattern, n)
    F = np.zeros(el.size)
    M = c * np.eye(n) - J
    M[nd:, nd:] = c * np.eye(n - nd)
    if not factor(c, J, F):
        return
    assert c != 0.0 or nd == n
    X = np.zeros((1, n))
    b = rng.normal(size=n)
    solve(F, b, X, 0)
    assert np.abs(M @ X[0] - b).max() <= 1e-6 * (1.0 + np.abs(M).max() * np.abs(X[0]).max())


def test_a_zero_pivot_is_refused():
    pattern = np.ones((2, 2), dtype=bool)
    factor, _solve, el = _functions(pattern, 2)
    J = np.array([[1.0, 2.0], [3.0, 0.5]])
    assert factor(1.0, J, np.zeros(el.size)) == 0         # c − J[0, 0] = 0


def test_growth_and_cancellation_are_refused():
    pattern = np.ones((2, 2), dtype=bool)
    factor, _solve, el = _functions(pattern, 2)
    F = np.zeros(el.size)
    # M = [[1e-12, 1], [1, 1]]: the static order's pivot 1e-12 makes the factors grow
    # by 1e12 (partial pivoting would swap the rows)
    J = np.array([[1.0 - 1e-12, -1.0], [-1.0, 0.0]])
    assert factor(1.0, J, F) == 0
    # M = [[1, 1], [1, 1 + 1e-10]]: the second pivot loses ten digits to cancellation
    J = np.array([[0.0, -1.0], [-1.0, -1e-10]])
    assert factor(1.0, J, F) == 0
    # and a plain one is taken
    assert factor(4.0, np.array([[1.0, -1.0], [-1.0, 0.0]]), F) == 1


def test_order_is_minimum_degree_with_the_kinematic_states_first():
    # a chain: speed 0 - twist 1 - speed 2; the twist (no self-dependence) goes first
    pattern = np.array([[1, 1, 0], [1, 0, 1], [0, 1, 1]], dtype=bool)
    order = elimination_order(pattern)
    assert order[0] in (0, 2)                # degree 1 beats degree 2
    pattern = np.array([[1, 1], [1, 0]], dtype=bool)
    assert elimination_order(pattern) == [1, 0]     # equal degree: the twist first


def test_dense_patterns_are_left_to_the_dense_inverse():
    assert elimination_source(np.ones((12, 12), dtype=bool), 12) is None
    assert elimination_source(np.eye(12, dtype=bool), 12) is not None


def test_compiled_and_python_forms_agree():
    rng = np.random.default_rng(3)
    pattern = rng.random((7, 5)) < 0.4
    J = np.hstack([np.where(pattern, rng.normal(size=(7, 5)), 0.0), np.zeros((7, 2))])
    out = []
    for as_python in (True, False):
        factor, solve, el = _functions(pattern, 7, as_python)
        F = np.zeros(el.size)
        assert factor(50.0, J, F) == 1
        X = np.zeros((2, 7))
        solve(F, np.arange(7.0), X, 1)
        out.append(X[1])
    assert np.array_equal(out[0], out[1])


# ---------------------------------------------------------------- the integrators' protocol
def _chain_tag(name, with_factor, refuse=False):
    """Three masses on two springs, a damper to ground and a quadrature (its dissipated
    energy), as a plant with or without its own factors."""
    tag = NamedTuple(name, [("k", int)])  # noqa: UP014

    @numba.njit
    def rhs(t, y, u, p, dy):
        dy[0] = (-p[0] * y[3] - p[1] * y[0]) / p[2]
        dy[1] = (p[0] * y[3] - p[0] * y[4]) / p[2]
        dy[2] = p[0] * y[4] / p[2]
        dy[3] = y[0] - y[1]
        dy[4] = y[1] - y[2]
        dy[5] = p[1] * y[0] * y[0]

    @numba.njit
    def jac(t, y, u, p, J):
        for i in range(6):
            for j in range(6):
                J[i, j] = 0.0
        J[0, 0] = -p[1] / p[2]
        J[0, 3] = -p[0] / p[2]
        J[1, 3] = p[0] / p[2]
        J[1, 4] = -p[0] / p[2]
        J[2, 4] = p[0] / p[2]
        J[3, 0], J[3, 1] = 1.0, -1.0
        J[4, 1], J[4, 2] = 1.0, -1.0
        J[5, 0] = 2.0 * p[1] * y[0]

    fns = {"rhs": rhs, "jac": jac}
    if with_factor:
        pattern = np.zeros((6, 5), dtype=bool)
        for i, j in ((0, 0), (0, 3), (1, 3), (1, 4), (2, 4), (3, 0), (3, 1), (4, 1),
                     (4, 2), (5, 0)):
            pattern[i, j] = True
        el = elimination_source(pattern, 6)
        ns = {"jit": numba.njit}     # exec'd source: numba cannot cache it on disk
        exec("\n".join(el.lines), ns)       # noqa: S102 (our own generated source)
        factor = ns["factor"]
        if refuse:
            @numba.njit
            def factor(c, J, F):
                return 0
        fns.update(factor=factor, solve=ns["solve"], factor_size=el.size)
    register_system(tag, **fns)
    return System(tag(0), np.array([400.0, 0.5, 0.1]), np.array([3.0, 0, 0, 0, 0, 0]),
                  tuple("abcdef"), ("rad/s",) * 3 + ("rad",) * 2 + ("J",),
                  quadratures=1)


@pytest.fixture(scope="module")
def chains():
    return {k: _chain_tag(f"Chain_{k}", k != "dense", k == "refused")
            for k in ("dense", "factored", "refused")}


def test_integrators_use_the_plants_factors_and_fall_back_to_the_dense_inverse(chains):
    opts = SolverOptions(rtol=1e-8, atol=1e-10, dt_out=0.01)
    runs = {k: simulate(s, (0.0, 2.0), solver="rodas5p", options=opts)
            for k, s in chains.items()}
    assert factor_size(chains["factored"].tag) > 0
    assert factor_size(chains["dense"].tag) == 0
    dense, fact, refused = runs["dense"], runs["factored"], runs["refused"]
    # a factor that refuses every matrix leaves the dense path: the same bits
    for k in "abcdef":
        assert np.array_equal(dense[k], refused[k])
    # the factored run: the same solution to round-off (the steps may differ slightly)
    assert fact.status == "completed" and fact.stats.steps == pytest.approx(dense.stats.steps, rel=0.05)
    for k in "abcdef":
        scale = np.abs(dense[k]).max()
        assert np.abs(np.interp(dense.t, fact.t, fact[k]) - dense[k]).max() < 1e-6 * scale


def test_register_rejects_half_a_solver(chains):
    tag = NamedTuple("Half", [("k", int)])  # noqa: UP014
    with pytest.raises(ValueError, match="go together"):
        register_system(tag, rhs=lambda *a: None, factor=lambda *a: 1)
    with pytest.raises(ValueError, match="need the exact jac"):
        register_system(tag, rhs=lambda *a: None, factor=lambda *a: 1,
                        solve=lambda *a: None, factor_size=3)


# ---------------------------------------------------------------- the network plants
@pytest.mark.parametrize("name", EXAMPLES)
def test_network_factors_hold_along_a_run(name):
    """At states along a run of each example, the plant's factors solve ``c·I − J``
    as LAPACK does: a non-zero of ``J`` outside the pattern the elimination was written
    for would show here."""
    from clutchsim.scenario import load_scenario
    sc = load_scenario(EXAMPLES_DIR / name)
    model = sc.models[0] if sc.models else None
    system = sc.system(model)
    nf = factor_size(system.tag)
    assert nf > 0, f"{name}: no factors generated"     # every example's pattern gains
    res = simulate(system, (0.0, sc.t_end), {n: sc.inputs[n] for n in system.input_names},
                   solver=sc.solver, options=sc.options)
    n, nd = system.n_states, system.n_states - system.quadratures
    rng = np.random.default_rng(0)
    taken = 0
    for k in np.linspace(0, len(res.t) - 1, 40).astype(int):
        y = np.array([float(res[c][k]) for c in system.state_names])
        u = np.array([float(np.asarray(res[c][k])) for c in system.input_names])
        J = np.zeros((n, n))
        call_jac(system.tag, float(res.t[k]), y, u, system.params, J)
        for c in (1e2, 1e4, 1e6):
            F = np.zeros(nf)
            if not call_factor(system.tag, c, J, F):
                continue
            taken += 1
            b = rng.normal(size=n)
            X = np.zeros((1, n))
            call_solve(system.tag, F, b, X, 0)
            want = _dense_solve(c, J, nd, b)
            assert np.allclose(X[0], want, rtol=1e-9, atol=1e-12 * np.abs(want).max()), \
                f"{name}: t = {res.t[k]}, c = {c}"
    assert taken >= 100
