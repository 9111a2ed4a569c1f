"""Benchmarks against the reference values of friction-models.md §3 ([C] numbers)."""

from __future__ import annotations

import math

import pytest

from clutchsim.benchmarks import BENCHMARKS, BenchmarkResult, run_benchmark


@pytest.fixture(scope="module")
def drift():
    return run_benchmark("drift", ["coulomb-robust", "dahl", "lugre", "elastoplastic",
                                   "mykhailevych2020", "mykhailevych2020,reset=zero"])


def test_drift_d1_references(drift):
    d1 = {k: v["D1"]["drift_per_cycle_m"] for k, v in drift.metrics.items()}
    assert d1["lugre"] == pytest.approx(6.637e-6, rel=0.05)
    assert drift.metrics["lugre"]["D1"]["x_end_m"] == pytest.approx(139.809e-6, rel=1e-3)
    assert d1["dahl"] == pytest.approx(16.661e-6, rel=0.05)
    assert abs(d1["elastoplastic"]) < 1e-9
    assert drift.metrics["elastoplastic"]["D1"]["x_end_m"] == pytest.approx(4.920e-6, rel=1e-3)
    assert abs(d1["mykhailevych2020"]) < 1e-9
    assert d1["mykhailevych2020,reset=zero"] > 100e-6
    assert d1["coulomb-robust"] == 0.0


def test_drift_d2(drift):
    d2 = {k: v["D2"] for k, v in drift.metrics.items()}
    assert abs(d2["elastoplastic"]["drift_per_cycle_m"]) < 1e-9
    assert abs(d2["mykhailevych2020"]["drift_per_cycle_m"]) < 1e-9
    assert d2["lugre"]["drift_per_cycle_m"] == pytest.approx(6.637e-6, rel=0.05)
    # model (6) with the clamp keeps its permanent slip (~0.16 mm, T11) after unloading
    assert d2["mykhailevych2020"]["x_sine_end_m"] == pytest.approx(0.1623e-3, rel=0.01)
    assert 0 < d2["mykhailevych2020"]["residual_m"] < d2["mykhailevych2020"]["x_sine_end_m"]


def test_result_is_immutable_and_json_ready(drift):
    assert isinstance(drift, BenchmarkResult)
    with pytest.raises(TypeError):
        drift.metrics["lugre"] = {}
    with pytest.raises(AttributeError):
        drift.benchmark = "x"
    doc = drift.metrics_json()
    assert doc["benchmark"] == "drift"
    assert set(doc["results"]["lugre"]) == {"D1", "D2", "outcome", "warnings"}
    assert doc["results"]["lugre"]["outcome"] == "completed"
    assert "residual_m" in doc["results"]["lugre"]["D2"]


def test_stick_slip_lugre():
    m = run_benchmark("stick-slip", ["lugre"]).metrics["lugre"]
    assert m["period_s"] == pytest.approx(6.3627, rel=1e-3)
    assert m["first_slip_s"] == pytest.approx(7.540, rel=1e-3)
    assert m["force_min_N"] == pytest.approx(0.7412, rel=1e-3)
    assert m["force_max_N"] == pytest.approx(1.5080, rel=1e-3)
    assert m["peak_velocity_m_s"] == pytest.approx(0.3698, rel=1e-3)


def test_coulomb_analytic_stick_time():
    m = run_benchmark("coulomb-analytic").metrics["coulomb-robust"]
    assert m["stick_time_analytic_s"] == pytest.approx(0.035124, abs=1e-6)
    assert abs(m["stick_time_error_s"]) < 1e-9
    assert m["restick_time_s"] == pytest.approx(0.31492, rel=1e-4)
    assert m["x1_restick_m"] == pytest.approx(3.9556, rel=1e-4)


def test_curves_lugre_static_curve():
    r = run_benchmark("curves", ["lugre", "coulomb-robust", "mykhailevych2020"])
    m = r.metrics["lugre"]
    assert m["f_static"] == pytest.approx(1.5, rel=1e-6)
    assert m["f_kinetic"] == pytest.approx(1.0, rel=1e-6)
    assert m["stribeck_min"]["value"] == pytest.approx(1.001261, rel=1e-5)
    assert m["stribeck_min"]["speed"] == pytest.approx(2.986e-3, rel=1e-3)
    assert r.metrics["coulomb-robust"]["stribeck_min"] is None
    six = r.metrics["mykhailevych2020"]
    assert six["f_static"] == pytest.approx(1.5, rel=1e-5)   # T_stat
    assert six["f_kinetic"] == pytest.approx(1.0, rel=1e-5)  # T_din
    pre = r.runs["mykhailevych2020"]["presliding"]
    assert max(abs(pre["F"])) == pytest.approx(1.5 * math.tanh(2.0), rel=1e-3)


def test_registry_and_unknown_names():
    assert set(BENCHMARKS) == {"curves", "drift", "hysteresis", "presliding", "lag",
                               "breakaway", "stick-slip", "coulomb-analytic"}
    with pytest.raises(ValueError, match="did you mean 'drift'"):
        run_benchmark("drfit")
    with pytest.raises(ValueError, match="does not apply"):
        run_benchmark("hysteresis", ["coulomb-robust"])
    with pytest.raises(ValueError, match="no parameter 'foo'"):
        run_benchmark("drift", ["lugre,foo=1"])
