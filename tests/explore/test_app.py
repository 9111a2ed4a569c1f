"""The explorer's logic without a server (:class:`clutchsim.explore.app.Explorer`): the
controls, the traces message (samples of the run, in display units, peaks kept), the
metrics sent before the traces, refused values, model comparison and export."""

from __future__ import annotations

import re

import numpy as np
import pytest

from clutchsim.explore import Session
from clutchsim.explore.app import Explorer, decode_payload, traces_payload


def _lockup(html: str) -> float:
    return float(re.search(r'id="lockup_time_s"[^>]*>([^<]+)<', html).group(1))


def _ops(answers) -> list[str]:
    return ["traces" if isinstance(a, bytes) else a["op"] for a in answers]


def _one(answers, op):
    return next(a for a in answers if not isinstance(a, bytes) and a["op"] == op)


def _figures(answers):
    return decode_payload(next(a for a in answers if isinstance(a, bytes)))


@pytest.fixture(scope="module")
def page(tmp_path_factory):
    out = tmp_path_factory.mktemp("explored")
    ex = Explorer(Session(), out_dir=out)
    return ex, ex.init(), out


def test_first_answers_controls_metrics_traces(page):
    _, answers, out = page
    assert _ops(answers) == ["controls", "metrics", "traces", "done"]
    controls = answers[0]
    keys = [p["key"] for p in controls["parameters"]]
    assert {"vehicle.mass", "engagement_time", "coupling[0].friction.overrides.T_stat"} <= set(keys)
    assert controls["models"] == ["mykhailevych2020", "coulomb-robust"]
    assert controls["export"] == str(out)
    html = _one(answers, "metrics")["html"]
    assert 0.9 < _lockup(html) < 1.5 and "completed" in html
    _, figures = _figures(answers)
    assert [f["title"] for f in figures] == ["speeds", "torques", "power", "acceleration",
                                             "temperatures"]
    assert [f["unit"] for f in figures[:3]] == ["rpm", "N·m", "kW"]


def test_slider_reruns_and_sends_the_run_in_display_units(page):
    ex, first, _ = page
    before = _lockup(_one(first, "metrics")["html"])
    answers = ex.handle({"op": "set", "key": "vehicle.mass", "value": 1800.0, "seq": 7})
    # the metrics go first: the page shows them before it draws the traces
    assert _ops(answers) == ["error", "metrics", "traces", "done"]
    assert _one(answers, "error")["text"] == "" and _one(answers, "done")["seq"] == 7
    assert _lockup(_one(answers, "metrics")["html"]) > before + 0.01     # heavier: later
    header, figures = _figures(answers)
    assert header["seq"] == 7
    ref = Session()
    ref.set("vehicle.mass", 1800.0)
    run = ref.run()
    t = run.traces["t"]
    for f in figures:
        rows = np.searchsorted(t, f["t"])
        np.testing.assert_array_equal(t[rows], f["t"])              # samples of the run
    speeds = figures[0]
    rows = np.searchsorted(t, speeds["t"])
    np.testing.assert_allclose(speeds["data"]["omega_disc"],
                               run.traces["omega_disc"][rows] * 30 / np.pi, rtol=1e-6, atol=1e-3)
    power = figures[2]
    name = power["series"][0]
    np.testing.assert_allclose(power["data"][name],
                               run.traces[name][np.searchsorted(t, power["t"])] * 1e-3,
                               rtol=1e-6, atol=1e-6)


def test_refused_value_shows_inline_and_keeps_the_run(page):
    ex, _, _ = page
    answers = ex.handle({"op": "field", "text": "vehicle.mass = -3", "seq": 8})
    assert _ops(answers) == ["error", "done"]                     # no new run drawn
    text = answers[0]["text"]
    assert "vehicle.mass" in text and "-3" in text and "must be > 0 kg" in text
    assert ex.session.values["vehicle.mass"] == 1800.0            # the last good value
    assert _ops(ex.handle({"op": "field", "text": "vehicle.mass 3"})) == ["error", "done"]
    assert "expected key.path = value" in ex.handle({"op": "field", "text": "x"})[0]["text"]
    assert "not a message" in ex.handle({"op": "open", "path": "/etc/passwd"})[0]["text"]


def test_display_rows_keep_every_peak():
    """A run longer than the figures draw: at most ``max_rows`` rows a figure, and every
    series' smallest and largest value among them (min/max decimation, no averaging)."""
    s = Session()
    run = s.run()
    _, figures = decode_payload(traces_payload(run, max_rows=300))
    _, full = decode_payload(traces_payload(run))
    for small, big in zip(figures, full):
        assert small["rows"] <= 300 < big["rows"]
        for name, v in small["data"].items():
            assert v.max() == big["data"][name].max() and v.min() == big["data"][name].min()


def test_export_writes_only_into_the_folder(page):
    from clutchsim.explore.app import export
    _, _, out = page
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


def test_export_from_the_page(page, tmp_path):
    ex, _, out = page
    answers = ex.handle({"op": "export", "seq": 9})
    assert _ops(answers) == ["info", "done"] and str(out) in answers[0]["text"]
    assert (out / "explore_set.txt").read_text() == "vehicle.mass=1800.0\n"
    refused = Explorer(Session()).handle({"op": "export"})      # no --out: nothing written
    assert "no --out folder" in refused[0]["text"]


def test_model_comparison_overlays_the_other_model():
    ex = Explorer(Session())
    ex.handle({"op": "set", "key": "vehicle.mass", "value": 1500.0})
    answers = ex.handle({"op": "compare", "value": "coulomb-robust"})
    ref = Session(None, "coulomb-robust")
    ref.set("vehicle.mass", 1500.0)      # the compared run takes the same values
    expected = ref.run().metrics["lockup_time_s"]
    html = _one(answers, "metrics")["html"]
    got = float(re.search(r'id="compared_lockup_time_s">([^<]+)<', html).group(1))
    assert got == pytest.approx(expected, rel=1e-3)
    _, figures = _figures(answers)
    overlay = [f for f in figures if f.get("overlay") == 0]
    assert len(overlay) == 1 and overlay[0]["rows"] > 100
    assert all(n.endswith("(coulomb-robust)") for n in overlay[0]["series"])
    # a value set later moves the compared run too
    later = ex.handle({"op": "set", "key": "vehicle.mass", "value": 1700.0})
    assert float(re.search(r'id="compared_lockup_time_s">([^<]+)<',
                           _one(later, "metrics")["html"]).group(1)) > got
    answers = ex.handle({"op": "compare", "value": "none"})
    assert "compared" not in _one(answers, "metrics")["html"]
    assert not [f for f in _figures(answers)[1] if "overlay" in f]


def test_model_change_sends_its_controls():
    ex = Explorer(Session())
    answers = ex.handle({"op": "model", "value": "coulomb-robust"})
    assert _ops(answers)[:2] == ["controls", "error"]
    controls = answers[0]
    assert controls["model"] == "coulomb-robust"
    friction = [p["key"] for p in controls["parameters"] if ".friction." in p["key"]]
    assert friction and all("alternatives.coulomb-robust" in k for k in friction)
    assert "unknown" in ex.handle({"op": "model", "value": "nonsense"})[0]["text"].lower()
