"""Network plants run as C: the printed plant compiled by the system C compiler and called by
the integrators through numba's calling convention (clutchsim.cgen), and numba's own
compilation of the same module where no C compiler is found."""

import logging

import numpy as np
import pytest

from clutchsim.cgen import loader
from clutchsim.core import NativeFunction, SolverOptions, simulate
from clutchsim.core.system import plant_functions
from clutchsim.network import Network
from clutchsim.network import plant as network_plant
from clutchsim.network.components import Inertia, SpringDamper, TorqueSource
from clutchsim.scenario import load_scenario

numba = pytest.importorskip("numba")


def random_states(system, rng, k):
    n = len(system.y0)
    for _ in range(k):
        y = system.y0 * (1.0 + 0.5 * rng.standard_normal(n)) + 3.0 * rng.standard_normal(n)
        yield y, rng.uniform(-0.2, 1.2, len(system.input_names)), rng.uniform(0.0, 4.0)


def two_mass(c=1e3, J2=2.0):
    return Network([TorqueSource("drive", input="tau"), Inertia("a", J=1.0),
                    SpringDamper("k", c=c, d=0.5), Inertia("b", J=J2)],
                   [["drive.flange", "a.a"], ["a.b", "k.a"], ["k.b", "b.a"]])


@numba.njit
def _through_function_values(fns, t, y, u, p, dy, g, out, J, k):
    """What the integrators do with a plant: call its five functions as values."""
    fns[0](t, y, u, p, dy)
    fns[1](t, y, u, p, g)
    fns[3](t, y, u, p, out)
    fns[4](t, y, u, p, J)
    return fns[2](t, y, u, p, k)


def test_launch_plant_is_native_and_both_faces_agree():
    """The default launch's plant functions are C (NativeFunction); called as function
    values from compiled code (numba's calling convention: arrays as their structure's
    members) they compute exactly what the same C computes called from Python (plain
    pointers), at random states: rhs, events, outputs, the 2-D Jacobian, the reset's action
    and the state it writes."""
    sc = load_scenario(None)
    system = sc.network("mykhailevych2020").build(sc.inputs0())
    fns = plant_functions(system.tag)
    assert all(isinstance(f, NativeFunction) for f in (fns.rhs, fns.events, fns.reset,
                                                       fns.outputs, fns.jac))
    n, ne, no = system.n_states, system.n_events, len(system.output_names)
    rng = np.random.default_rng(3)
    for y, u, t in random_states(system, rng, 20):
        k = int(rng.integers(0, ne))
        a = [np.zeros(n), np.zeros(ne), np.zeros(no), np.zeros((n, n)), y.copy()]
        values = (fns.rhs, fns.events, fns.reset, fns.outputs, fns.jac)
        action = _through_function_values(values, t, a[4], u, system.params, a[0], a[1],
                                          a[2], a[3], k)
        b = [np.zeros(n), np.zeros(ne), np.zeros(no), np.zeros((n, n)), y.copy()]
        fns.rhs(t, y, u, system.params, b[0])
        fns.events(t, y, u, system.params, b[1])
        fns.outputs(t, y, u, system.params, b[2])
        fns.jac(t, y, u, system.params, b[3])
        assert fns.reset(t, b[4], u, system.params, k) == action
        for x, z in zip(a, b):
            np.testing.assert_array_equal(x, z)
        assert np.any(a[3] != 0.0)


def _two_mass_run():
    options = SolverOptions(rtol=1e-9, atol=1e-11, dt_out=1e-3)
    sys_ = two_mass().build()
    y0 = sys_.y0.copy()
    y0[sys_.state_names.index("phi_k")] = 1e-3
    return sys_, simulate(sys_, (0.0, 0.5), {"tau": 0.0}, y0=y0, options=options)


def _rig_run():
    from clutchsim.friction import make_model
    from clutchsim.rig import make_rig
    sys_ = make_rig(make_model("coulomb-robust"), spring=2.0, pull_speed=0.1)
    return sys_, simulate(sys_, (0.0, 1.5), {"force": 0.0, "scale": 1.0})


@pytest.mark.parametrize(("run", "names"), [
    (_two_mass_run, ("phi_k", "omega_a", "omega_b")),
    (_rig_run, ("x", "v", "mode", "F")),
], ids=["network", "rig"])
def test_without_a_c_compiler_numba_compiles_the_same_plant(run, names, drop_c_compiler,
                                                            caplog):
    """No C compiler: a generated plant's module (a network's, the friction rig's) is
    compiled by numba instead (logged once, with why), and the run is the same up to
    round-off."""
    native_sys, native = run()
    assert isinstance(plant_functions(native_sys.tag).rhs, NativeFunction)

    tmp_path = drop_c_compiler()
    with caplog.at_level(logging.WARNING, logger="clutchsim"):
        fallback_sys, fallback = run()
    assert not isinstance(plant_functions(fallback_sys.tag).rhs, NativeFunction)
    assert not list(tmp_path.glob("*.so"))
    assert any("compiled by numba, not C" in r.getMessage() and "no C compiler" in
               r.getMessage() for r in caplog.records)
    assert fallback.stats.steps == native.stats.steps
    for name in names:
        np.testing.assert_allclose(fallback[name], native[name], rtol=0, atol=1e-12)


def test_the_library_is_built_once_and_reloaded(monkeypatch, tmp_path):
    """A topology's library is written once, atomically, beside its module; a process that
    has not loaded it (a fresh in-memory table) loads the file without compiling again."""
    monkeypatch.setattr(loader, "module_dir", lambda kind: tmp_path)
    monkeypatch.setattr(loader, "_LOADED", {})
    monkeypatch.setattr(network_plant, "_PLANS", {})
    two_mass().build()
    libs = list(tmp_path.glob("*.so"))
    assert len(libs) == 1 and not list(tmp_path.glob(".build-*"))
    stamp = libs[0].stat().st_mtime_ns

    from clutchsim.cgen import compiler

    def must_not_compile(*args, **kwargs):
        raise AssertionError("the library was compiled again")

    monkeypatch.setattr(compiler, "compile_shared", must_not_compile)
    monkeypatch.setattr(loader, "_LOADED", {})
    monkeypatch.setattr(network_plant, "_PLANS", {})
    sys_ = two_mass(c=2e3).build()
    assert isinstance(plant_functions(sys_.tag).rhs, NativeFunction)
    assert libs[0].stat().st_mtime_ns == stamp


def test_a_numba_that_passes_arrays_otherwise_is_refused(monkeypatch):
    """The numba entry points are written for numba's array data model; a numba whose model
    differs is refused with what it passes, so the plant falls back instead of being
    called wrongly."""
    from clutchsim.cgen import CompilerError, compiler
    compiler.check_numba_abi()          # this numba: as written
    compiler.check_numba_abi.cache_clear()
    monkeypatch.setitem(compiler._NB_VALUE_TYPES, compiler.A1,
                        "{ptr, i64, ptr, [1 x i64], [1 x i64]}")
    with pytest.raises(CompilerError, match=r"passes array\(float64, 1d, C\) as \{ptr, ptr, "):
        compiler.check_numba_abi()
    compiler.check_numba_abi.cache_clear()
