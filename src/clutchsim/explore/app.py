"""The launch explorer as a small local web app: sliders for the launch parameters of a
:class:`~clutchsim.explore.session.Session`, re-simulating on every change and redrawing
the traces and the launch metrics.

Design, chosen by measurement (docs/explore.md): a Tornado server (Tornado comes with the
``explore`` extra, as Bokeh's server) serving one page and one websocket, and a lean client
drawing with uPlot (``static/uPlot.iife.min.js``, v1.6.32, MIT licence in
``static/uPlot.LICENSE``, 51 kB, canvas time series with zoom, cursor values and series
toggled from the legend).  Bokeh's client spent 80--250 ms of a software-rendered
browser's time applying a new run to five figures (its layout, text measurement and
per-renderer indices) where the server needed 4--9 ms; uPlot redraws the same five figures
in a few ms.  The interactive report keeps Bokeh (one self-contained file, no server).

The protocol, one websocket per page (each page its own session): the client sends JSON
(``{"op": "set", "key", "value"}``, ``{"op": "field", "text"}``, ``{"op": "model"}``,
``{"op": "compare"}``, ``{"op": "export"}``, each with its ``seq``); the server answers a
re-run with the metrics first (JSON, ``op`` ``metrics``: the table as escaped HTML), then
the traces (one binary message, :func:`traces_payload`), then ``{"op": "done"}``; a refused
value with ``{"op": "error"}`` (the run command's message) and ``done``; an export with
``{"op": "info"}`` naming the files written.  The page's controls come as
``{"op": "controls"}``, first and after a change of model.  The client keeps at most one
request in flight and, of the values set meanwhile, sends only each control's latest.

:class:`Explorer` is that logic without a server (the tests drive it directly);
:func:`make_app` the Tornado application and :func:`serve` runs it on the loopback
interface.
"""

from __future__ import annotations

import json
import logging
import struct
from html import escape
from pathlib import Path

import numpy as np

from .session import METRICS, Session, check_error

__all__ = ["EXPLORER_GROUPS", "MAX_ROWS", "STATIC", "Explorer", "decode_payload", "export",
           "make_app", "metrics_html", "require_server", "serve", "traces_payload"]

log = logging.getLogger("clutchsim")

#: the trace groups the explorer draws (titles of :func:`clutchsim.plot.interactive.unit_groups`)
EXPLORER_GROUPS = ("speeds", "torques", "power", "acceleration", "temperatures")
#: the most rows of a run one figure draws; above it, the rows where a series of the
#: figure is smallest or largest in each bucket (:func:`clutchsim.plot.interactive.display_rows`)
MAX_ROWS = 20_000
#: the page, its script and style, and uPlot
STATIC = Path(__file__).with_name("static")
_BINARY_MAGIC = b"CSX1"


def require_server():
    """The ``tornado`` module, or ModuleNotFoundError naming the extra that installs it."""
    try:
        import tornado
    except ModuleNotFoundError:
        raise ModuleNotFoundError(
            "the explorer needs Tornado (installed with Bokeh): pip install 'clutchsim[explore]'",
            name="tornado") from None
    return tornado


def _display(outcome, groups=EXPLORER_GROUPS):
    """``[(title, unit, {name: values in the display unit}), ...]`` of an
    :class:`~clutchsim.explore.session.ExplorerRun`, the explorer's ``groups`` only."""
    from ..plot.interactive import unit_groups
    units = {k: u for k, u in outcome.units.items() if k != "t"}
    return [(title, unit, {n: np.asarray(outcome.traces[n], dtype=float) * factor
                           for n in names})
            for title, unit, names, factor in unit_groups(units) if title in groups]


def traces_payload(outcome, compared=None, *, seq: int = 0, max_rows: int = MAX_ROWS) -> bytes:
    """The traces of a run as one binary message: ``b"CSX1"``, the length of a JSON header
    (uint32, little-endian), the header, then per figure its time [s] as float64 and its
    series as float32, each block starting on a multiple of 8 bytes.  The header holds
    ``seq`` and ``figures``: ``[{"title", "unit", "rows", "series": [names],
    "offset"}]``; ``compared`` (another model's run) adds a figure with ``"overlay": 0``,
    its speeds, to be drawn dashed over the first.  Each figure keeps at most ``max_rows``
    rows of the run (:func:`clutchsim.plot.interactive.display_rows`: samples, peaks kept)."""
    from ..plot.interactive import display_rows
    figures = [(title, unit, cols, None, outcome.traces["t"])
               for title, unit, cols in _display(outcome)]
    if compared is not None:
        title, unit, cols = _display(compared)[0]
        figures.append((f"{title} ({compared.model})", unit,
                        {f"{n} ({compared.model})": v for n, v in cols.items()}, 0,
                        compared.traces["t"]))
    blocks, header, offset = [], [], 0
    for title, unit, cols, overlay, t in figures:
        t = np.asarray(t, dtype=float)
        rows = display_rows(t, list(cols.values()), max_rows)
        block = t[rows].astype("<f8").tobytes() + b"".join(
            np.asarray(v[rows], dtype="<f4").tobytes() for v in cols.values())
        block += b"\0" * (-len(block) % 8)
        entry = {"title": title, "unit": unit, "rows": len(rows), "series": list(cols),
                 "offset": offset}
        if overlay is not None:
            entry["overlay"] = overlay
        header.append(entry)
        blocks.append(block)
        offset += len(block)
    head = json.dumps({"seq": seq, "figures": header}).encode("utf-8")
    head += b" " * (-(len(head) + 8) % 8)
    return _BINARY_MAGIC + struct.pack("<I", len(head)) + head + b"".join(blocks)


def decode_payload(data: bytes) -> tuple[dict, list[dict]]:
    """``(header, figures)`` of a :func:`traces_payload` message, each figure its header
    entry with ``"t"`` and ``"data"`` (series name -> array) added (what the page reads)."""
    if data[:4] != _BINARY_MAGIC:
        raise ValueError("not an explorer traces message")
    (n,) = struct.unpack("<I", data[4:8])
    header = json.loads(data[8:8 + n])
    base = 8 + n
    figures = []
    for f in header["figures"]:
        at, rows = base + f["offset"], f["rows"]
        t = np.frombuffer(data, "<f8", rows, at)
        at += 8 * rows
        cols = {}
        for name in f["series"]:
            cols[name] = np.frombuffer(data, "<f4", rows, at)
            at += 4 * rows
        figures.append({**f, "t": t, "data": cols})
    return header, figures


def metrics_html(outcome, compared=None) -> str:
    """The status and launch metrics of a run as a small HTML table (values escaped);
    ``compared``: the run of another model, its status, lock-up time and slip energy."""
    ok = outcome.completed
    rows = [(f'<tr><th>status</th><td id="status" class="{"ok" if ok else "bad"}">'
             f'{escape(outcome.status)}: {escape(outcome.message)}</td></tr>')]
    for key, (label, unit) in METRICS.items():
        v = outcome.metrics.get(key)
        if isinstance(v, float) and np.isfinite(v):
            text = f"{v:.4g}"
        elif v is None or isinstance(v, float):
            text = "—"
        else:
            text = escape(str(v))
        rows.append(f'<tr><th>{escape(label)}</th><td id="{key}" data-key="{key}">{text}</td>'
                    f"<td>{escape(unit)}</td></tr>")
    rows.append(f"<tr><th>run time</th><td>{outcome.run_ms:.1f}</td><td>ms</td></tr>")
    if compared is not None:
        m = compared.metrics
        rows.append(f'<tr><th colspan="3">compared: {escape(compared.model)} '
                    f"({escape(compared.status)})</th></tr>")
        for key in ("lockup_time_s", "slip_energy_J"):
            v = m.get(key)
            text = f"{v:.4g}" if isinstance(v, float) and np.isfinite(v) else "—"
            label, unit = METRICS[key]
            rows.append(f'<tr><th>{escape(label)}</th><td id="compared_{key}">{text}</td>'
                        f"<td>{escape(unit)}</td></tr>")
    return '<table class="metrics">' + "".join(rows) + "</table>"


class Explorer:
    """The explorer of one page, without a server: ``handle(message)`` takes a message of
    the page (a dict) and returns the answers (dicts, and bytes for the traces) in the order
    they are sent.  ``out_dir``: where "export" writes (None: no export)."""

    def __init__(self, session: Session, *, out_dir: str | Path | None = None):
        self.session, self.out_dir = session, out_dir
        self.compare: Session | None = None

    def controls(self) -> dict:
        """The controls of the page (``op`` ``controls``): the scenario's name, the models,
        the parameters with their current values and ranges, the export folder."""
        s = self.session
        return {"op": "controls", "title": s.scenario.name, "model": s.model,
                "models": list(s.models) if len(s.models) > 1 else [],
                "export": None if self.out_dir is None else str(self.out_dir),
                "parameters": [{"key": p.key, "label": p.label, "unit": p.unit,
                                "value": s.value(p.key), "low": p.low, "high": p.high,
                                "step": p.step, "doc": p.doc} for p in s.parameters]}

    def init(self) -> list:
        """The first answers: the controls and the first run."""
        return [self.controls(), *self._redraw(0)]

    def _redraw(self, seq: int) -> list:
        """Metrics first (the page shows them at once), then the traces, then done."""
        out = self.session.run()
        other = self.compare.run() if self.compare is not None else None
        return [{"op": "metrics", "seq": seq, "html": metrics_html(out, other)},
                traces_payload(out, other, seq=seq), {"op": "done", "seq": seq}]

    def _refused(self, seq: int, exc: BaseException) -> list:
        return [{"op": "error", "seq": seq, "text": check_error(exc)},
                {"op": "done", "seq": seq}]

    def handle(self, msg: dict) -> list:
        """Answers to one message of the page (see the module docstring)."""
        op, seq = msg.get("op"), msg.get("seq", 0)
        if not isinstance(seq, int):
            seq = 0
        try:
            if op == "set":
                self._set(str(msg.get("key")), msg.get("value"))
            elif op == "field":
                text = str(msg.get("text", ""))
                if "=" not in text:
                    raise ValueError(f"{text!r}: expected key.path = value")
                key, value = (x.strip() for x in text.split("=", 1))
                self._set(key, value)
            elif op == "model":
                self.session.set_model(str(msg.get("value")))
            elif op == "compare":
                self._compare(str(msg.get("value", "none")))
            elif op == "export":
                if self.out_dir is None:
                    raise ValueError("export: no --out folder was given to clutchsim explore")
                written = export(self.session, self.out_dir)
                return [{"op": "info", "seq": seq,
                         "text": "written: " + ", ".join(str(p) for p in written)},
                        {"op": "done", "seq": seq}]
            else:
                raise ValueError(f"op = {op!r}: not a message the explorer knows")
        except (ValueError, KeyError, OSError) as exc:
            return self._refused(seq, exc)
        head = [self.controls()] if op == "model" else []    # its friction parameters
        return [*head, {"op": "error", "seq": seq, "text": ""}, *self._redraw(seq)]

    def _set(self, key: str, value) -> None:
        self.session.set(key, value)
        if self.compare is not None and ".friction." not in key:
            self.compare.set(key, self.session.values[key])

    def _compare(self, model: str) -> None:
        if model == "none":
            self.compare = None
            return
        other = Session(self.session.scenario, model)
        for k, v in self.session.values.items():
            if ".friction." not in k:
                other.set(k, v)
        self.compare = other


def export(session: Session, out_dir: str | Path) -> list[Path]:
    """Write the current run's traces (``explore_traces.csv``, units in the column names),
    the values set (``explore_set.txt``, one ``--set`` item a line) and the scenario with
    them (``explore_scenario.toml``) into ``out_dir``, atomically; nothing else there is
    touched."""
    from .._util import atomic_write
    d = Path(out_dir)
    out = session.run()
    names = list(out.traces)
    header = ",".join(f"{n} [{out.units.get(n, '')}]" for n in names)
    table = np.column_stack([out.traces[n] for n in names])

    def write_csv(p):
        np.savetxt(p, table, delimiter=",", header=header, comments="", fmt="%.9g")
    items = session.overrides()
    text = session.scenario_toml()
    return [atomic_write(d / "explore_traces.csv", write_csv),
            atomic_write(d / "explore_set.txt",
                         lambda p: Path(p).write_text("".join(f"{i}\n" for i in items),
                                                      encoding="utf-8")),
            atomic_write(d / "explore_scenario.toml",
                         lambda p: Path(p).write_text(text, encoding="utf-8"))]


_STATIC_FILES = ("explore.js", "explore.css", "uPlot.iife.min.js", "uPlot.min.css")


def make_app(session: Session, port: int, *, out_dir: str | Path | None = None):
    """The Tornado application of the explorer on ``port``: ``/`` (the page),
    ``/static/NAME`` (its script, style and uPlot; nothing else is served) and ``/ws``
    (each connection an :class:`Explorer` on a new session of ``session``'s scenario and
    model).  Requests whose Host is not ``127.0.0.1:PORT`` or ``localhost:PORT`` are refused
    (403), as are websockets from another origin."""
    from urllib.parse import urlsplit

    from tornado import web, websocket

    hosts = {f"127.0.0.1:{port}", f"localhost:{port}"}
    page = (STATIC / "explore.html").read_text(encoding="utf-8").replace(
        "{{title}}", escape(f"clutchsim explore: {session.scenario.name}"))
    csp = ("default-src 'none'; script-src 'self'; style-src 'self'; img-src 'self' data:; "
           f"connect-src ws://127.0.0.1:{port} ws://localhost:{port}; base-uri 'none'; "
           "form-action 'none'; frame-ancestors 'none'")

    class Local(web.RequestHandler):
        def prepare(self):
            if self.request.host not in hosts:
                raise web.HTTPError(403)
            self.set_header("Content-Security-Policy", csp)
            self.set_header("X-Content-Type-Options", "nosniff")

    class Page(Local):
        def get(self):
            self.set_header("Content-Type", "text/html; charset=utf-8")
            self.set_header("Cache-Control", "no-store")
            self.write(page)

    class Static(Local):
        def get(self, name):
            if name not in _STATIC_FILES:      # a fixed list: no path from the page
                raise web.HTTPError(404)
            kind = "text/css" if name.endswith(".css") else "text/javascript"
            self.set_header("Content-Type", f"{kind}; charset=utf-8")
            self.write((STATIC / name).read_bytes())

    class Socket(websocket.WebSocketHandler):
        def check_origin(self, origin):
            return urlsplit(origin).netloc in hosts and self.request.host in hosts

        def open(self):
            self.explorer = Explorer(Session(session.scenario, session.model), out_dir=out_dir)
            self._send(self.explorer.init())

        def on_message(self, message):
            try:
                msg = json.loads(message)
            except (TypeError, ValueError):
                msg = {"op": None}
            msg = msg if isinstance(msg, dict) else {"op": None}
            try:
                answers = self.explorer.handle(msg)
            except Exception as exc:     # a bug: said on the page and logged, the page goes on
                log.exception("clutchsim explore: internal error")
                seq = msg.get("seq", 0)
                answers = [{"op": "error", "seq": seq, "text": f"internal error (a bug in "
                            f"clutchsim): {type(exc).__name__}: {exc}"},
                           {"op": "done", "seq": seq}]
            self._send(answers)

        def _send(self, answers):
            for a in answers:
                if isinstance(a, bytes):
                    self.write_message(a, binary=True)
                else:
                    self.write_message(json.dumps(a))

    return web.Application([(r"/", Page), (r"/static/([A-Za-z0-9_.\-]+)", Static),
                            (r"/ws", Socket)], websocket_max_message_size=1 << 16,
                           log_function=lambda handler: None)


def serve(session: Session, *, port: int = 0, open_browser: bool = True,
          out_dir: str | Path | None = None, on_start=None) -> None:
    """Run the explorer on ``http://127.0.0.1:PORT/`` until interrupted (``port`` 0: a
    free one).  Bound to the loopback interface only.  ``on_start(url)`` is called once
    the server listens.  OSError when the port is taken."""
    import asyncio

    from tornado.httpserver import HTTPServer
    from tornado.netutil import bind_sockets

    sockets = bind_sockets(port, address="127.0.0.1")
    actual = sockets[0].getsockname()[1]
    url = f"http://127.0.0.1:{actual}/"

    async def main():
        server = HTTPServer(make_app(session, actual, out_dir=out_dir))
        server.add_sockets(sockets)
        if on_start is not None:
            on_start(url)
        if open_browser:
            import webbrowser
            webbrowser.open(url)
        try:
            await asyncio.Event().wait()
        finally:
            server.stop()
    asyncio.run(main())
