"""Fixtures shared by the test folders: a headless Chromium for the browser tests of the
report (tests/report) and of the interactive report and explorer (tests/explore); they
skip cleanly where no Chromium and chromedriver are installed (.ci/run installs them when
it runs as root).  Under CI (``.ci/run`` sets ``CI``) the property tests draw the same
examples on every run (hypothesis profile ``ci``: derandomised, no example database), so
that a landing is not decided by the draw; a local run draws new ones, which is how they
find something new, and ``scripts/fuzz_networks.py`` runs thousands with a seed."""

from __future__ import annotations

import contextlib
import os
import shutil
from pathlib import Path

import pytest
from hypothesis import settings

settings.register_profile("ci", derandomize=True, database=None)
if os.environ.get("CI"):
    settings.load_profile("ci")

_BROWSERS = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")
_DRIVERS = ("chromedriver", "/usr/lib/chromium/chromedriver")
_FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
          "--no-first-run", "--disable-component-update", "--disable-sync", "--disable-quic",
          "--window-size=1280,900")


@pytest.hookimpl(tryfirst=True)
def pytest_sessionstart(session):
    """Before the workers start, compile the C engine, the default launch's plant and the
    launch-metrics kernel (~22 s) once, into the caches the workers then load from, instead
    of each worker compiling them beside the other."""
    config = session.config
    if hasattr(config, "workerinput") or (getattr(config.option, "numprocesses", 0) or 0) < 2:
        return
    from clutchsim._jit import cache_dir
    if not cache_dir or any(Path(cache_dir).glob("*/*.launch_kernel-*.nbi")):
        return
    from clutchsim.scenario import run_scenario
    # only a head start: a launch that fails here fails in its own tests, with a report
    with contextlib.suppress(Exception):
        run_scenario(None)


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


@pytest.fixture
def screenshot():
    """``screenshot(driver, path)``: the whole page as a PNG at ``path`` (copied into
    ``$CLUTCHSIM_SCREENSHOT_DIR`` too when that is set, for the test artefacts)."""
    return _screenshot


def _screenshot(driver, path: Path) -> Path:
    """Resize the window to the page height, then capture the whole page."""
    height = driver.execute_script("return document.documentElement.scrollHeight")
    driver.set_window_size(1280, min(int(height) + 120, 16000))
    path.parent.mkdir(parents=True, exist_ok=True)
    assert driver.save_screenshot(str(path))
    extra = os.environ.get("CLUTCHSIM_SCREENSHOT_DIR")
    if extra:
        Path(extra).mkdir(parents=True, exist_ok=True)
        shutil.copy(path, Path(extra) / path.name)
    return path


@pytest.fixture
def drop_c_compiler(monkeypatch, tmp_path):
    """A function that takes the C compiler away for the rest of the test (``find_compiler``
    raises what it raises on a machine without one) and empties the table of generated
    plants into ``tmp_path``: the next generated plant goes the numba fallback's way.  It
    returns ``tmp_path``."""
    from clutchsim import _cc, rig
    from clutchsim.cgen import NoCompilerError, loader
    from clutchsim.network import plant as network_plant

    def no_compiler():
        raise NoCompilerError("no C compiler found (looked for cc, gcc, clang on the PATH)")

    def drop():
        monkeypatch.setattr(_cc, "find_compiler", no_compiler)
        monkeypatch.setattr(loader, "module_dir", lambda kind: tmp_path)
        monkeypatch.setattr(loader, "_LOADED", {})
        monkeypatch.setattr(loader, "_FALLBACK_LOGGED", set())
        monkeypatch.setattr(network_plant, "_PLANS", {})
        monkeypatch.setattr(rig, "_TAGS", {})
        return tmp_path

    return drop
