"""``clutchsim report DIR --interactive`` on the study directories: sweep, UQ (Sobol'),
durability, judder (modes, stability map) and fit, each made by its real command with
the smallest settings; the page is one self-contained Bokeh document whose figures hold
the directory's data (compared with the data files), and a sweep's report renders in
headless Chromium."""

from __future__ import annotations

import html
import json
import logging
import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

pytest.importorskip("bokeh", reason="the interactive report needs Bokeh (clutchsim[explore])")
from test_explore_browser import assert_renders_offline
from test_report_interactive import _array, _entries, _models, assert_self_contained

from clutchsim.cli import main
from clutchsim.studies.sweeps import read_results

#: every page: Bokeh's library (~1.3 MB) and the figures; the docs state each kind's size
SIZE_BOUND = 2_500_000
FAST = ["--set", "scenario.t_end=1.3", "--set", "solver.dt_out=0.005", "-q"]


def _cli(argv) -> int:
    root = logging.getLogger()
    saved = list(root.handlers)
    try:
        return main(argv)
    finally:
        root.handlers[:] = saved


@pytest.fixture(scope="module")
def dirs(tmp_path_factory):
    """Output directories of sweep (sampled, 2-D grid), uq, durability, judder (modes, map,
    frequency response) and fit."""
    base = tmp_path_factory.mktemp("kinds")
    d = {k: base / k for k in ("sweep", "uq", "durability", "judder", "jmap", "fit", "grid",
                               "frf")}
    assert _cli(["sweep", "--vary", "vehicle.mass=uniform(1100,1500)", "--vary",
                 "vehicle.grade=uniform(0,6)", "--samples", "6", "--seed", "5", "--out",
                 str(d["sweep"]), *FAST]) == 0
    assert _cli(["uq", "--method", "sobol", "--vary", "vehicle.grade=uniform(0,1.5)",
                 "--vary", "vehicle.mass=uniform(1100,1500)", "--samples", "8", "--seed",
                 "1", "--out", str(d["uq"]), *FAST]) == 0
    duty = base / "duty.toml"
    scenario = Path(__file__).resolve().parents[2] / "examples" / "launch_wear.toml"
    duty.write_text(
        '[duty]\nname = "report duty"\ncycles = 12\nmodel = "coulomb-robust"\n'
        'clamp_force = 4000.0\n\n[[manoeuvre]]\nname = "launch"\n'
        f'scenario = "{scenario.as_posix()}"\nrest = 20.0\n'
        'set = ["thermal[0].theta0=120", "thermal[1].theta0=120"]\n\n'
        '[[cycle]]\nmanoeuvre = "launch"\ncount = 1\n')
    assert _cli(["durability", str(duty), "--cycles", "12", "--out", str(d["durability"]),
                 "--no-plots", "-q"]) == 0
    assert _cli(["judder", "--model", "coulomb-robust", "--at", "3", "--out",
                 str(d["judder"]), "-q"]) == 0
    assert _cli(["judder", "--map", "coupling[1].d=0.1:1:3", "--map", "vehicle.grade=0:1:2",
                 "--out", str(d["jmap"]), "-q"]) == 0
    assert _cli(["sweep", "--vary", "vehicle.mass=1100:1500:3", "--vary",
                 "vehicle.grade=0:6:2", "--out", str(d["grid"]), *FAST]) == 0
    assert _cli(["judder", "--model", "coulomb-robust", "--at", "3", "--frf",
                 "throttle:a_vehicle", "--points", "60", "--out", str(d["frf"]), "-q"]) == 0
    record = base / "rec.csv"
    assert _cli(["rig", "--model", "tanh", "--velocity", "sine(0.05, 0.5)", "--t-end", "2",
                 "--out", str(record), "-q"]) == 0
    assert _cli(["fit", str(record), "--model", "tanh", "--plant", "rig-velocity", "--time",
                 "time [s]", "--column", "v=v [m/s]", "--column", "F=F [N]", "--input", "v",
                 "--output", "F", "--params", "F_c", "--start", "F_c=2", "--window", "0:1",
                 "--out", str(d["fit"]), "-q", "--no-plots"]) == 0
    return d


def _report(d, capsys) -> str:
    capsys.readouterr()
    assert _cli(["report", str(d), "--interactive", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    page = (d / "report.html").read_text(encoding="utf-8")
    assert doc == {"report": str(d / "report.html")}
    assert_self_contained(page)
    size = (d / "report.html").stat().st_size
    assert size < SIZE_BOUND, f"{size:,} bytes"
    return page


def _texts(models, attr: str) -> set[str]:
    """The strings (or ``{"value": str}``) of ``attr`` in the models, as the page shows
    them (Bokeh writes the document into a JavaScript string: ``\\u00b0`` for °)."""
    out = set()
    for m in models:
        v = m["attributes"].get(attr)
        v = v.get("value") if isinstance(v, dict) else v
        if isinstance(v, str):
            out.add(html.unescape(re.sub(r"\\u([0-9a-fA-F]{4})",
                                         lambda g: chr(int(g.group(1), 16)), v)))
    return out


def _columns(model) -> dict:
    data = model["attributes"]["data"]
    keys, values = _entries(data)
    return {k: (_array(v) if not isinstance(v, list) or not v or not isinstance(v[0], str)
                else v) for k, v in zip(keys, values)}


def _sources(models) -> list[dict]:
    return [_columns(m) for m in models if m["name"] == "ColumnDataSource"]


def test_sweep_scatter_panels_hold_every_run(dirs, capsys):
    page = _report(dirs["sweep"], capsys)
    models = _models(page)
    labels = _texts(models, "axis_label")
    assert {"vehicle.mass [kg]", "vehicle.grade [%]", "lockup_time_s [s]",
            "slip_energy_J [J]"} <= labels
    table = read_results(dirs["sweep"])
    shared = next(s for s in _sources(models) if "outcome" in s and "vehicle.mass" in s)
    assert list(shared["outcome"]) == list(table["outcome"])      # every run, its outcome
    np.testing.assert_allclose(shared["vehicle.grade"], table["vehicle.grade"])
    np.testing.assert_allclose(shared["lockup_time_s"], table["lockup_time_s"])
    # one source for all panels: a selection in one panel is a selection in all
    scatter = [m["attributes"] for m in models if m["name"] == "GlyphRenderer"
               and m["attributes"]["glyph"].get("name") == "Scatter"]
    # a panel for each metric with values (not the solver's statistics) and parameter
    metrics = [m for m in json.loads((dirs["sweep"] / "sweep.json").read_text())["metrics"]
               if table[m].dtype == float and table[m].notna().any()
               and m not in ("min_step_s",)]
    assert len(metrics) >= 15 and len(scatter) == 2 * len(metrics)
    assert {f"{m} [{table.attrs['units'][m]}]" if table.attrs["units"][m] != "-" else m
            for m in metrics} <= labels
    assert len({r["data_source"]["id"] for r in scatter}) == 1
    assert "BoxSelectTool" in page and "LassoSelectTool" in page
    assert '<figure id="fig-scatter_' not in page and '<figure id="fig-histograms' not in page


def test_grid_sweep_heat_maps_hold_every_grid_point(dirs, capsys):
    page = _report(dirs["grid"], capsys)
    models = _models(page)
    table = read_results(dirs["grid"])
    ok = (table["status"] == "completed").to_numpy()
    assert ok.sum() >= 4
    cells = [s for s in _sources(models) if {"x", "y", "z"} <= set(s)]
    assert len(cells) == 3                        # the main metrics, as heatmap_*.png
    want = {(m, g): t for m, g, t, good in zip(table["vehicle.mass"], table["vehicle.grade"],
                                               table["lockup_time_s"], ok) if good}
    lockup = next(c for c in cells if np.nanmax(c["z"]) < 10)       # seconds, not joules
    got = {(x, y): z for x, y, z in zip(lockup["x"], lockup["y"], lockup["z"])}
    assert len(got) == 3 * 2 and all(got[k] == pytest.approx(v, rel=1e-9)
                                     for k, v in want.items())
    assert {"vehicle.mass [kg]", "vehicle.grade [%]"} <= _texts(models, "axis_label")
    assert "lockup_time_s [s]" in _texts(models, "title")            # the colour bar
    assert '<figure id="fig-heatmap_' not in page
    assert (dirs["grid"] / "heatmap_lockup_time_s.png").is_file()   # kept for printing


def test_uq_distributions_quantiles_sobol_and_convergence(dirs, capsys):
    page = _report(dirs["uq"], capsys)
    models = _models(page)
    doc = json.loads((dirs["uq"] / "uq.json").read_text())
    table = read_results(dirs["uq"])
    labels = _texts(models, "label")
    # the study's quantiles marked, with their values
    q = doc["quantiles"]["lockup_time_s"]
    for name in ("p05", "p50", "p95"):
        assert f"{name} = {q[name]:.4g} s" in labels
    # the CDF: every finite value, sorted, rising to 1
    v = np.sort(table["lockup_time_s"].to_numpy(float))
    cdf = next(s for s in _sources(models) if set(s) == {"x", "F"} and len(s["x"]) == v.size
               and np.allclose(s["x"], v))
    np.testing.assert_allclose(cdf["F"], np.arange(1, v.size + 1) / v.size)
    # Sobol' S1 and ST with their 95 % intervals as error bars
    s = doc["sobol"]["lockup_time_s"]
    bars = [b for b in _sources(models) if set(b) == {"label", "v", "lo", "hi"}]
    for part in ("S1", "ST"):
        want = [s[k][part] for k in ("vehicle.grade", "vehicle.mass")]
        lo = [s[k][f"{part}_ci95"][0] for k in ("vehicle.grade", "vehicle.mass")]
        assert any(np.allclose(b["v"], want) and np.allclose(b["lo"], lo) for b in bars), part
    assert "Whisker" in page
    titles = _texts(models, "text")
    assert "P(completed)" in titles and "p50(lockup_time_s)" in titles
    conv = doc["convergence"]["p50(lockup_time_s)"]
    assert any(set(b) == {"n", "v", "lo", "hi"} and np.allclose(b["n"], conv["n"])
               and np.allclose(b["v"], conv["value"]) for b in _sources(models))
    for png in ("uq_distributions", "uq_sensitivity", "uq_convergence"):
        assert f'<figure id="fig-{png}.png"' not in page
    assert '<figure id="fig-uq_probabilities.png"' in page      # stays (with the table)
    assert "<h3>uq.json › probabilities › stalled</h3>" in page     # the tables stay


def test_durability_history_against_start(dirs, capsys):
    page = _report(dirs["durability"], capsys)
    models = _models(page)
    frame = pd.read_csv(dirs["durability"] / "durability.csv", skiprows=[1])
    src = next(s for s in _sources(models) if "start" in s)
    np.testing.assert_array_equal(src["start"], frame["cycle"].to_numpy(float))
    np.testing.assert_allclose(src["wear"], frame["wear_m"] * 1e3, rtol=1e-6)
    np.testing.assert_allclose(src["peak temperature"], frame["peak_theta_C"], rtol=1e-6)
    np.testing.assert_allclose(src["friction work"], frame["friction_work_J"] * 1e-3,
                               rtol=1e-6)
    assert {"peak temperature [°C]", "friction work [kJ]", "wear [mm]"} <= \
        _texts(models, "text")
    assert {"start [-]", "[°C]", "[mm]"} <= _texts(models, "axis_label")


def test_judder_modes_and_stability_map(dirs, capsys):
    page = _report(dirs["judder"], capsys)
    models = _models(page)
    modes = json.loads((dirs["judder"] / "judder.json").read_text())["modes"]
    shown = [s for s in _sources(models) if {"f", "zeta", "growth"} <= set(s)]
    f = np.concatenate([s["f"] for s in shown])
    assert sorted(f) == pytest.approx(sorted(m["frequency_hz"] for m in modes))
    unstable = [m for m in modes if not m["stable"]]
    assert len(shown) == 1 + bool(unstable)
    assert {"natural frequency [Hz]", "damping ratio [-]"} <= _texts(models, "axis_label")

    page = _report(dirs["jmap"], capsys)
    models = _models(page)
    doc = json.loads((dirs["jmap"] / "judder_map.json").read_text())
    cells = next(s for s in _sources(models) if {"x", "y", "z"} <= set(s))
    want = {(p["coupling[1].d"], p["vehicle.grade"]): p["damping_ratio"] for p in doc["points"]}
    got = {(x, y): z for x, y, z in zip(cells["x"], cells["y"], cells["z"])}
    assert got.keys() == want.keys() and all(got[k] == pytest.approx(want[k]) for k in want)
    assert {"coupling[1].d", "vehicle.grade"} <= _texts(models, "axis_label")
    assert "smallest damping ratio [-]" in _texts(models, "title")
    assert '<figure id="fig-judder_map.png"' not in page


def test_fit_measured_simulated_and_residual(dirs, capsys):
    page = _report(dirs["fit"], capsys)
    models = _models(page)
    frame = pd.read_csv(dirs["fit"] / "traces.csv")
    src = next(s for s in _sources(models) if "measured" in s)
    np.testing.assert_array_equal(src["t"], frame["t"].to_numpy())
    np.testing.assert_allclose(src["measured"], frame["measured"], rtol=1e-6, atol=1e-30)
    np.testing.assert_allclose(src["simulated"], frame["simulated"], rtol=1e-6, atol=1e-30)
    np.testing.assert_allclose(src["residual"], frame["residual"], rtol=1e-5, atol=1e-12)
    titles = _texts(models, "text")
    assert "F: measured and simulated" in titles and \
        "F: residual (measured − simulated)" in titles
    # the two figures share one time axis (zoom one, the other follows)
    ranges = [m["attributes"]["x_range"]["id"] for m in models if m["name"] == "Figure"]
    assert len(ranges) == 2 and len(set(ranges)) == 1
    # the output's unit, from the data file (F [N]), on the axes and in the hover
    assert json.loads((dirs["fit"] / "fit.json").read_text())["output_unit"] == "N"
    assert "[N]" in _texts(models, "axis_label") and "t [s]" in _texts(models, "axis_label")
    assert "F in N against time [s]" in page


def test_frequency_response_magnitude_and_phase(dirs, capsys):
    page = _report(dirs["frf"], capsys)
    models = _models(page)
    doc = json.loads((dirs["frf"] / "frf.json").read_text())
    src = next(s for s in _sources(models) if {"f", "mag", "phase"} <= set(s))
    np.testing.assert_allclose(src["f"], doc["frequency_hz"], rtol=1e-12)
    np.testing.assert_allclose(src["mag"], doc["magnitude"], rtol=1e-12)
    # the phase drawn unwrapped: equal to the file's modulo 360 degrees, and continuous
    d = np.asarray(src["phase"]) - np.asarray(doc["phase_deg"])
    np.testing.assert_allclose((d + 180) % 360 - 180, 0, atol=1e-9)
    assert np.all(np.abs(np.diff(src["phase"])) < 180)
    labels = _texts(models, "axis_label")
    assert {"frequency [Hz]", "phase [deg]", f"|a_vehicle/throttle| [{doc['unit']}]"} <= labels
    logs = [m for m in models if m["name"] == "LogAxis"]
    assert len(logs) >= 2                                          # the frequency axes
    if doc["peaks"]:
        peaks = next(s for s in _sources(models) if set(s) == {"f", "mag"})
        np.testing.assert_allclose(peaks["f"], [p["frequency_hz"] for p in doc["peaks"]])
    assert '<figure id="fig-frf.png"' not in page


def test_damaged_data_file_gives_the_static_figures_and_says_why(dirs, tmp_path, capsys):
    import shutil
    d = tmp_path / "sweep"
    shutil.copytree(dirs["sweep"], d)
    (d / "results.parquet").write_bytes(b"not parquet")
    capsys.readouterr()
    assert _cli(["report", str(d), "--interactive"]) == 0
    page = (d / "report.html").read_text(encoding="utf-8")
    assert 'id="interactive"' not in page and "const docs_json" not in page
    assert "the interactive figures of this sweep directory could not be drawn" in page
    assert '<figure id="fig-histograms.png"' in page          # today's report
    # a directory that is no clutchsim output: the error of the static report (exit 2)
    other = tmp_path / "notes"
    other.mkdir()
    (other / "notes.txt").write_text("mine")
    assert _cli(["report", str(other), "--interactive"]) == 2
    assert "is not a clutchsim output directory" in capsys.readouterr().err


def test_sweep_report_renders_in_chromium(chrome, screenshot, dirs, capsys, tmp_path):
    _report(dirs["sweep"], capsys)
    # every scatter panel and histogram is a canvas of its own
    assert_renders_offline(chrome, dirs["sweep"] / "report.html", 30, timeout_s=30)
    screenshot(chrome, tmp_path / "screenshots" / "report_interactive_sweep.png")
