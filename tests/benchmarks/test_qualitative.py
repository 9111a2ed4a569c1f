"""Qualitative properties where the reference gives no number (T2, T3, T4, hysteresis)."""

from __future__ import annotations

import numpy as np

from clutchsim.benchmarks import run_benchmark


def test_breakaway_decreases_with_force_rate():
    r = run_benchmark("breakaway", ["lugre", "elastoplastic", "coulomb-robust"])
    for label in ("lugre", "elastoplastic"):
        pairs = np.array(r.metrics[label]["breakaway"])
        assert np.all(np.diff(pairs[:, 0]) > 0)
        assert np.all(np.diff(pairs[:, 1]) < 0), pairs
        assert pairs[0, 1] < 1.5   # below F_s
    coulomb = np.array(r.metrics["coulomb-robust"]["breakaway"])
    np.testing.assert_allclose(coulomb[:, 1], 1.5)   # no rate dependence


def test_lag_loop_widens_with_frequency():
    r = run_benchmark("lag", ["lugre", "elastoplastic", "stribeck"])
    for label in ("lugre", "elastoplastic"):
        w = r.metrics[label]["loop_width_N"]
        assert 0 < w["1"] < w["10"] < w["25"]   # lower friction when v decreases
    assert max(abs(x) for x in r.metrics["stribeck"]["loop_width_N"].values()) < 1e-5


def test_presliding_loop_closes():
    r = run_benchmark("presliding", ["lugre", "elastoplastic", "mykhailevych2020"])
    for label, m in r.metrics.items():
        assert m["loop_closes"], label
        assert 0 < m["x_first_ramp_m"] < 1e-4   # micrometres: pre-sliding, not sliding
        assert m["loop_width_m"] > 0


def test_hysteresis_energy_and_closure():
    r = run_benchmark("hysteresis", ["lugre", "elastoplastic", "mykhailevych2020"])
    for label, m in r.metrics.items():
        pre, sl = m["presliding"], m["sliding"]
        assert 0 < pre["loop_energy_J"] < sl["loop_energy_J"], label
        assert sl["loop_closes"], label
    # gross sliding over 4 mm per cycle at F_c = 1 N dissipates about 4 mJ
    assert abs(r.metrics["lugre"]["sliding"]["loop_energy_J"] - 4e-3) < 2e-4
    assert r.metrics["elastoplastic"]["presliding"]["loop_closes"]


def test_figures_render(tmp_path):
    from clutchsim.plot._style import save_png
    from clutchsim.plot.benchmarks import plot_benchmark
    r = run_benchmark("stick-slip", ["lugre"])
    fig, axes = plot_benchmark(r)
    assert all(ax.get_xlabel() or ax.get_ylabel() for ax in axes.ravel())
    assert "[N]" in axes[0][0].get_ylabel()
    path = save_png(fig, tmp_path / "ss.png")
    assert path.stat().st_size > 10_000
