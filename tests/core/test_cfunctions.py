"""A plant of numba functions reaches the C engine through adapters (core/_cfunctions.py):
numba ``cfunc``s that view the engine's plain pointers as the arrays the plant's functions
take.  Called through their C addresses they compute what the functions compute called
directly, for every entry point (the factors too); they are built once per plant type and
sizes; a printed plant needs none."""

from __future__ import annotations

import ctypes
from typing import NamedTuple

import numba
import numpy as np
import pytest

from clutchsim.core import cengine, register_system, simulate
from clutchsim.core._cfunctions import c_functions
from clutchsim.core.reference_problems import ball, oscillator, riccati
from clutchsim.core.system import System, plant_functions

_D, _P, _I = ctypes.c_double, ctypes.c_void_p, ctypes.c_int
_KERNEL = ctypes.CFUNCTYPE(None, _D, _P, _P, _P, _P)
_RESET = ctypes.CFUNCTYPE(_I, _D, _P, _P, _P, _I)
_JAC = ctypes.CFUNCTYPE(None, _D, _P, _P, _P, _P, _I)
_FACTOR = ctypes.CFUNCTYPE(_I, _D, _P, _I, _P)
_SOLVE = ctypes.CFUNCTYPE(None, _P, _P, _P, _I, _I)


def _p(a):
    return a.ctypes.data


# a damped linear oscillator with its exact Jacobian and its own 2 x 2 solver: M = c·I − J
# factored as its inverse (4 floats), solve writes X[r] = M⁻¹·b
@numba.njit
def _lin_rhs(t, y, u, p, dy):
    dy[0] = y[1]
    dy[1] = -p[0] * y[0] - p[1] * y[1] + u[0]


@numba.njit
def _lin_events(t, y, u, p, g):
    g[0] = y[0] - p[2]


@numba.njit
def _lin_reset(t, y, u, p, k):
    y[1] = -y[1]          # an elastic stop at x = p[2]
    return 1


@numba.njit
def _lin_outputs(t, y, u, p, out):
    out[0] = p[0] * y[0]
    out[1] = y[1] * y[1]


@numba.njit
def _lin_jac(t, y, u, p, J):
    J[0, 0], J[0, 1] = 0.0, 1.0
    J[1, 0], J[1, 1] = -p[0], -p[1]


@numba.njit
def _lin_factor(c, J, F):
    a, b, cc, d = c - J[0, 0], -J[0, 1], -J[1, 0], c - J[1, 1]
    det = a * d - b * cc
    if det == 0.0:
        return 0
    F[0], F[1], F[2], F[3] = d / det, -b / det, -cc / det, a / det
    return 1


@numba.njit
def _lin_solve(F, b, X, r):
    X[r, 0] = F[0] * b[0] + F[1] * b[1]
    X[r, 1] = F[2] * b[0] + F[3] * b[1]


class _Linear(NamedTuple):
    k: int


register_system(_Linear, rhs=_lin_rhs, events=_lin_events, reset=_lin_reset,
                outputs=_lin_outputs, jac=_lin_jac, factor=_lin_factor, solve=_lin_solve,
                factor_size=4)


def _linear(k=40.0, d=0.3):
    return System(_Linear(0), np.array([k, d, 0.5]), np.array([1.0, 0.0]), ("x", "v"),
                  ("m", "m/s"), input_names=("F",), input_units=("N",),
                  output_names=("F_spring", "v2"), output_units=("N", "m2/s2"),
                  event_names=("x_half",), event_directions=(-1,), name="linear")


def test_every_adapter_computes_what_its_function_computes():
    system = _linear()
    fns = plant_functions(system.tag)
    addr = c_functions(system)
    assert all(a > 0 for a in addr)
    rng = np.random.default_rng(5)
    for _ in range(20):
        t, y, u, p = rng.uniform(0, 2), rng.normal(size=2), rng.normal(size=1), system.params
        for fn, c, width in ((fns.rhs, addr[0], 2), (fns.events, addr[1], 1),
                             (fns.outputs, addr[3], 2)):
            want, got = np.zeros(width), np.zeros(width)
            fn(t, y, u, p, want)
            _KERNEL(c)(t, _p(y), _p(u), _p(p), _p(got))
            np.testing.assert_array_equal(got, want)
        y1, y2 = y.copy(), y.copy()
        assert _RESET(addr[2])(t, _p(y2), _p(u), _p(p), 0) == fns.reset(t, y1, u, p, 0)
        np.testing.assert_array_equal(y2, y1)                  # the reset map writes y
        want, got = np.zeros((2, 2)), np.zeros((2, 2))
        fns.jac(t, y, u, p, want)
        _JAC(addr[4])(t, _p(y), _p(u), _p(p), _p(got), 2)
        np.testing.assert_array_equal(got, want)
        c = rng.uniform(1, 100)
        F1, F2 = np.zeros(4), np.zeros(4)
        assert _FACTOR(addr[5])(c, _p(want), 2, _p(F2)) == fns.factor(c, want, F1) == 1
        np.testing.assert_array_equal(F2, F1)
        b = rng.normal(size=2)
        X1, X2 = np.full((3, 2), 7.0), np.full((3, 2), 7.0)
        fns.solve(F1, b, X1, 1)
        _SOLVE(addr[6])(_p(F2), _p(b), _p(X2), 2, 1)
        np.testing.assert_array_equal(X2, X1)
        np.testing.assert_allclose(X2[1], np.linalg.solve(c * np.eye(2) - want, b))


def test_a_plant_with_its_own_solver_runs_in_the_engine_as_the_dense_path_does():
    """The factors reach the engine too: the same run without them (the engine inverts
    densely) agrees to round-off."""
    system = _linear()
    own = simulate(system, (0.0, 3.0), {"F": 0.2}, solver="rodas4")

    class _Dense(NamedTuple):
        k: int
    register_system(_Dense, rhs=_lin_rhs, events=_lin_events, reset=_lin_reset,
                    outputs=_lin_outputs, jac=_lin_jac)
    from dataclasses import replace
    dense = simulate(replace(system, tag=_Dense(0)), (0.0, 3.0), {"F": 0.2}, solver="rodas4")
    assert own.status == dense.status == "completed" and not own.warnings
    assert own.stats.events == dense.stats.events > 0
    np.testing.assert_allclose(own["x"][-1], dense["x"][-1], rtol=1e-9)


def test_adapters_are_built_once_per_plant_type_and_sizes():
    system = _linear()
    assert c_functions(system) is c_functions(system)
    other = _linear(k=10.0)                   # other values, the same sizes: the same ones
    assert c_functions(other) is c_functions(system)


def test_a_printed_plant_passes_its_own_c_functions():
    from clutchsim.scenario import load_scenario
    sc = load_scenario(None)
    system = sc.network("mykhailevych2020").build(sc.inputs0())
    fns = plant_functions(system.tag)
    addr = c_functions(system)
    assert addr[:5] == tuple(f.c_address for f in (fns.rhs, fns.events, fns.reset,
                                                    fns.outputs, fns.jac))


def test_a_plant_function_that_is_not_compiled_is_refused_by_name():
    class _Plain(NamedTuple):
        k: int

    def rhs(t, y, u, p, dy):
        dy[0] = 1.0
    register_system(_Plain, rhs=rhs)
    system = System(_Plain(0), np.zeros(0), np.zeros(1), ("x",), ("m",), name="plain")
    with pytest.raises(TypeError, match="neither numba-compiled"):
        c_functions(system)


@pytest.mark.skipif(not cengine.available(), reason="no C compiler to build the C engine")
def test_hand_written_plants_run_in_the_engine_and_give_their_answers():
    for system, inputs in ((oscillator(), {"F": 0.0}), (riccati(), None), (ball(), None)):
        for solver in ("ros34pw2", "dopri5"):
            res = simulate(system, (0.0, 1.0), inputs, solver=solver)
            assert res.status == "completed" and res.solver == solver, res.message
    # and the answers are the plants' own: Riccati's exact solution 1/(1 + t²)
    res = simulate(riccati(), (0.0, 1.0), solver="rodas4")
    np.testing.assert_allclose(res["y"], 1.0 / (1.0 + res.t ** 2), rtol=1e-5)
