"""Every row of a sweep is the run of its variant on its own, bit for bit.

The sweep's fast path (the plan built once, a variant's values packed on it, the loop's
arguments prepared once per sweep, one table per chunk) must give the same table as
running each variant alone the ordinary way (``run_scenario`` with the overrides: parse,
validate, build the chain, simulate, analyse), whatever the chunking and the threads.
"""

from __future__ import annotations

import math

import pytest

from clutchsim.scenario import run_scenario
from clutchsim.scenario.loader import toml_value
from clutchsim.studies.sweeps import DEFAULT_METRICS, SweepOptions, SweepSpec, sweep

BASE = ["scenario.t_end=1.3", "solver.dt_out=0.005"]
MODEL = "mykhailevych2020"
# grades up to 12 %: some variants stall (the engine's event ends the run)
VARY = {"vehicle.mass": "uniform(1000, 1700)", "vehicle.grade": "uniform(0, 12)",
        "coupling[0].friction.overrides.phi0": "uniform(9e-4, 1.1e-3)"}


@pytest.fixture(scope="module")
def table(tmp_path_factory):
    out = tmp_path_factory.mktemp("rows") / "s"
    return sweep(None, SweepSpec(vary=VARY, samples=10, seed=5, model=MODEL, overrides=BASE),
                 SweepOptions(chunk_size=3, workers=2), out=out).table


def _alone(row) -> dict:
    sets = [f"{k}={toml_value(float(row[k]))}" for k in VARY]
    lr = run_scenario(None, MODEL, overrides=BASE + sets)
    m = lr.metrics
    want = {"status": lr.result.status, "outcome": m["outcome"], "message": m["message"],
            "warnings": list(m["warnings"])}
    for k in DEFAULT_METRICS:
        v = m[k]
        want[k] = None if isinstance(v, float) and not math.isfinite(v) else v
    return want


def test_each_row_is_its_variant_run_alone(table):
    assert set(table["outcome"]) >= {"completed", "stalled"}   # both kinds of run occur
    for _, row in table.iterrows():
        want = _alone(row)
        got = {"status": row["status"], "outcome": row["outcome"],
               "message": row["message"], "warnings": list(row["warnings"])}
        for k in DEFAULT_METRICS:
            v = row[k]
            got[k] = None if v is None or (isinstance(v, float) and math.isnan(v)) else \
                type(want[k])(v) if want[k] is not None else v
        assert got == want, f"run {row['run']}"


def test_chunking_and_threads_do_not_change_a_row(table, tmp_path):
    one = sweep(None, SweepSpec(vary=VARY, samples=10, seed=5, model=MODEL, overrides=BASE),
                SweepOptions(workers=1), out=tmp_path / "one").table
    assert one.equals(table)
