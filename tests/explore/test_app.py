"""The explorer's Bokeh document builds, and its widgets drive the session."""

from __future__ import annotations

import re

import numpy as np
import pytest

pytest.importorskip("bokeh", reason="the explorer needs Bokeh (the extra clutchsim[explore])")
from bokeh.document import Document
from bokeh.models import Slider, TextInput

from clutchsim.explore import Session
from clutchsim.explore.app import make_document


def _lockup(html: str) -> float:
    return float(re.search(r'id="lockup_time_s"[^>]*>([^<]+)<', html).group(1))


@pytest.fixture(scope="module")
def page(tmp_path_factory):
    out = tmp_path_factory.mktemp("explored")
    doc = Document()
    make_document(doc, Session(), out_dir=out)
    return doc, out


def test_document_has_sliders_figures_and_metrics(page):
    doc, _ = page
    sliders = {m.name: m for m in doc.select({"type": Slider})}
    assert {"vehicle.mass", "engagement_time", "coupling[0].friction.overrides.T_stat"} \
        <= set(sliders)
    figures = doc.get_model_by_name("plots").children[0].children
    assert [f.title.text for f in figures][:2] == ["speeds [rpm]", "torques [N·m]"]
    assert all(f.x_range is figures[0].x_range for f in figures)     # linked time axes
    metrics = doc.get_model_by_name("metrics")
    assert 0.9 < _lockup(metrics.text) < 1.5
    assert "completed" in metrics.text


def test_slider_reruns_and_redraws(page):
    doc, _ = page
    metrics = doc.get_model_by_name("metrics")
    before = _lockup(metrics.text)
    source = doc.get_model_by_name("plots").children[0].children[0].renderers[0].data_source
    speed0 = np.array(source.data["omega_disc"])
    doc.get_model_by_name("vehicle.mass").value = 1800.0
    assert _lockup(metrics.text) > before + 0.01       # heavier: later lock-up
    speed1 = np.array(source.data["omega_disc"])
    assert speed1.shape != speed0.shape or not np.allclose(speed1, speed0)
    # the figures draw the speeds in rpm
    expected = Session()
    expected.set("vehicle.mass", 1800.0)
    ref = expected.run()
    t = ref.traces["t"]
    rows = np.searchsorted(t, source.data["t"])
    np.testing.assert_array_equal(t[rows], source.data["t"])     # samples of the run
    np.testing.assert_allclose(source.data["omega_disc"],
                               ref.traces["omega_disc"][rows] * 30 / np.pi, rtol=1e-5,
                               atol=1e-3)


def test_refused_value_shows_inline(page):
    doc, _ = page
    metrics = doc.get_model_by_name("metrics")
    shown = metrics.text
    field = next(iter(doc.select({"type": TextInput})))
    field.value = "vehicle.mass = -3"
    error = doc.get_model_by_name("error").text
    assert "vehicle.mass" in error and "-3" in error and "must be &gt; 0 kg" in error
    assert metrics.text == shown                       # the last good run stays


def test_export_writes_only_into_the_folder(page):
    from clutchsim.explore.app import export
    _, out = page
    s = Session()
    s.set("vehicle.grade", 2.0)
    written = export(s, out)
    assert sorted(p.name for p in out.iterdir()) == ["explore_scenario.toml", "explore_set.txt",
                                                     "explore_traces.csv"]
    assert all(p.parent == out for p in written)
    assert (out / "explore_set.txt").read_text() == "vehicle.grade=2.0\n"
    head = (out / "explore_traces.csv").read_text().splitlines()[0]
    assert head.startswith("t [s],") and "omega_engine [rad/s]" in head
    # the saved scenario is a scenario file that runs the same launch
    from clutchsim.scenario import load_scenario, run_scenario
    saved = load_scenario(out / "explore_scenario.toml")
    assert saved.data["vehicle"]["grade"] == 2.0
    assert run_scenario(saved, s.model).metrics["lockup_time_s"] == pytest.approx(
        s.run().metrics["lockup_time_s"], rel=1e-9)


def test_model_comparison_overlays_the_other_model(tmp_path):
    from bokeh.models import Select
    doc = Document()
    make_document(doc, Session())
    doc.get_model_by_name("vehicle.mass").value = 1500.0
    compare = next(m for m in doc.select({"type": Select}) if m.name == "compare")
    compare.value = "coulomb-robust"
    text = doc.get_model_by_name("metrics").text
    ref = Session(None, "coulomb-robust")
    ref.set("vehicle.mass", 1500.0)      # the compared run takes the same values
    expected = ref.run().metrics["lockup_time_s"]
    got = float(re.search(r'id="compared_lockup_time_s">([^<]+)<', text).group(1))
    assert got == pytest.approx(expected, rel=1e-3)
    speeds = doc.get_model_by_name("plots").children[0].children[0]
    dashed = [r for r in speeds.renderers if r.glyph.line_dash == [6]]  # "dashed"
    assert dashed and len(dashed[0].data_source.data["t"]) > 100
    compare.value = "none"
    assert "compared" not in doc.get_model_by_name("metrics").text
    assert len(dashed[0].data_source.data["t"]) == 0
