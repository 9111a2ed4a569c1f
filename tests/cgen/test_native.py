"""Network plants run as C: the printed plant compiled by the system C compiler and called by
the C engine through its C entries (clutchsim.cgen), and numba's own compilation of the
same module where no C compiler is found."""

import logging

import numpy as np
import pytest

from clutchsim.cgen import loader
from clutchsim.core import NativeFunction, SolverOptions, simulate
from clutchsim.core.system import plant_functions
from clutchsim.network import Network
from clutchsim.network import plant as network_plant
from clutchsim.network.components import Inertia, SpringDamper, TorqueSource


def two_mass(c=1e3, J2=2.0):
    return Network([TorqueSource("drive", input="tau"), Inertia("a", J=1.0),
                    SpringDamper("k", c=c, d=0.5), Inertia("b", J=J2)],
                   [["drive.flange", "a.a"], ["a.b", "k.a"], ["k.b", "b.a"]])


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
