"""Rendering: self-contained, escaped, images as data: URIs."""

from __future__ import annotations

import json
import re

from clutchsim.report import build_report, render
from clutchsim.report.html import format_value
from clutchsim.report.tables import MISSING

EVIL = '<script>alert("x")</script>&'


def test_format_value():
    assert format_value(1.23456789) == "1.235"
    assert format_value(12345.678) == "12346"
    assert format_value(1.5e-12) == "1.5e-12"
    assert format_value(0.0) == "0" and format_value(7) == "7"
    assert format_value(True) == "yes" and format_value(None) == "—"
    assert format_value(float("nan")) == "NaN" and format_value(MISSING) == ""
    assert format_value(list(range(100))) == "[0, 1, 2, …, 99] (100 values)"


def test_report_is_self_contained(run_dir):
    page = build_report(run_dir).read_text(encoding="utf-8")
    assert not re.search(r"https?:", page, re.IGNORECASE)
    assert "<script" not in page.lower()
    imgs = re.findall(r"<img [^>]*>", page)
    assert len(imgs) == 2
    assert all(re.search(r' src="data:image/png;base64,[A-Za-z0-9+/=]+"', i) for i in imgs)
    assert not re.search(r'(src|href)="/', page)         # no absolute paths
    assert "Content-Security-Policy" in page
    # what the directory holds is all there
    for text in ("Position of the mass", "friction force", "spring = 2.0", "timeseries.csv",
                 "lining temperature above 80 C", "stopped by chatter detection",
                 "clutchsim rig --model lugre --out launch", "1 of 2 runs did not complete",
                 "rhs evals", 'class="failed"', '<a href="timeseries.csv">'):
        assert text in page, text


def test_untrusted_strings_are_escaped(run_dir):
    (run_dir / "evil.json").write_text(json.dumps({
        "status": "failed", "message": EVIL, "warnings": [EVIL],
        "models": {EVIL: {EVIL + "_s": EVIL}}}))
    (run_dir / "figures.json").write_text(json.dumps({"position.png": EVIL}))
    (run_dir / "odd.toml").write_text(EVIL)
    (run_dir / 'a"b<c>.csv').write_text("t\n0\n")
    page = build_report(run_dir, title=EVIL).read_text(encoding="utf-8")
    assert "<script" not in page and EVIL not in page
    assert "&lt;script&gt;alert(&quot;x&quot;)&lt;/script&gt;&amp;" in page
    assert 'href="a%22b%3Cc%3E.csv"' in page


def test_broken_inputs_are_reported_not_fatal(run_dir):
    (run_dir / "broken.png").write_bytes(b"not a png")
    (run_dir / "broken.json").write_text("{oops")
    from clutchsim.report import gather
    data = gather(run_dir)
    assert [f.name for f in data.figures] == ["friction_force.png", "position.png"]
    assert len(data.problems) == 2
    page = render(data)
    assert "broken.png is not a readable PNG" in page and "broken.json could not be read" in page


def test_result_html(rig_result):
    from clutchsim.report import result_html
    page = result_html(rig_result)
    assert page.startswith('<div class="clutchsim-result">')
    assert "completed" in page and "rhs evals" in page and "friction power" in page
    assert "@media" not in page and "body{" not in page      # scoped: the notebook keeps its style
    assert re.findall(r"}([^{}]+)\{", page)[0].startswith(".clutchsim-result")
