"""Open a generated report in headless Chromium: images decode, no console errors."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest

from clutchsim.report import build_report

_BROWSERS = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")
_DRIVERS = ("chromedriver", "/usr/lib/chromium/chromedriver")
_FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
          "--no-first-run", "--disable-component-update", "--disable-sync", "--disable-quic",
          "--window-size=1280,900")


def _find(names, env):
    if os.environ.get(env):
        return os.environ[env]
    for n in names:
        hit = shutil.which(n) or (n if os.path.isabs(n) and os.access(n, os.X_OK) else None)
        if hit:
            return hit
    return None


@pytest.fixture
def chrome(tmp_path):
    """A headless Chromium driven by chromedriver with a fresh profile (skips if absent)."""
    webdriver = pytest.importorskip("selenium.webdriver", reason="selenium is not installed")
    browser, driver_bin = _find(_BROWSERS, "CHROME_BIN"), _find(_DRIVERS, "CHROMEDRIVER")
    if browser is None or driver_bin is None:
        pytest.skip("no Chromium browser and chromedriver found (apt-get install chromium "
                    "chromium-driver, or set CHROME_BIN and CHROMEDRIVER)")
    from selenium.webdriver.chrome.service import Service
    opts = webdriver.ChromeOptions()
    opts.binary_location = browser
    for f in _FLAGS:
        opts.add_argument(f)
    opts.add_argument(f"--user-data-dir={tmp_path / 'chrome-profile'}")
    opts.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    # an explicit driver path: selenium-manager never looks anything up on the network
    driver = webdriver.Chrome(service=Service(executable_path=driver_bin), options=opts)
    try:
        yield driver
    finally:
        driver.quit()


def _screenshot(driver, path: Path) -> Path:
    """Resize the window to the page height, then capture the whole page."""
    height = driver.execute_script("return document.documentElement.scrollHeight")
    driver.set_window_size(1280, min(int(height) + 120, 16000))
    path.parent.mkdir(parents=True, exist_ok=True)
    assert driver.save_screenshot(str(path))
    return path


def test_report_opens_in_chromium(chrome, run_dir, tmp_path):
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

    shot = _screenshot(chrome, tmp_path / "screenshots" / "report.png")
    assert shot.stat().st_size > 10_000
    extra = os.environ.get("CLUTCHSIM_SCREENSHOT_DIR")
    if extra:
        Path(extra).mkdir(parents=True, exist_ok=True)
        shutil.copy(shot, Path(extra) / "report.png")
