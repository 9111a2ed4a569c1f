"""Quadrature states: trailing pure integrals leave the implicit solve, not the result."""

from dataclasses import replace

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from clutchsim.core import cengine, simulate

_ENGINE = pytest.mark.skipif(not cengine.available(),
                             reason="no C compiler to build the C engine here")


def _stage_solve(J, inv_gh, nd, b, rows=3, r=1):
    """The engine's inverse (engine.c: ``invert``), then its solve into row ``r`` of a
    stage array (``solve_into_row``); returns (ok, that array)."""
    lib = cengine._library()
    n = J.shape[0]
    J = np.ascontiguousarray(J, dtype=float)
    b = np.ascontiguousarray(b, dtype=float)
    M = np.empty((n, n))
    piv = np.empty(n, dtype=np.int64)
    ok = lib.cl_invert_nb(J.ctypes.data, inv_gh, M.ctypes.data, piv.ctypes.data, n, nd)
    K = np.full((rows, n), 7.0)
    if ok:
        lib.cl_solve_into_row_nb(M.ctypes.data, b.ctypes.data, K.ctypes.data, r, n, nd)
    return bool(ok), K


@_ENGINE
@pytest.mark.parametrize("nd", [5, 3, 1])
def test_block_inverse_solves_the_full_iteration_matrix(nd):
    # J with zero columns for the quadrature states: M = I/(gamma h) - J is block lower
    # triangular, and the block solve must equal a dense solve of the whole matrix
    rng = np.random.default_rng(nd)
    n = 5
    J = rng.normal(size=(n, n))
    J[:, nd:] = 0.0
    inv_gh = 7.3
    b = rng.normal(size=n)
    ok, K = _stage_solve(J, inv_gh, nd, b)
    assert ok
    full = np.eye(n) * inv_gh - J
    np.testing.assert_allclose(K[1], np.linalg.solve(full, b), rtol=1e-12, atol=1e-12)
    np.testing.assert_array_equal(K[[0, 2]], 7.0)       # the other rows are untouched


@_ENGINE
@settings(max_examples=200, deadline=None)
@given(n=st.integers(1, 16), data=st.data(), seed=st.integers(0, 2**32 - 1),
       log_gh=st.floats(-5.0, 1.0), scale=st.floats(0.01, 1e4))
def test_stage_solve_equals_a_dense_solve_of_the_whole_matrix(n, data, seed, log_gh, scale):
    nd = data.draw(st.integers(1, n), label="nd")
    r = data.draw(st.integers(0, 2), label="row")
    rng = np.random.default_rng(seed)
    J = rng.normal(size=(n, n)) * scale
    J[:, nd:] = 0.0
    inv_gh = 10.0 ** -log_gh
    full = np.eye(n) * inv_gh - J
    assume(np.linalg.cond(full) < 1e4)
    b = rng.normal(size=n) * rng.uniform(0.1, 10.0, size=n)
    ok, K = _stage_solve(J, inv_gh, nd, b, r=r)
    assert ok
    x = np.linalg.solve(full, b)
    assert np.max(np.abs(K[r] - x)) <= 1e-10 * np.max(np.abs(x))
    np.testing.assert_array_equal(np.delete(K, r, axis=0), 7.0)


@_ENGINE
@settings(max_examples=60, deadline=None)
@given(n=st.integers(1, 12), data=st.data(), seed=st.integers(0, 2**32 - 1),
       kind=st.sampled_from(["zero row", "zero column", "nan"]))
def test_singular_or_nan_leading_block_is_refused(n, data, seed, kind):
    nd = data.draw(st.integers(1, n), label="nd")
    k = data.draw(st.integers(0, nd - 1), label="k")
    rng = np.random.default_rng(seed)
    inv_gh = 3.0
    J = rng.normal(size=(n, n))
    J[:, nd:] = 0.0
    if kind == "zero row":          # row k of I/(γh) − J is zero in the leading block
        J[k, :nd] = 0.0
        J[k, k] = inv_gh
    elif kind == "zero column":
        J[:, k] = 0.0
        J[k, k] = inv_gh
    else:                           # a NaN anywhere in the (dense) leading block
        J[k, data.draw(st.integers(0, nd - 1), label="j")] = np.nan
    ok, _K = _stage_solve(J, inv_gh, nd, np.ones(n))
    assert not ok


def _launch():
    from clutchsim.scenario import load_scenario
    sc = load_scenario(None, overrides=["scenario.t_end=1.6"])
    u0 = {name: float(np.asarray(sig(0.0)).ravel()[0]) for name, sig in sc.inputs.items()}
    sys_ = sc.network("mykhailevych2020").build(u0)
    return sc, sys_, {n: sc.inputs[n] for n in sys_.input_names}


def test_chain_energy_accounts_are_declared_quadratures_and_nothing_depends_on_them():
    from clutchsim.analysis.launch_metrics import ENERGY_STATES
    from clutchsim.core.system import call_rhs
    _sc, sys_, _inputs = _launch()
    # the accounts (the only friction element's own work is W_friction, an output)
    assert "W_friction_clutch" in sys_.output_names
    assert sys_.quadratures == len(ENERGY_STATES)
    assert sys_.state_names[-sys_.quadratures:] == ENERGY_STATES
    y = sys_.y0.copy()
    u = np.array([0.3, 0.5])[:len(sys_.input_names)]
    base = np.empty_like(y)
    call_rhs(sys_.tag, 0.7, y, u, sys_.params, base)
    for k in range(sys_.quadratures):
        y2 = y.copy()
        y2[-1 - k] += 123.0
        dy = np.empty_like(y)
        call_rhs(sys_.tag, 0.7, y2, u, sys_.params, dy)
        np.testing.assert_array_equal(dy, base)


@pytest.mark.parametrize("method", ["ros34pw2", "rodas4"])
def test_launch_with_and_without_quadratures_agree(method):
    sc, sys_, inputs = _launch()
    # the launch plant has an exact Jacobian; the saving is in the columns a differenced
    # Jacobian leaves out, so the same plant runs here without its Jacobian
    from typing import NamedTuple

    from clutchsim.core import register_system
    from clutchsim.core.system import plant_functions
    fns = plant_functions(sys_.tag)
    Differenced = NamedTuple("Differenced", [("k", int)])  # noqa: UP014
    register_system(Differenced, rhs=fns.rhs, events=fns.events, reset=fns.reset,
                    outputs=fns.outputs)
    sys_ = replace(sys_, tag=Differenced(0))
    # the tolerances this comparison was written for (the scenario's own are looser now)
    opts = replace(sc.options, rtol=1e-6, atol=1e-8)
    a = simulate(sys_, (0.0, 1.6), inputs, solver=method, options=opts)
    b = simulate(replace(sys_, quadratures=0), (0.0, 1.6), inputs, solver=method,
                 options=opts)
    assert a.status == b.status == "completed"
    # the same steps up to round-off: the full 16 x 16 inverse and the 10 x 10 block with
    # its substitution differ in the last bits, which may move a step or two
    assert abs(a.stats.jacobians - b.stats.jacobians) <= 0.01 * b.stats.jacobians
    # fewer right-hand sides: the quadrature columns are not differenced
    assert a.stats.rhs_evals < b.stats.rhs_evals
    # on the output grid (event rows sit at times that differ within the event tolerance
    # of a near-stick slip crossing, so rows are compared at common grid times)
    grid = np.round(np.arange(0.0, 1.6 + 1e-9, 0.01), 9)
    ia = np.flatnonzero(np.isin(np.round(a.t, 9), grid))
    ib = np.flatnonzero(np.isin(np.round(b.t, 9), grid))
    np.testing.assert_array_equal(a.t[ia], b.t[ib])
    assert ia.size == grid.size
    for name in ("omega_engine", "omega_wheels", "W_friction", "W_in"):
        scale = np.max(np.abs(b[name])) + 1e-30
        assert np.max(np.abs(a[name][ia] - b[name][ib])) / scale < 1e-6, name


def test_bad_quadrature_count_is_named():
    _sc, sys_, _inputs = _launch()
    with pytest.raises(ValueError, match="quadratures = -1 must be an integer"):
        replace(sys_, quadratures=-1)
    with pytest.raises(ValueError, match="quadratures = 99 must be an integer"):
        replace(sys_, quadratures=99)
