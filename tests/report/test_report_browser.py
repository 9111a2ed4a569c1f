"""Open a generated report in headless Chromium: images decode, no console errors (the
``chrome`` fixture: tests/conftest.py)."""

from __future__ import annotations

from clutchsim.report import build_report


def test_report_opens_in_chromium(chrome, screenshot, run_dir, tmp_path):
    report = build_report(run_dir)
    chrome.get(report.resolve().as_uri())
    assert chrome.title.startswith("clutchsim run report")

    images = chrome.execute_script(
        "return Array.from(document.images).map(i => [i.alt, i.complete, i.naturalWidth, "
        "i.src.slice(0, 22), i.getBoundingClientRect().width])")
    assert len(images) == 2
    for alt, complete, natural_width, src, shown_width in images:
        assert complete and natural_width > 0, f"image {alt!r} did not decode"
        assert src == "data:image/png;base64,"
        assert 0 < shown_width <= 1280

    resources = chrome.execute_script(
        "return performance.getEntriesByType('resource').map(e => e.name)")
    assert not [r for r in resources if not r.startswith(("data:", "file:"))]

    # nothing overflows the page sideways (wide tables scroll inside their own box)
    widths = chrome.execute_script(
        "return [document.documentElement.scrollWidth, document.documentElement.clientWidth]")
    assert widths[0] <= widths[1]

    severe = [e for e in chrome.get_log("browser") if e.get("level") == "SEVERE"]
    assert not severe, severe

    shot = screenshot(chrome, tmp_path / "screenshots" / "report.png")
    assert shot.stat().st_size > 10_000
