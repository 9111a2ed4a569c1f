"""Batch sweeps: designs, the table, failing runs, resume, Dask, bad input."""

from __future__ import annotations

import socket
import time

import numpy as np
import pyarrow.parquet as pq
import pytest

import clutchsim.studies.sweeps as S
from clutchsim.studies.sweeps import (
    SweepError,
    SweepOptions,
    SweepSpec,
    make_design,
    parse_vary,
    read_results,
    sweep,
)

# a short launch (lock-up at ~1.1 s) keeps each run to a fraction of a second
BASE = ["scenario.t_end=1.3", "solver.dt_out=0.005"]
GRID = {"vehicle.mass": "1100:1500:2", "vehicle.grade": "0:40:2"}   # 40 %: the engine stalls


def test_grid_is_the_full_product_first_key_slowest():
    d = make_design(parse_vary(["a.x=0:1:2", "a.y=10,20,30"]))
    assert d.n == 6
    np.testing.assert_array_equal(d.columns["a.x"], [0, 0, 0, 1, 1, 1])
    np.testing.assert_array_equal(d.columns["a.y"], [10, 20, 30, 10, 20, 30])


def test_samples_are_seeded_and_crossed_with_the_grid():
    vary = parse_vary({"a.x": "uniform(1, 2)", "a.g": (0.0, 1.0, 2)})
    d1, d2 = make_design(vary, 5, seed=3), make_design(vary, 5, seed=3)
    assert d1.n == 10
    np.testing.assert_array_equal(d1.columns["a.x"], d2.columns["a.x"])
    np.testing.assert_array_equal(d1.columns["a.x"][:5], d1.columns["a.x"][5:])
    assert np.all((d1.columns["a.x"] >= 1) & (d1.columns["a.x"] <= 2))
    assert not np.array_equal(make_design(vary, 5, seed=4).columns["a.x"], d1.columns["a.x"])


@pytest.mark.parametrize("spec, words", [
    ("1:2:0", "N must be an integer >= 1"), ("2:1:3", "LO > HI"), ("1:2", "LO:HI:N"),
    ("1:2:1.5", "N must be an integer"), ("unifrom(1,2)", "did you mean 'uniform'"),
    ("uniform(2,1)", "a <= b"), ("x", "not a number")])
def test_bad_specs_say_what_is_wrong(spec, words):
    with pytest.raises(SweepError, match=words.replace("(", r"\(")):
        parse_vary([f"vehicle.mass={spec}"])


def test_random_keys_need_samples_and_seed():
    with pytest.raises(SweepError, match="--samples"):
        make_design(parse_vary(["a.x=uniform(1,2)"]))
    with pytest.raises(SweepError, match="--seed"):
        make_design(parse_vary(["a.x=uniform(1,2)"]), 4)


def test_unknown_key_suggests_the_closest(tmp_path):
    with pytest.raises(SweepError, match="did you mean 'mass'"):
        sweep(None, SweepSpec(vary={"vehicle.mas": "1000:1200:2"}, overrides=BASE),
              out=tmp_path / "s")
    with pytest.raises(SweepError, match="vehicle.mass"):
        sweep(None, SweepSpec(vary={"vehicle.mass": "-5:1200:2"}, overrides=BASE),
              out=tmp_path / "s")


def test_a_table_key_on_a_network_scenario_names_the_component_key(tmp_path):
    from pathlib import Path

    from clutchsim.scenario import load_scenario
    path = Path(__file__).resolve().parents[2] / "examples" / "launch_dmf.toml"
    comps = load_scenario(path).data["component"]
    i = next(i for i, c in enumerate(comps) if c.get("type") == "vehicle")
    with pytest.raises(SweepError, match=rf"did you mean component\[{i}\]\.mass\?"):
        sweep(path, SweepSpec(vary={"vehicle.mass": "1200:1400:2"}), out=tmp_path / "s")


@pytest.fixture(scope="module")
def grid_sweep(tmp_path_factory):
    out = tmp_path_factory.mktemp("grid") / "sweep"
    return sweep(None, SweepSpec(vary=GRID, overrides=BASE), SweepOptions(chunk_size=2,
                 workers=2), out=out, plots=True)


def test_failing_variants_are_rows_and_the_sweep_goes_on(grid_sweep):
    t = grid_sweep.table
    assert list(t["run"]) == [0, 1, 2, 3]
    ok = t["vehicle.grade"] == 0.0
    assert (t["status"][ok] == "completed").all()
    assert (t["status"][~ok] == "failed").all()
    assert t["message"][~ok].str.contains("engine stalled").all()
    assert t["engine_stalled"][~ok].all() and np.isnan(t["lockup_time_s"][~ok]).all()
    assert 0.9 < t["lockup_time_s"][ok].min() < t["lockup_time_s"][ok].max() < 1.3
    assert grid_sweep.status_counts == {"completed": 2, "failed": 2}


def test_2d_grid_round_trips_through_parquet_with_units(grid_sweep):
    path = grid_sweep.path / "results.parquet"
    schema = pq.read_schema(path)
    unit = {f.name: f.metadata[b"unit"].decode() for f in schema}
    assert unit["vehicle.mass"] == "kg" and unit["vehicle.grade"] == "%"
    assert unit["slip_energy_J"] == "J" and unit["peak_heat_node_temp_C"] == "°C"
    back = read_results(grid_sweep.path)
    assert back.attrs["units"] == unit
    assert back.attrs["sweep"]["grid_keys"] == ["vehicle.mass", "vehicle.grade"]
    assert back.equals(grid_sweep.table)
    assert (grid_sweep.path / "heatmap_lockup_time_s.png").stat().st_size > 1000


def test_a_directory_holding_another_sweep_is_refused(grid_sweep):
    with pytest.raises(SweepError, match="different sweep.*another --out"):
        sweep(None, SweepSpec(vary={"vehicle.mass": "1100:1500:3"}, overrides=BASE),
              out=grid_sweep.path)


def test_an_interrupted_sweep_resumes_with_one_row_per_variant(tmp_path):
    vary = {"vehicle.mass": "uniform(1100, 1500)"}
    spec = SweepSpec(vary=vary, samples=6, seed=7, overrides=BASE,
                     metrics=["lockup_time_s", "slip_energy_J"])
    kw = {"out": tmp_path / "s"}
    options = SweepOptions(chunk_size=2, workers=1)

    def stop_after_two(done, total):
        if done >= 4:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        sweep(None, spec, options, progress=stop_after_two, **kw)
    assert len(list((tmp_path / "s" / "chunks").glob("*.parquet"))) == 2
    assert not (tmp_path / "s" / "results.parquet").exists()
    res = sweep(None, spec, options, **kw)
    assert (res.chunks, res.chunks_skipped) == (3, 2)
    assert list(res.table["run"]) == list(range(6))
    again = sweep(None, spec, options, **kw)   # complete: nothing re-run, same table
    assert again.chunks_skipped == 3 and again.table.equals(res.table)
    fresh = sweep(None, spec, options, **{**kw, "out": tmp_path / "fresh"})
    assert fresh.table.equals(res.table)


def test_the_public_sweep_is_the_studies_function():
    import clutchsim
    from clutchsim.studies.sweeps import api
    assert clutchsim.sweep is S.sweep is api.sweep
    assert (clutchsim.SweepSpec, clutchsim.SweepOptions) == (api.SweepSpec, api.SweepOptions)
    assert not callable(S)


# ------------------------------------------------------------------ Dask
@pytest.fixture(scope="module")
def dask_client():
    distributed = pytest.importorskip("distributed")
    cluster = distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False,
                                       dashboard_address=":0")
    client = distributed.Client(cluster)
    yield client
    client.close()
    cluster.close()


def test_dask_gives_the_same_table_as_in_process(tmp_path, dask_client):
    spec = SweepSpec(samples=4, seed=11, overrides=BASE,
                     vary={"vehicle.mass": "uniform(1100, 1500)", "vehicle.grade": "0,30"})
    local = sweep(None, spec, SweepOptions(chunk_size=3), out=tmp_path / "threads")
    remote = sweep(None, spec, SweepOptions(chunk_size=3, backend=dask_client),
                   out=tmp_path / "dask")
    assert len(local.table) == 8
    assert remote.table.equals(local.table)
    assert remote.manifest["sweep_id"] == local.manifest["sweep_id"]


def test_a_dask_address_that_does_not_answer_fails_fast(tmp_path):
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    t0 = time.perf_counter()
    with pytest.raises(SweepError, match="no Dask scheduler answered.*within 2 s"):
        sweep(None, SweepSpec(vary={"vehicle.mass": "1100:1500:2"}, overrides=BASE),
              SweepOptions(backend="dask", address=f"tcp://127.0.0.1:{port}",
              connect_timeout=2.0), out=tmp_path / "s")
    assert time.perf_counter() - t0 < 15
