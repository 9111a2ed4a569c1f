"""A sweep's chunk runs as one compiled batch (clutchsim.analysis.launch_batch), and its rows are
those of the variants run one by one, to the bit: completed, stalled, chatter and
warned runs alike.  What the batch cannot run (traces, a controller) runs one by one."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from clutchsim.analysis.launch_batch import batch_supported, launch_batch
from clutchsim.scenario import load_scenario
from clutchsim.scenario.run import batch_reason
from clutchsim.scenario.variants import VariantPlan
from clutchsim.studies.sweeps import (
    DEFAULT_METRICS,
    SweepOptions,
    SweepSpec,
    backends,
    runner,
    sweep,
)

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

MODEL = "mykhailevych2020"
BASE = ["scenario.t_end=1.3", "solver.dt_out=0.005"]


def _sweep(tmp_path, monkeypatch, name, batch, scenario=None, chunk_size=None, **kw):
    """``sweep(scenario, SweepSpec(**kw))`` with the batch on or off; returns (table, runs
    batched)."""
    counted = {"batched": 0}
    original = runner.run_chunk

    def run_chunk(job, runs):
        out = original({**job, "batch": batch}, runs)
        counted["batched"] += out["batched"]
        return out
    monkeypatch.setattr(backends, "run_chunk", run_chunk)
    res = sweep(scenario, SweepSpec(**kw), SweepOptions(workers=1, chunk_size=chunk_size),
                out=tmp_path / name)
    return res.table, counted["batched"]


def _same_tables(a, b):
    assert list(a.columns) == list(b.columns)
    for col in a.columns:
        if col == "wall_s":
            continue
        for x, y in zip(a[col], b[col]):
            if isinstance(x, np.ndarray) or isinstance(y, np.ndarray):
                assert list(x) == list(y), col
            elif isinstance(x, float) and math.isnan(x):
                assert isinstance(y, float) and math.isnan(y), col
            else:
                assert x == y, col


@pytest.mark.parametrize("model, vary, overrides, outcomes", [
    # completed and stalled launches (grades up to 14 %)
    (MODEL, {"vehicle.mass": "uniform(1000, 1700)", "vehicle.grade": "uniform(0, 14)",
             "coupling[0].friction.overrides.phi0": "uniform(9e-4, 1.1e-3)"}, BASE,
     {"completed", "stalled"}),
    # the naive stick/slip model is stopped by chatter detection at lock-up
    ("coulomb-naive", {"vehicle.mass": "uniform(1100, 1500)"}, BASE, {"chatter"}),
    # too short to lock up: every run completes with the "never locked up" warning
    (MODEL, {"vehicle.mass": "uniform(1100, 1500)"}, ["scenario.t_end=0.4"], {"completed"}),
])
def test_batched_rows_are_the_rows_run_one_by_one(tmp_path, monkeypatch, model, vary,
                                                   overrides, outcomes):
    kw = {"scenario": None, "vary": vary, "samples": 7, "seed": 3, "model": model, "overrides": overrides,
              "chunk_size": 4, "metrics": list(DEFAULT_METRICS)}
    batched, n = _sweep(tmp_path, monkeypatch, "b", True, **kw)
    single, n_single = _sweep(tmp_path, monkeypatch, "s", False, **kw)
    assert (n, n_single) == (7, 0)
    assert set(batched["outcome"]) >= outcomes
    _same_tables(batched, single)
    if overrides == ["scenario.t_end=0.4"]:
        assert all(any("never locked up" in w for w in ws) for ws in batched["warnings"])
    if model == "coulomb-naive":
        assert all(m.startswith("stopped by chatter detection at clutch lock-up")
                   for m in batched["message"])


def test_traces_and_rebuild_keys_run_one_by_one(tmp_path, monkeypatch):
    kw = {"scenario": None, "vary": {"vehicle.mass": [1200.0, 1300.0]}, "model": MODEL,
              "overrides": BASE}
    _t, n = _sweep(tmp_path, monkeypatch, "t", True, keep_traces=True, **kw)
    assert n == 0
    # a solver key is a rebuild key: its variants are built from the scenario text
    _t, n = _sweep(tmp_path, monkeypatch, "r", True, scenario=None,
                   vary={"solver.rtol": [1e-5, 2e-5]}, model=MODEL, overrides=BASE)
    assert n == 0


def test_a_controller_scenario_is_not_batched_and_says_why():
    sc = load_scenario(EXAMPLES / "launch_closed_loop.toml")
    plan = VariantPlan(sc, None)
    assert "controller" in batch_reason(sc, plan.base_system())


def test_a_span_longer_than_the_filter_grid_is_not_batched():
    plan = VariantPlan(load_scenario(None), MODEL)
    system = plan.base_system()
    assert batch_supported(system, (0.0, 4.0), "clutch") == ""
    assert "filter step" in batch_supported(system, (0.0, 5000.0), "clutch")


def test_bad_batches_are_refused_with_the_variant_and_entry():
    sc = load_scenario(None)
    plan = VariantPlan(sc, MODEL)
    system = plan.base_system()
    p = np.array([system.params, system.params])
    y0 = np.array([system.y0, system.y0])
    kw = {"clutch": "clutch", "solver": "rodas5p", "options": sc.options}
    with pytest.raises(ValueError, match="shape"):
        launch_batch(system, (0.0, 1.0), {n: sc.inputs[n] for n in system.input_names},
                     p[:, :-1], y0, **kw)
    p[1, 3] = np.nan
    with pytest.raises(ValueError, match="variant 1: parameter vector entry 3 = nan"):
        launch_batch(system, (0.0, 1.0), {n: sc.inputs[n] for n in system.input_names},
                     p, y0, **kw)
    with pytest.raises(ValueError, match="compiled method"):
        launch_batch(system, (0.0, 1.0), {n: sc.inputs[n] for n in system.input_names},
                     y0=y0[:1], params=np.array([system.params]),
                     **{**kw, "solver": "scipy-rk45"})


def test_the_warmup_compiles_the_kernel_signature_a_batch_calls():
    """``kernel_signature_example`` (what the warm-up compiles in a second process) has the
    types the batch passes: the run's time column (the integrator's ``ts[:n]``), contiguous
    copies of the columns ``_column`` cuts from its rows, the constants the batch passes
    on; and that is the single run's specialisation (one compilation for both)."""
    import numba

    from clutchsim.analysis import launch_batch as lb
    from clutchsim.analysis.launch_metrics import kernel_signature

    example = lb.kernel_signature_example()

    @numba.njit
    def first_rows(a, n):           # as the integrator returns its rows
        return a[:n]

    @numba.njit
    def copied_column(rows, n):     # as the batch passes a column on
        return np.ascontiguousarray(lb._column(rows, rows, rows, n, 0, 1, rows[:0, 0]))

    first_rows(np.zeros(3), 2)
    assert numba.typeof(example[0]) == first_rows.nopython_signatures[0].return_type
    copied_column(np.zeros((3, 2)), 2)
    column = copied_column.nopython_signatures[0].return_type
    assert all(numba.typeof(x) == column for x in example[1:10])
    assert numba.typeof(example[10]) == numba.typeof(np.empty(0))     # the clutch's events
    assert [numba.typeof(x) for x in example[11:]] == \
        [numba.typeof(x) for x in lb._kernel_constants(1.0)]
    assert tuple(numba.typeof(x) for x in example) == kernel_signature()
    assert len(example) == lb._k.launch_kernel.py_func.__code__.co_argcount
