"""``clutchsim explore``: --list, a busy port, and Bokeh missing (a clear message, and the
other commands unaffected)."""

from __future__ import annotations

import json
import logging
import socket
import sys

import pytest

from clutchsim.cli import main


def test_list_json(capsys):
    assert main(["explore", "--list", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["model"] == "mykhailevych2020"
    keys = {p["key"]: p for p in doc["parameters"]}
    assert keys["vehicle.mass"]["value"] == 1300.0 and keys["vehicle.mass"]["unit"] == "kg"
    assert "engagement_time" in keys


def test_list_of_an_actuated_launch_has_the_touch_point(capsys):
    assert main(["explore", "examples/launch_actuated.toml", "--list", "--json"]) == 0
    keys = {p["key"]: p for p in json.loads(capsys.readouterr().out)["parameters"]}
    assert keys["component[1].touch_point"]["value"] == 0.006
    assert "duration of the ramp of inputs.travel_command" in keys["engagement_time"]["doc"]


def test_bad_set_is_exit_2(capsys):
    assert main(["explore", "--set", "vehicle.mass=-1", "--list"]) == 2
    err = capsys.readouterr().err
    assert "vehicle.mass" in err and "must be > 0" in err and "Traceback" not in err


def test_busy_port_is_exit_2(capsys):
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        s.listen(1)
        port = s.getsockname()[1]
        assert main(["explore", "--port", str(port), "--no-browser"]) == 2
    err = capsys.readouterr().err
    assert f"--port {port}" in err and "in use" in err


@pytest.fixture(autouse=True)
def _log_handlers():
    """main() points the log at this test's captured stderr: restore the handlers after."""
    root = logging.getLogger()
    saved = list(root.handlers)
    yield
    root.handlers[:] = saved


def test_without_bokeh(monkeypatch, capsys, launch_dir):
    for name in [m for m in sys.modules if m == "bokeh" or m.startswith("bokeh.")]:
        monkeypatch.delitem(sys.modules, name)
    monkeypatch.setitem(sys.modules, "bokeh", None)     # import bokeh fails
    assert main(["explore", "--no-browser"]) == 2
    err = capsys.readouterr().err
    assert "clutchsim[explore]" in err and "Bokeh" in err
    assert main(["report", str(launch_dir), "--interactive"]) == 2
    assert "clutchsim[explore]" in capsys.readouterr().err
    assert main(["report", str(launch_dir)]) == 0        # the static report needs no Bokeh
    assert main(["explore", "--list"]) == 0              # nor does the session


@pytest.mark.parametrize("port", ["-1", "70000"])
def test_port_range(port, capsys):
    assert main(["explore", "--port", port, "--no-browser"]) == 2
    assert "--port" in capsys.readouterr().err


def test_serves_on_loopback_until_ctrl_c(tmp_path):
    """The URL on stdout is on 127.0.0.1, the page loads, Ctrl-C ends it with 130."""
    import signal
    import subprocess
    import urllib.request
    log = tmp_path / "explore.log"
    with open(log, "w") as err:
        proc = subprocess.Popen([sys.executable, "-m", "clutchsim", "explore", "--no-browser"],
                                stdout=subprocess.PIPE, stderr=err, text=True)
    try:
        url = proc.stdout.readline().strip()
        assert url.startswith("http://127.0.0.1:"), log.read_text()
        with urllib.request.urlopen(url, timeout=120) as page:
            assert b"clutchsim explore: passenger-car launch" in page.read()
    finally:
        proc.send_signal(signal.SIGINT)
        proc.communicate(timeout=30)
    assert proc.returncode == 130
    text = log.read_text()
    assert "interrupted (SIGINT)" in text and "Traceback" not in text
    assert "GET /" not in text                   # no line a request
