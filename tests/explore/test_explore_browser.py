"""In headless Chromium (the ``chrome`` fixture of tests/conftest.py; skips without one):
the interactive report renders offline, and the explorer answers a slider within the
latency budget (issue 42: 100 ms), showing the lock-up time the simulation gives, also at
the end of a drag."""

from __future__ import annotations

import os
import re
import subprocess
import sys
import time

import numpy as np
import pytest

pytest.importorskip("bokeh", reason="the explorer needs Bokeh (the extra clutchsim[explore])")
from clutchsim.explore import Session
from clutchsim.report.interactive import build_interactive_report

MASSES = (1350.0, 1450.0, 1550.0, 1650.0, 1750.0, 1850.0, 1950.0, 1400.0, 1500.0, 1600.0,
          1700.0, 1800.0)


#: canvases in the page, inside the shadow roots Bokeh draws into too
_CANVASES = """
function count(root) {
  let n = root.querySelectorAll('canvas').length;
  for (const el of root.querySelectorAll('*')) if (el.shadowRoot) n += count(el.shadowRoot);
  return n;
}
return count(document);
"""


def _severe(driver):
    return [e for e in driver.get_log("browser") if e.get("level") == "SEVERE"]


def assert_renders_offline(chrome, page, canvases: int, timeout_s: float = 20) -> None:
    """``page`` (a file) in the browser draws at least ``canvases`` canvases within
    ``timeout_s``, fetches nothing but data:, file: and blob: URLs, and logs no error."""
    chrome.get(page.resolve().as_uri())
    deadline, drawn = time.monotonic() + timeout_s, 0
    while time.monotonic() < deadline and drawn < canvases:
        drawn = chrome.execute_script(_CANVASES)
        time.sleep(0.2)
    assert drawn >= canvases, "the Bokeh figures did not render"
    resources = chrome.execute_script(
        "return performance.getEntriesByType('resource').map(e => e.name)")
    assert not [r for r in resources if not r.startswith(("data:", "file:", "blob:"))]
    assert not _severe(chrome)


def test_interactive_report_renders_offline(chrome, screenshot, launch_dir, tmp_path):
    report = build_interactive_report(launch_dir)
    assert_renders_offline(chrome, report, 5)
    assert screenshot(chrome, tmp_path / "screenshots" / "report_interactive.png") \
        .stat().st_size > 10_000


_MOVE = """
const [key, value, done] = arguments;
const input = document.querySelector(`input[name="${key}"]`), ex = window.explorer;
const out = {};
function move() {
  const before = ex.sent, t0 = performance.now();
  input.value = value;                            // the slider moved, as a drag moves it
  input.dispatchEvent(new Event('input'));
  const seq = ex.sent;
  if (seq !== before + 1) { done({error: `not sent at once: ${before} -> ${seq}`}); return; }
  out.value = +input.value;                       // on the slider's step grid
  (function check() {
    if (out.metrics === undefined && ex.metricsSeq >= seq) out.metrics = performance.now() - t0;
    if (ex.drawnSeq >= seq) {                     // uPlot has drawn the new traces: the
      out.drawn = performance.now() - t0;         // next frame shows them
      requestAnimationFrame(() => {
        out.painted = performance.now() - t0;
        out.html = document.getElementById('metrics').innerHTML;
        done(out);
      });
    } else if (performance.now() - t0 > 10000) done(out);
    else setTimeout(check, 0);
  })();
}
// the previous request answered in full (its "done" follows its traces): nothing in flight
(function idle() { if (ex.doneSeq === ex.sent) move(); else setTimeout(idle, 1); })();
"""


_DRAG = """
const [key, values, done] = arguments;
const input = document.querySelector(`input[name="${key}"]`), ex = window.explorer;
function drag() {
  const before = ex.sent;
  for (const v of values) { input.value = v; input.dispatchEvent(new Event('input')); }
  (function check() {
    if (ex.doneSeq === ex.sent && ex.drawnSeq === ex.sent && ex.sent > before)
      done({requests: ex.sent - before, value: +input.value,
            html: document.getElementById('metrics').innerHTML});
    else setTimeout(check, 5);
  })();
}
(function idle() { if (ex.doneSeq === ex.sent) drag(); else setTimeout(idle, 1); })();
"""


@pytest.fixture
def explorer(tmp_path):
    """``clutchsim explore --no-browser`` in a subprocess: its URL."""
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}
    log = tmp_path / "explore.log"
    with open(log, "w") as err:
        proc = subprocess.Popen([sys.executable, "-m", "clutchsim", "explore", "--no-browser",
                                 "--quiet"], stdout=subprocess.PIPE, stderr=err, text=True,
                                env=env)
    try:
        url = proc.stdout.readline().strip()
        assert url.startswith("http://127.0.0.1:"), (url, log.read_text())
        yield url
    finally:
        proc.terminate()
        proc.communicate(timeout=30)


def test_explorer_slider_latency(chrome, screenshot, explorer, tmp_path):
    chrome.get(explorer)
    chrome.set_script_timeout(30)
    deadline, ready = time.monotonic() + 60, False
    while time.monotonic() < deadline and not ready:
        ready = chrome.execute_script(
            "return !!window.explorer && window.explorer.drawnSeq >= 0 && "
            "window.explorer.charts.length === 5")
        time.sleep(0.2)
    assert ready, "the explorer page did not load"
    assert chrome.execute_script(_CANVASES) >= 5
    moves = [chrome.execute_async_script(_MOVE, "vehicle.mass", m) for m in MASSES]
    assert all("painted" in m for m in moves), moves
    painted = [m["painted"] for m in moves]
    metrics = [m["metrics"] for m in moves]
    median = float(np.median(painted))
    print(f"explorer latency over {len(moves)} moves, load {os.getloadavg()[0]:.1f}: slider -> "
          f"metrics shown median {np.median(metrics):.1f} ms, -> traces repainted median "
          f"{median:.1f} ms (max {max(painted):.1f} ms)")
    # the lock-up time shown is the one the simulation gives for the slider's last value
    s = Session()
    s.set("vehicle.mass", moves[-1]["value"])
    expected = s.run().metrics["lockup_time_s"]
    got = float(re.search(r'id="lockup_time_s"[^>]*>([^<]+)<', moves[-1]["html"]).group(1))
    assert got == pytest.approx(expected, rel=1e-3)
    # a drag: many values at once; one request in flight, then only the latest value runs,
    # and the page ends on the last value's run
    drag = chrome.execute_async_script(_DRAG, "vehicle.mass", list(np.linspace(1300, 1900, 25)))
    assert drag["requests"] == 2
    s.set("vehicle.mass", drag["value"])
    got = float(re.search(r'id="lockup_time_s"[^>]*>([^<]+)<', drag["html"]).group(1))
    assert got == pytest.approx(s.run().metrics["lockup_time_s"], rel=1e-3)
    assert not _severe(chrome)
    screenshot(chrome, tmp_path / "screenshots" / "explorer.png")
    # issue 42: slider -> traces and metrics redrawn within 100 ms (median).  Measured on the
    # shared 2-core development machine at a load of 2-3: 28-43 ms (docs/explore.md)
    bound = float(os.environ.get("CLUTCHSIM_EXPLORE_LATENCY_MS", "100"))
    assert median <= bound, painted
