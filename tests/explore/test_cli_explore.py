"""``clutchsim explore``: --list, a busy port, the extra missing (a clear message, and the
other commands unaffected), and the server: loopback only, its own Host and origin only, no
file but its page's."""

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


def test_without_the_extra(monkeypatch, capsys, launch_dir):
    for top in ("bokeh", "tornado"):
        for name in [m for m in sys.modules if m == top or m.startswith(top + ".")]:
            monkeypatch.delitem(sys.modules, name)
        monkeypatch.setitem(sys.modules, top, None)     # import bokeh / tornado fails
    assert main(["explore", "--no-browser"]) == 2
    err = capsys.readouterr().err
    assert "clutchsim[explore]" in err and "Tornado" in err
    assert main(["report", str(launch_dir), "--interactive"]) == 2
    assert "clutchsim[explore]" in capsys.readouterr().err
    assert main(["report", str(launch_dir)]) == 0        # the static report needs no Bokeh
    assert main(["explore", "--list"]) == 0              # nor does the session


@pytest.mark.parametrize("port", ["-1", "70000"])
def test_port_range(port, capsys):
    assert main(["explore", "--port", port, "--no-browser"]) == 2
    assert "--port" in capsys.readouterr().err


def _get(url, host=None):
    """``(status, headers, body)`` of a GET of ``url`` (``host``: that Host header)."""
    import urllib.error
    import urllib.request
    req = urllib.request.Request(url, headers={"Host": host} if host else {})
    try:
        with urllib.request.urlopen(req, timeout=120) as r:
            return r.status, r.headers, r.read()
    except urllib.error.HTTPError as exc:
        return exc.code, exc.headers, b""


def test_serves_on_loopback_until_ctrl_c(tmp_path):
    """The URL on stdout is on 127.0.0.1, the page loads with a policy that lets it reach
    nothing but its own server, only the page's files are served, a request for another
    Host (DNS rebinding) or a websocket from another origin is refused, Ctrl-C ends it
    with 130."""
    import asyncio
    import signal
    import subprocess

    pytest.importorskip("tornado", reason="the explorer needs the extra clutchsim[explore]")
    from tornado.httpclient import HTTPClientError, HTTPRequest
    from tornado.websocket import websocket_connect
    log = tmp_path / "explore.log"
    with open(log, "w") as err:
        proc = subprocess.Popen([sys.executable, "-m", "clutchsim", "explore", "--no-browser"],
                                stdout=subprocess.PIPE, stderr=err, text=True)
    try:
        url = proc.stdout.readline().strip()
        assert url.startswith("http://127.0.0.1:"), log.read_text()
        status, headers, body = _get(url)
        assert status == 200 and b"clutchsim explore: passenger-car launch" in body
        port = url.rsplit(":", 1)[1].strip("/")
        assert "connect-src ws://127.0.0.1:" + port in headers["Content-Security-Policy"]
        assert "default-src 'none'" in headers["Content-Security-Policy"]
        assert _get(url + "static/explore.js")[0] == 200
        for path in ("static/..%2F__init__.py", "static/app.py", "static/explore.html",
                     "static/%2Fetc%2Fpasswd", "../../etc/passwd", "ws/../app.py"):
            assert _get(url + path)[0] in (403, 404), path
        assert _get(url, host=f"attacker.example:{port}")[0] == 403

        async def connect(origin):
            req = HTTPRequest(url.replace("http", "ws") + "ws", headers={"Origin": origin})
            try:
                ws = await websocket_connect(req)
            except HTTPClientError as exc:
                return exc.code
            first = await ws.read_message()        # the page's controls
            ws.close()
            # until the server's close frame: the socket is closed here, not left to the
            # garbage collector (with warnings as errors its ResourceWarning failed
            # whichever later test was running when it was collected)
            while await ws.read_message() is not None:
                pass
            return json.loads(first)["op"]
        assert asyncio.run(connect("http://attacker.example")) == 403
        assert asyncio.run(connect(url.rstrip("/"))) == "controls"
    finally:
        proc.send_signal(signal.SIGINT)
        proc.communicate(timeout=30)
    assert proc.returncode == 130
    text = log.read_text()
    assert "interrupted (SIGINT)" in text and "Traceback" not in text
    assert "GET /" not in text                   # no line a request
