"""The interactive report: one self-contained HTML file whose figures hold the run's data."""

from __future__ import annotations

import base64
import gzip
import json
import re
from html.parser import HTMLParser

import numpy as np
import pytest

pytest.importorskip("bokeh", reason="the interactive report needs Bokeh (clutchsim[explore])")
from clutchsim.plot.interactive import display_rows
from clutchsim.report.interactive import (
    MAX_POINTS,
    build_interactive_report,
    read_series,
)


class _Tags(HTMLParser):
    def __init__(self):
        super().__init__()
        self.tags = []

    def handle_starttag(self, tag, attrs):
        self.tags.append((tag, dict(attrs)))


def _sources(page: str) -> list[dict]:
    """The ColumnDataSources of the embedded Bokeh document, columns decoded."""
    return [{k: _array(v) for k, v in zip(*_entries(m["attributes"]["data"]))}
            for m in _models(page) if m["name"] == "ColumnDataSource"]


def _models(page: str) -> list[dict]:
    """Every model of the embedded Bokeh document (``{"name", "attributes", ...}``)."""
    blob = re.search(r"const docs_json = '(.*?)';\n", page, re.DOTALL).group(1)
    found = []

    def walk(node):
        if isinstance(node, dict):
            if "name" in node and isinstance(node.get("attributes"), dict):
                found.append(node)
            for v in node.values():
                walk(v)
        elif isinstance(node, list):
            for v in node:
                walk(v)
    walk(json.loads(blob))
    return found


def _entries(data):
    entries = data["entries"] if isinstance(data, dict) and "entries" in data else data
    return [k for k, _ in entries], [v for _, v in entries]


def _array(v):
    if isinstance(v, dict) and v.get("type") == "ndarray":
        buf = base64.b64decode(v["array"]["data"])
        if buf[:2] == b"\x1f\x8b":                    # gzip, as Bokeh 3.9 writes it
            buf = gzip.decompress(buf)
        return np.frombuffer(buf, dtype=v["dtype"]).reshape(v["shape"])
    return np.asarray(v, dtype=float)


@pytest.fixture(scope="module")
def report(launch_dir):
    return build_interactive_report(launch_dir)


def assert_self_contained(page: str) -> None:
    """Bokeh inlined (no script or stylesheet from anywhere, no URL in any attribute), a
    policy that lets the page run its own scripts and fetch nothing, one Bokeh document
    in the section "Interactive figures"."""
    parser = _Tags()
    parser.feed(page)
    for tag, attrs in parser.tags:
        assert not (tag == "script" and attrs.get("src")), attrs      # all inlined
        assert not (tag == "link" and attrs.get("rel") == "stylesheet"), attrs
        for value in attrs.values():
            assert not str(value).startswith(("http:", "https:", "//")), (tag, attrs)
    csp = next(a["content"] for t, a in parser.tags
               if t == "meta" and a.get("http-equiv") == "Content-Security-Policy")
    assert "default-src 'none'" in csp and "script-src 'unsafe-inline'" in csp
    assert "connect-src" not in csp                 # nothing fetched, not even by scripts
    assert "Bokeh" in page and 'id="interactive"' in page
    assert page.count("const docs_json = ") == 1


def test_self_contained_and_small(report):
    page = report.read_text(encoding="utf-8")
    assert_self_contained(page)
    assert "<h2>Metrics" in page and "<h2>Scenario" in page   # the static report's tables
    assert '<figure id="fig-launch_' not in page   # the PNGs of the traces: in the directory
    size = report.stat().st_size
    assert size < 2_500_000, f"{size:,} bytes"      # docs: ~1.6 MB for a default run


def test_figures_hold_the_runs_data(report, launch_dir):
    sources = _sources(report.read_text(encoding="utf-8"))
    runs = sorted(launch_dir.glob("timeseries_*.parquet"))
    assert len(runs) == 2
    first = next(s for s in sources if "W_friction" in s and len(s["t"]) > 1000)
    t, cols, units = read_series(runs[0])
    rows = display_rows(t, [cols[n] for n in cols if units[n] != "rad"], MAX_POINTS)
    np.testing.assert_array_equal(first["t"], t[rows])
    np.testing.assert_allclose(first["omega_engine"], cols["omega_engine"][rows] * 30 / np.pi,
                               rtol=1e-6)
    np.testing.assert_allclose(first["W_friction"], cols["W_friction"][rows], rtol=1e-6)
    # the lock-up zoom: 0.1 s either side of the lock-up time of summary.json
    summary = json.loads((launch_dir / "summary.json").read_text())
    tl = summary["models"][runs[0].stem.split("_", 1)[1]]["lockup_time_s"]
    zoom = [s for s in sources if len(s["t"]) and s["t"][0] >= tl - 0.1 - 1e-9
            and s["t"][-1] <= tl + 0.1 + 1e-9 and len(s["t"]) < 200]
    assert zoom
    # the models overlaid on one axis
    labels = [r.stem.split("_", 1)[1] for r in runs]
    page = report.read_text(encoding="utf-8")
    assert all(f"omega_engine ({label})" in page for label in labels)


def test_display_rows_keep_samples_and_peaks():
    t = np.linspace(0.0, 1.0, 100_001)
    y = np.sin(40 * t)
    y[31_415] = 5.0                                 # a one-sample spike
    rows = display_rows(t, [y, np.cos(t)], 1000)
    assert len(rows) <= 1000 and rows[0] == 0 and rows[-1] == len(t) - 1
    assert np.all(np.diff(rows) > 0)
    assert 31_415 in rows                           # the peak survives
    assert np.array_equal(display_rows(t[:500], [y[:500]], 1000), np.arange(500))


def test_engine_torque_against_its_full_load_curve(report, launch_dir):
    """Each run's engine torque under its full-load torque at the same speed (the plant's
    ``T_full_load``): a figure of its own holding both columns; the engine never gives more
    than full load, and gives it where the throttle (governor included) is wide open."""
    sources = _sources(report.read_text(encoding="utf-8"))
    engine = [s for s in sources if set(s) >= {"t", "T_engine", "T_full_load"}
              and "W_friction" not in s]
    assert len(engine) == 2                            # one per model
    t, cols, _ = read_series(min(launch_dir.glob("timeseries_*.parquet")))
    rows = display_rows(t, [cols["T_engine"], cols["T_full_load"]], MAX_POINTS)
    np.testing.assert_allclose(engine[0]["T_full_load"], cols["T_full_load"][rows], rtol=1e-6)
    assert np.all(cols["T_full_load"] - cols["T_engine"] >= -1e-9 * np.abs(cols["T_full_load"]).max())


def test_full_load_torque_is_the_engine_torque_at_full_throttle():
    """``T_full_load`` is the full-load table at the engine's speed minus its drag: at full
    throttle the engine gives exactly that."""
    from clutchsim.scenario.run import run_scenario
    full = run_scenario(None, overrides=["inputs.throttle=1.0"]).result
    np.testing.assert_allclose(full["T_engine"], full["T_full_load"], rtol=0, atol=1e-12)
    # the table itself, read at the engine's speed (drag 8 N·m + 0.02 N·m·s/rad·ω in
    # the packaged launch), with the rev limiter's ramp to 0 over 5 % above its last
    # speed, where this full-throttle launch takes the engine (653 rad/s)
    w = full["omega_engine"]
    speed = [0.0, 62.8, 104.7, 157.1, 209.4, 314.2, 418.9, 628.3, 628.3 * 1.05]
    torque = [0.0, 110.0, 150.0, 180.0, 200.0, 200.0, 185.0, 140.0, 0.0]
    assert w.max() > speed[-2]
    drag = 8.0 * np.tanh(w) + 0.02 * w
    np.testing.assert_allclose(full["T_full_load"], np.interp(w, speed, torque) - drag,
                               rtol=1e-12, atol=1e-9)
