"""The C engine (core/engine.c) against stored references: the numba loop's results
(core/_driver.py, recorded at f2e613f, when the engine gave its bits on every case; the
numba loop was then deleted, issue 41).

Each case prepares a run as ``simulate`` does and calls the engine directly.  The cases
cover the four methods (RODAS5P, RODAS4, the W-method ROS34PW2 with its reused Jacobian,
the explicit DOPRI5 with its own dense output), model (6)'s passing events and the
switching models' resets, input tables and breakpoints, one-way clutches, dog clutches, a
run that stores every step and whose rows and event log outgrow the engine's first
buffers (memory it hands over), the stops (the step budget, chatter, the stop flag another
thread sets), and plants of numba functions (the reference problems, through their
adapters, core/_cfunctions.py).  Counters, row and event counts, end codes and event
indices must be equal; times and values agree to 1e-12 relative (the bits agree on this
machine and compiler: the SHA-256 of every array is stored too, and its mismatch alone is
reported, not failed, since another compiler may contract a product differently).

``python tests/core/test_cengine.py --record`` writes the references again from the
engine, for a deliberate change of the numerics (say which in the commit).
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import sys
import threading
import warnings
from pathlib import Path

import numpy as np
import pytest

from clutchsim.core import cengine
from clutchsim.core import reference_problems as rp
from clutchsim.core.simulate import prepare_runs, simulate
from clutchsim.core.status import Code
from clutchsim.scenario import load_scenario

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
REFS = Path(__file__).with_name("engine_refs.json")

pytestmark = pytest.mark.skipif(not cengine.available(),
                                reason="no C compiler to build the C engine here")

#: (example, model, solver, options)
SCENARIO_CASES = [
    ("launch.toml", "mykhailevych2020", None, {}),          # RODAS5P, 121 passing events
    ("launch.toml", "coulomb-robust", None, {}),            # a stick/slip clutch's resets
    ("launch.toml", "coulomb-robust", "dopri5", {}),        # explicit, polynomial dense output
    ("launch_wear.toml", "mykhailevych2020", None, {}),     # ROS34PW2 (W-method)
    ("launch_actuated.toml", "coulomb-robust", None, {}),
    ("hill_start.toml", "coulomb-robust", None, {}),
    ("dog_clutch.toml", None, None, {}),
    ("one_way_clutch.toml", None, None, {}),
    ("lossy_gear_demo2.toml", None, None, {}),
    ("dct_upshift.toml", None, None, {}),
    ("test_speed_rotational.toml", None, None, {}),
    ("elasto_gap.toml", None, None, {}),
    # every step a row (4,096 to start with) and 1,753 events (256): handed-over memory
    ("launch_dmf.toml", "mykhailevych2020", None, {"dt_out": 0.0}),
    ("launch.toml", "mykhailevych2020", None, {"max_steps": 300}),   # the step budget
    ("launch.toml", "coulomb-naive", None, {}),                       # chatter
]
#: (reference problem, solver): plants of numba functions
PLANT_CASES = [(name, solver) for name in ("ball", "oscillator", "van_der_pol", "sign_switch",
                                           "monitored_oscillator", "stiff_tracker")
               for solver in ("rodas4", "dopri5", "ros34pw2")]


def _scenario_args(name, model=None, solver=None, **options):
    sc = load_scenario(EXAMPLES / name)
    model = model or (sc.models[0] if sc.models else None)
    system = sc.system(model)
    inputs = {n: sc.inputs[n] for n in system.input_names}
    opts = dataclasses.replace(sc.options, **options)
    prep = prepare_runs(system, (0.0, sc.t_end), inputs, solver=solver or sc.solver,
                        options=opts)
    return system, _own(prep, system)


def _plant_args(name, solver):
    system = getattr(rp, name)()
    prep = prepare_runs(system, (0.0, 3.0), {n: 0.0 for n in system.input_names},
                        solver=solver)
    return system, _own(prep, system)


def _own(prep, system):
    """The run's arguments with its own initial state, parameters and int options."""
    args = list(prep.args)
    args[6] = np.ascontiguousarray(system.y0, dtype=float)
    args[7] = system.params.copy()
    args[13] = prep.args[13].copy()
    return args


def _run(system, args):
    engine = cengine.engine_for(args, system.n_states)
    assert engine is not None, "every plant within the bounds runs in the C engine"
    return engine(args)


def digest(out) -> dict:
    """What is stored of an engine result: its scalars and counters, rows at a third, two
    thirds and the end, up to 48 events spread over the log, and the SHA-256 of every
    array."""
    (status, t_end, k, i, ts, ys, us, outs, ev_t, ev_k, ev_a, st, h_small) = out[:13]
    h = hashlib.sha256()
    for a in (ts, ys, us, outs, ev_t, ev_k, ev_a):
        h.update(np.ascontiguousarray(a).tobytes())
    n, ne = ts.shape[0], ev_t.shape[0]
    idx = sorted(set(np.linspace(0, ne - 1, min(ne, 48)).round().astype(int).tolist())
                 ) if ne else []
    return {"status": int(status), "t_end": float(t_end), "info_k": int(k), "info_i": int(i),
            "stats": [int(x) for x in st], "h_smallest": float(h_small), "rows": int(n),
            "t": [float(x) for x in ts[[0, n // 3, 2 * n // 3, n - 1]]],
            "y": [[float(x) for x in ys[j]] for j in (n // 3, 2 * n // 3, n - 1)],
            "outputs": [float(x) for x in outs[n - 1]],
            "ev_t": [float(ev_t[j]) for j in idx], "ev_k": [int(ev_k[j]) for j in idx],
            "ev_a": [int(ev_a[j]) for j in idx], "sha256": h.hexdigest(), "ev_index": idx}


def _assert_matches(got: dict, ref: dict) -> None:
    for key in ("status", "info_k", "info_i", "stats", "rows", "ev_k", "ev_a", "ev_index"):
        assert got[key] == ref[key], f"{key}: {got[key]} against the reference {ref[key]}"
    for key in ("t_end", "h_smallest", "t", "y", "outputs", "ev_t"):
        np.testing.assert_allclose(np.asarray(got[key], float), np.asarray(ref[key], float),
                                   rtol=1e-12, atol=0.0, err_msg=key)
    if got["sha256"] != ref["sha256"]:
        warnings.warn("the engine's arrays agree with the reference to 1e-12, not to the "
                      "bit (another compiler or CPU?)", stacklevel=2)


def _key(name, model, solver, options):
    return f"{name}|{model}|{solver}|{json.dumps(options, sort_keys=True)}"


@pytest.fixture(scope="module")
def refs():
    return json.loads(REFS.read_text())


@pytest.mark.parametrize(("name", "model", "solver", "options"), SCENARIO_CASES,
                         ids=[f"{n}-{m}-{s}-{'-'.join(o)}" for n, m, s, o in SCENARIO_CASES])
def test_the_engine_gives_the_recorded_runs(refs, name, model, solver, options):
    system, args = _scenario_args(name, model, solver, **options)
    ref = refs[_key(name, model or _default_model(name), solver, options)]
    _assert_matches(digest(_run(system, args)), ref)


@pytest.mark.parametrize(("name", "solver"), PLANT_CASES,
                         ids=[f"{n}-{s}" for n, s in PLANT_CASES])
def test_plants_of_numba_functions_give_the_recorded_runs(refs, name, solver):
    system, args = _plant_args(name, solver)
    _assert_matches(digest(_run(system, args)), refs[f"{name}|{solver}"])


def _default_model(name):
    sc = load_scenario(EXAMPLES / name)
    return sc.models[0] if sc.models else None


def test_rows_and_events_beyond_the_first_buffers_are_handed_over():
    """Every step stored (no output grid: the engine starts with 4,096 rows) and 1,753
    events (256 to start with): the engine continues in memory of its own, which the
    arrays then own."""
    system, args = _scenario_args("launch_dmf.toml", "mykhailevych2020", dt_out=0.0)
    got = _run(system, args)
    assert got[11][cengine.S_OUTPUT] > 4096 and got[11][cengine.S_EVENTS] > 256
    ts, ev_t = got[4], got[8]
    assert ts.flags.c_contiguous and ev_t.flags.c_contiguous
    del got, ts, ev_t       # the engine's memory is freed with the arrays (no crash)


def test_the_stop_flag_set_by_another_thread_ends_the_run():
    """The watcher thread of ``simulate`` sets ``iopt[I_STOP]`` while the engine runs
    without the GIL; the engine reads it every 256 steps and ends as at the wall-time
    budget."""
    system, args = _scenario_args("ten_launches.toml", "mykhailevych2020")
    engine = cengine.engine_for(args, system.n_states)
    iopt = args[13]
    timer = threading.Timer(0.05, lambda: iopt.__setitem__(cengine.I_STOP, 1))
    timer.start()
    out = engine(args)
    timer.join()
    assert out[0] == Code.WALL_TIME and out[1] < 50.0


def _simulate(name):
    sc = load_scenario(EXAMPLES / name)
    system = sc.system(sc.models[0] if sc.models else None)
    inputs = {n: sc.inputs[n] for n in system.input_names}
    return simulate(system, (0.0, sc.t_end), inputs, solver=sc.solver, options=sc.options)


def test_without_the_engine_runs_take_the_reference_backend_and_say_so(monkeypatch):
    """A machine where the engine cannot be built (no C compiler) runs every plant on
    scipy's reference backend (Radau for the implicit methods): the run completes within
    the tolerances of the engine's, and its result says which integrator made it and
    why."""
    import importlib
    via_engine = _simulate("lossy_gear_demo2.toml")
    monkeypatch.setitem(cengine._state, "lib", None)
    monkeypatch.setattr(importlib.import_module("clutchsim.core.simulate"), "_PREPARED", {})
    assert not cengine.available()
    fallback = _simulate("lossy_gear_demo2.toml")
    assert fallback.status == "completed", fallback.message
    assert fallback.solver == "scipy-radau"
    assert any("not available here" in w and "scipy's RADAU" in w for w in fallback.warnings)
    assert not via_engine.warnings
    for name in ("omega_in", "omega_out"):
        if name in via_engine.signals:
            scale = float(np.max(np.abs(via_engine[name]))) + 1.0
            assert abs(fallback[name][-1] - via_engine[name][-1]) < 1e-3 * scale, name


def test_an_engine_that_cannot_be_built_is_said_once(monkeypatch, caplog):
    from clutchsim import _cc

    def no_compiler():
        raise _cc.NoCompilerError("no C compiler found (looked for cc, gcc, clang on the PATH)")
    monkeypatch.setattr(cengine, "_state", {})
    monkeypatch.setattr(cengine, "_build", no_compiler)
    with caplog.at_level("WARNING", logger="clutchsim"):
        assert cengine._library() is None
        assert cengine._library() is None
    said = [r.getMessage() for r in caplog.records if "C integration engine" in r.getMessage()]
    assert len(said) == 1 and "no C compiler found" in said[0]
    assert "reference backend" in said[0]


def test_a_plant_beyond_the_engine_s_bounds_takes_the_reference_backend(monkeypatch):
    """Bounds are the engine's fixed scratch sizes (states, events, outputs, ...): a plant
    beyond one runs on the reference backend, and the result names the bound."""
    monkeypatch.setattr(cengine, "MAX_STATES", 1)
    import importlib
    monkeypatch.setattr(importlib.import_module("clutchsim.core.simulate"), "_PREPARED", {})
    res = simulate(rp.ball(), (0.0, 1.0))
    assert res.status == "completed" and res.solver == "scipy-radau"
    assert any("2 states, beyond the C engine's 1" in w for w in res.warnings), res.warnings
    assert cengine.beyond_bounds(prepare_runs(rp.ball(), (0.0, 1.0)).args, 2)


def test_a_batch_whose_runs_outgrow_the_engine_s_buffers_gives_the_single_runs_rows():
    """A sweep's batch calls the engine from numba (``cengine.integrate_nb``); a run whose
    events outgrow its first rows (model (6) on the dual-mass flywheel: 1,750 events, 256
    rows beyond the output grid) is made again with room for all of them, and its metrics
    are the single run's."""
    from clutchsim.scenario.run import run_batch, run_system
    sc = load_scenario(EXAMPLES / "launch_dmf.toml")
    system = sc.system("mykhailevych2020")
    batched = run_batch(sc, system, [(system.params.copy(), system.y0.copy(), None)] * 2)
    single = run_system(sc, system, "mykhailevych2020")
    assert single.result.stats.events > 256
    for status, metrics in batched:
        assert status == single.result.status
        for key, value in single.metrics.items():
            if key not in ("wall_s", "loop_wall_s"):
                both_nan = isinstance(value, float) and math.isnan(value) and math.isnan(
                    metrics[key])
                assert metrics[key] == value or both_nan, key


def _record() -> None:
    """Write the references from this engine (see the module docstring)."""
    out = {}
    for name, model, solver, options in SCENARIO_CASES:
        system, args = _scenario_args(name, model, solver, **options)
        out[_key(name, model or _default_model(name), solver, options)] = digest(
            _run(system, args))
    for name, solver in PLANT_CASES:
        system, args = _plant_args(name, solver)
        out[f"{name}|{solver}"] = digest(_run(system, args))
    REFS.write_text(json.dumps(out, separators=(",", ":")))


if __name__ == "__main__":
    if sys.argv[1:] != ["--record"]:
        sys.exit("usage: python tests/core/test_cengine.py --record")
    _record()
