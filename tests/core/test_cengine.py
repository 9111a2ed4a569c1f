"""The C engine (core/engine.c) and the numba loop (core/_driver.py) are one loop: on the
same arguments they give the same bits, every output row, event and counter.

Each case prepares a scenario's run as ``simulate`` does and calls both loops directly.
The cases cover the four methods (RODAS5P, RODAS4, the W-method ROS34PW2 with its reused
Jacobian, the explicit DOPRI5 with its own dense output), model (6)'s passing events and
the switching models' resets, input tables and breakpoints, one-way clutches, dog
clutches, a run that stores every step and runs whose rows and event log outgrow the
engine's first buffers (memory it hands over), and the stops: the step budget, the stop
flag another thread sets, chatter.
"""

from __future__ import annotations

import dataclasses
import math
import threading
from pathlib import Path

import numpy as np
import pytest

from clutchsim.core import _driver as drv
from clutchsim.core import cengine
from clutchsim.core.simulate import prepare_runs, simulate
from clutchsim.core.status import Code
from clutchsim.scenario import load_scenario

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

pytestmark = pytest.mark.skipif(not cengine.available(),
                                reason="no C compiler to build the C engine here")


def _args(name, model=None, solver=None, **options):
    sc = load_scenario(EXAMPLES / name)
    model = model or (sc.models[0] if sc.models else None)
    system = sc.system(model)
    inputs = {n: sc.inputs[n] for n in system.input_names}
    opts = dataclasses.replace(sc.options, **options)
    prep = prepare_runs(system, (0.0, sc.t_end), inputs, solver=solver or sc.solver,
                        options=opts)
    args = list(prep.args)
    args[6] = np.ascontiguousarray(system.y0, dtype=float)
    args[7] = system.params.copy()
    args[13] = prep.args[13].copy()
    return system, args


def _both(args):
    """(numba's result, the engine's result) on the same arguments (each with its own
    parameter vector: a plant may switch its values at events)."""
    engine = cengine.engine_for(args)
    assert engine is not None, "a printed plant must run in the C engine"
    a = list(args)
    a[7] = args[7].copy()
    ref = drv.integrate(*a)
    b = list(args)
    b[7] = args[7].copy()
    got = engine(b)
    assert got is not None
    return ref, got


def _assert_same(ref, got):
    names = ("status", "t_end", "info_k", "info_i", "t", "y", "u", "outputs", "ev_t", "ev_k",
             "ev_a", "stats", "h_smallest")
    for name, r, g in zip(names, ref[:13], got[:13]):
        if isinstance(r, np.ndarray):
            assert r.shape == g.shape, f"{name}: shape {g.shape}, numba {r.shape}"
            assert np.array_equal(r, g, equal_nan=True), (
                f"{name}: largest difference {np.nanmax(np.abs(np.asarray(r, float) - g))}")
        else:
            assert r == g, f"{name}: {g} against numba's {r}"


CASES = [
    ("launch.toml", "mykhailevych2020", None),      # RODAS5P, 121 passing events
    ("launch.toml", "coulomb-robust", None),        # a stick/slip clutch's resets
    ("launch.toml", "coulomb-robust", "dopri5"),    # explicit, polynomial dense output
    ("launch_wear.toml", "mykhailevych2020", None),  # ROS34PW2 (W-method)
    ("launch_actuated.toml", "coulomb-robust", None),
    ("hill_start.toml", "coulomb-robust", None),
    ("dog_clutch.toml", None, None),
    ("one_way_clutch.toml", None, None),
    ("lossy_gear_demo2.toml", None, None),
    ("dct_upshift.toml", None, None),
    ("test_speed_rotational.toml", None, None),
    ("elasto_gap.toml", None, None),
]


@pytest.mark.parametrize(("name", "model", "solver"), CASES,
                         ids=[f"{n}-{m}-{s}" for n, m, s in CASES])
def test_the_engine_gives_the_numba_loops_bits(name, model, solver):
    _, args = _args(name, model, solver)
    ref, got = _both(args)
    assert ref[0] in (Code.DONE, Code.EVENT_STOP)
    _assert_same(ref, got)


def test_rows_and_events_beyond_the_first_buffers_are_handed_over():
    """Every step stored (no output grid: the engine starts with 4,096 rows) and 1,700
    events (256 to start with): the engine continues in memory of its own, which the
    arrays then own."""
    _, args = _args("launch_dmf.toml", "mykhailevych2020", dt_out=0.0)
    ref, got = _both(args)
    assert ref[11][drv.S_OUTPUT] > 4096 and ref[11][drv.S_EVENTS] > 256
    _assert_same(ref, got)
    ts, ev_t = got[4], got[8]
    assert ts.flags.c_contiguous and ev_t.flags.c_contiguous
    del ref, got, ts, ev_t      # the engine's memory is freed with the arrays (no crash)


def test_a_step_budget_and_chatter_end_the_run_as_in_the_numba_loop():
    _, args = _args("launch.toml", "mykhailevych2020", max_steps=300)
    ref, got = _both(args)
    assert ref[0] == Code.MAX_STEPS
    _assert_same(ref, got)
    _, args = _args("launch.toml", "coulomb-naive")
    ref, got = _both(args)
    assert ref[0] == Code.CHATTER
    _assert_same(ref, got)


def test_the_stop_flag_set_by_another_thread_ends_the_run():
    """The watcher thread of ``simulate`` sets ``iopt[I_STOP]`` while the engine runs
    without the GIL; the engine reads it every 256 steps and ends as at the wall-time
    budget."""
    _, args = _args("ten_launches.toml", "mykhailevych2020")
    engine = cengine.engine_for(args)
    iopt = args[13]
    timer = threading.Timer(0.05, lambda: iopt.__setitem__(drv.I_STOP, 1))
    timer.start()
    out = engine(args)
    timer.join()
    assert out[0] == Code.WALL_TIME and out[1] < 50.0


def _simulate(name):
    sc = load_scenario(EXAMPLES / name)
    system = sc.system(sc.models[0] if sc.models else None)
    inputs = {n: sc.inputs[n] for n in system.input_names}
    return simulate(system, (0.0, sc.t_end), inputs, solver=sc.solver, options=sc.options)


def test_without_the_engine_runs_take_the_numba_loop_with_the_same_result(monkeypatch):
    """A machine where the engine cannot be built (no C compiler: its plants are numba's
    too, tests/cgen) runs every plant in the numba loop, with the engine's results."""
    import importlib
    via_engine = _simulate("lossy_gear_demo2.toml")
    monkeypatch.setitem(cengine._state, "lib", None)
    monkeypatch.setattr(importlib.import_module("clutchsim.core.simulate"), "_PREPARED", {})
    assert not cengine.available()
    _, args = _args("lossy_gear_demo2.toml")
    assert cengine.engine_for(args) is None
    via_numba = _simulate("lossy_gear_demo2.toml")
    assert np.array_equal(via_engine.t, via_numba.t)
    for name in via_engine.signals:
        assert np.array_equal(via_engine[name], via_numba[name], equal_nan=True), name
    assert via_engine.stats.steps == via_numba.stats.steps


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
    assert len(said) == 1 and "no C compiler found" in said[0] and "numba loop" in said[0]


def test_a_plant_of_numba_functions_takes_the_numba_loop():
    """A hand-written plant's functions are numba's (no C address): the numba loop."""
    from clutchsim.core.reference_problems import oscillator
    prep = prepare_runs(oscillator(), (0.0, 1.0), {"F": 0.0})
    assert cengine.engine_for(prep.args) is None
    assert simulate(oscillator(), (0.0, 1.0), {"F": 0.0}).status == "completed"


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
