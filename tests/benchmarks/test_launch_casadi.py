"""The CasADi launch model of benchmarks/launch_speed.py is the same model as clutchsim's.

Loaded from its file like ``test_launch_plain.py`` (``benchmarks/`` is not a package);
skipped when the benchmark scripts are not present or casadi (the optional ``bench``
extra) is not installed.
"""

from __future__ import annotations

import importlib.util
import math
import sys
from pathlib import Path

import numpy as np
import pytest

_DIR = Path(__file__).resolve().parents[2] / "benchmarks"


def _load(name: str):
    """Import ``benchmarks/<name>.py`` under its own name (``_launch_casadi`` imports
    ``_launch_plain`` by that name)."""
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(name, _DIR / f"{name}.py")
        mod = importlib.util.module_from_spec(spec)
        sys.modules[name] = mod         # dataclasses look the module up while it loads
        spec.loader.exec_module(mod)
    return sys.modules[name]


@pytest.fixture(scope="module")
def cas():
    if not (_DIR / "_launch_casadi.py").is_file():
        pytest.skip(f"{_DIR / '_launch_casadi.py'} not present (benchmarks are not installed)")
    pytest.importorskip("casadi", minversion="3.6",
                        reason="casadi >= 3.6 is not installed (optional extra 'bench')")
    _load("_launch_plain")
    return _load("_launch_casadi")


@pytest.fixture(scope="module")
def tight():
    """clutchsim's default launch, 0-2 s at rtol = atol = 1e-8."""
    from clutchsim.scenario import load_scenario, run_scenario
    sc = load_scenario(None, overrides=["solver.rtol=1e-8", "solver.atol=1e-8",
                                        "solver.wall_time=100000", "scenario.t_end=2.0"])
    return sc, run_scenario(sc, "mykhailevych2020").result


def test_casadi_rhs_is_the_plain_rhs(cas):
    from clutchsim.scenario import load_scenario
    par = sys.modules["_launch_plain"].launch_params(load_scenario(None))
    assert cas.rhs_mismatch(par, n_states=200) < 1e-12


def test_unknown_solver_is_refused(cas):
    from clutchsim.scenario import load_scenario
    par = sys.modules["_launch_plain"].launch_params(load_scenario(None))
    with pytest.raises(ValueError, match="solver='rk4'"):
        cas.build(par, "rk4")


@pytest.mark.slow
@pytest.mark.parametrize(("solver", "max_order"),
                         [("cvodes", None), ("idas", None), ("cvodes", 2), ("idas", 2)])
def test_casadi_launch_matches_clutchsim(cas, tight, solver, max_order):
    plain = sys.modules["_launch_plain"]
    sc, ref = tight
    par = plain.launch_params(sc)
    dt = sc.options.dt_out
    run = cas.simulate_casadi(cas.build(par, solver, 1e-8, 1e-8, dt, max_order=max_order))
    assert run.status == "completed"
    diff = plain.speed_diff_rpm(ref.t, ref, run.t, {n: run[n] for n in plain.SPEEDS}, dt)
    assert diff["grid_points"] == math.floor(par.t_end / dt + 1e-9) + 1
    assert max(diff[n] for n in plain.SPEEDS) <= plain.SPEED_TOL_RPM
    # the first slip zero crossing (lock-up) is located and model (6)'s reset applied:
    # the integrated slip, about -100 rad before it, is clamped to 2·phi0 and stays small
    first = next(e.t for e in ref.events if "velocity_zero_crossing" in e.name)
    assert abs(run.events[0] - first) < 1e-6
    before, after = run.t < run.events[0], run.t > run.events[0]
    assert np.max(np.abs(run["phi_clutch"][before])) > 1.0
    assert np.max(np.abs(run["phi_clutch"][after])) <= par.reset_c * par.phi0 * 1.5
    _, rows = plain.grid_rows(ref.t, dt)
    lk_ref = plain.lockup_time(ref.t[rows], ref["w_slip_clutch"][rows],
                               ref["capacity_clutch"][rows])
    assert plain.lockup_time(run.t, run.slip, run.capacity) == pytest.approx(lk_ref, abs=1e-3)


@pytest.mark.parametrize("solver", ["cvodes", "idas"])
def test_stall_ends_the_run_as_in_the_plain_model(cas, solver):
    """No throttle and no idle governor: the engine stalls at 0.59 s, before the clutch
    closes; both models stop at the same grid point with the same speeds."""
    import dataclasses

    from clutchsim.scenario import load_scenario
    plain = sys.modules["_launch_plain"]
    par = dataclasses.replace(plain.launch_params(load_scenario(None)), throttle=(0.0, ()),
                              idle=0.0, kp=0.0, ki=0.0)
    ref = plain.simulate_plain(par, "LSODA", 1e-8, 1e-8)
    run = cas.simulate_casadi(cas.build(par, solver, 1e-8, 1e-8))
    assert ref.status == run.status == "stalled"
    assert run.t[-1] == pytest.approx(ref.t[-1], abs=1e-12) and run.t[-1] < par.t_end / 2
    diff = plain.speed_diff_rpm(ref.t, {n: ref[n] for n in plain.SPEEDS}, run.t,
                                {n: run[n] for n in plain.SPEEDS}, 0.002)
    assert diff["grid_points"] == ref.t.size
    assert max(diff[n] for n in plain.SPEEDS) < 1e-3


@pytest.mark.parametrize("installed", [None, "3.5.5"])
def test_launch_speed_without_casadi_reports_null_rows(monkeypatch, installed):
    """Without casadi >= 3.6 the benchmark still runs: CasADi keys null, a reason given."""
    if not (_DIR / "launch_speed.py").is_file():
        pytest.skip(f"{_DIR / 'launch_speed.py'} not present (benchmarks are not installed)")
    for name in ("_common", "_launch_plain"):
        _load(name)
    bench = _load("launch_speed")

    def version(dist):
        if installed is None:
            raise bench.importlib.metadata.PackageNotFoundError(dist)
        return installed

    monkeypatch.setattr(bench.importlib.metadata, "version", version)
    monkeypatch.setattr(bench, "run_baseline", lambda *args: pytest.fail("child started"))
    out = {}
    bench.casadi_rows(None, out, {"ms": 1.0, "ref": None, "dt": 0.002, "err": None})
    assert out["ratio_vs_casadi"] is None and out["casadi_version"] is None
    assert {c[1] for c in bench.CASADI} >= {"casadi_cvodes", "casadi_idas"}
    for key in (c[1] for c in bench.CASADI):
        assert out[f"{key}_ms"] is None and out[f"ratio_vs_{key}"] is None
    assert ("not installed" if installed is None else "3.5.5") in out["casadi_note"]
