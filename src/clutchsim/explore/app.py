"""The launch explorer as a Bokeh server app: sliders for the launch parameters of a
:class:`~clutchsim.explore.session.Session`, re-simulating on every change and redrawing
the traces and the launch metrics.

Why a Bokeh server: the session lives in Python (the compiled plant is reused between
runs), a slider change travels over one websocket to it and back as new column data, the
figures are the same ones the interactive report draws (:mod:`clutchsim.plot.interactive`),
and Bokeh is a maintained library with its own server, so no web framework is added.

:func:`make_document` fills a Bokeh ``Document`` (the tests build one without a server);
:func:`serve` runs the server on the loopback interface.
"""

from __future__ import annotations

import logging
from html import escape
from pathlib import Path

import numpy as np

from .session import METRICS, Session, check_error

__all__ = ["EXPLORER_GROUPS", "MAX_POINTS", "export", "free_port", "make_document", "metrics_html", "serve"]

log = logging.getLogger("clutchsim")

#: the trace groups the explorer draws (titles of :func:`clutchsim.plot.interactive.unit_groups`)
EXPLORER_GROUPS = ("speeds", "torques", "power", "acceleration", "temperatures")
#: the most rows of a run the explorer draws (less data a redraw: the round trip is the
#: latency budget; peaks are kept, :func:`clutchsim.plot.interactive.display_rows`)
MAX_POINTS = 2500


def _display(outcome):
    """``(groups, units)`` for :func:`clutchsim.plot.interactive.traces_column` from an
    :class:`~clutchsim.explore.session.ExplorerRun`: the explorer's groups in display units."""
    from ..plot.interactive import unit_groups
    units = {k: u for k, u in outcome.units.items() if k != "t"}
    groups, shown = [], {}
    for title, unit, names, factor in unit_groups(units):
        if title not in EXPLORER_GROUPS:
            continue
        groups.append((f"{title} [{unit}]",
                       {n: np.asarray(outcome.traces[n], dtype=float) * factor for n in names}))
        shown.update({n: unit for n in names})
    return groups, shown


def _columns(groups, t) -> dict:
    """The column data the figures draw (at most :data:`MAX_POINTS` rows)."""
    from ..plot.interactive import display_rows
    data = {"t": np.asarray(t, dtype=float)}
    for _, cols in groups:
        data.update({k: np.asarray(v, dtype=float) for k, v in cols.items()})
    rows = display_rows(data["t"], [v for k, v in data.items() if k != "t"], MAX_POINTS)
    return {k: v[rows] if k == "t" else v[rows].astype(np.float32) for k, v in data.items()}


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
    return ('<table class="metrics" style="border-collapse:collapse;font-size:13px">'
            + "".join(rows) + "</table>")


def make_document(doc, session: Session, *, out_dir: str | Path | None = None) -> None:
    """Fill the Bokeh ``doc`` with the explorer of ``session``: a slider per parameter, a
    field for any key path, the model, the metrics and the traces.  ``out_dir``: where
    "export" writes the traces and the ``--set`` items of the current state (None: no
    export button)."""
    from bokeh.layouts import column, row
    from bokeh.models import Button, Div, Select, Slider, TextInput

    from ..plot.interactive import traces_column

    outcome = session.run()
    groups, units = _display(outcome)
    plots, source = traces_column(outcome.traces["t"], groups, units=units, height=190,
                                  width=820, max_points=MAX_POINTS)
    holder = column(plots, name="plots")
    metrics = Div(text=metrics_html(outcome), name="metrics", width=360, height=300)
    error = Div(text="", name="error", width=360, styles={"color": "#b3261e"})
    state = {"keys": set(source.data), "source": source, "compare": None,
             "cmp_source": _attach_compare(plots.children[0], groups[0][1])}

    def compared():
        """The run of the compared model (None: no comparison), its speeds drawn dashed."""
        other = state["compare"]
        if other is None:
            state["cmp_source"].data = {k: [] for k in state["cmp_source"].data}
            return None
        out = other.run()
        g, _ = _display(out)
        data = _columns(g[:1], out.traces["t"])
        state["cmp_source"].data = {k: data.get(k, np.zeros(len(data["t"]), np.float32))
                                    for k in state["cmp_source"].data}
        return out

    def redraw():
        out = session.run()
        g, u = _display(out)
        data = _columns(g, out.traces["t"])
        if set(data) == state["keys"]:
            state["source"].data = data
        else:       # another model: other series, new figures
            new, src = traces_column(out.traces["t"], g, units=u, height=190, width=820,
                                     max_points=MAX_POINTS)
            holder.children = [new]
            state["keys"], state["source"] = set(src.data), src
            state["cmp_source"] = _attach_compare(new.children[0], g[0][1])
        metrics.text = metrics_html(out, compared())

    def apply(key, value):
        try:
            session.set(key, value)
            if state["compare"] is not None and ".friction." not in key:
                state["compare"].set(key, value)
        except (ValueError, KeyError) as exc:
            error.text = escape(check_error(exc))
            return
        error.text = ""
        redraw()

    sliders = []
    for p in session.parameters:
        s = Slider(start=p.low, end=p.high, value=p.value, step=p.step,
                   title=f"{p.label} [{p.unit}]", name=p.key, width=340, format="0[.]0000")
        s.on_change("value", lambda attr, old, new, key=p.key: apply(key, new))
        sliders.append(s)
    field = TextInput(title="any key path = value (e.g. vehicle.rolling = 0.015)",
                      name="keyvalue", width=340)

    def on_field(attr, old, new):
        if "=" not in new:
            error.text = escape(f"{new!r}: expected key.path = value")
            return
        key, value = (x.strip() for x in new.split("=", 1))
        apply(key, value)
    field.on_change("value", on_field)
    controls = [*sliders, field]
    if len(session.models) > 1:
        select = Select(title="friction model", value=session.model,
                        options=list(session.models), name="model", width=340)

        def on_model(attr, old, new):
            try:
                session.set_model(new)
            except (ValueError, KeyError) as exc:
                error.text = escape(check_error(exc))
                return
            error.text = ""
            redraw()
        select.on_change("value", on_model)
        others = Select(title="compare with (speeds dashed)", value="none",
                        options=["none", *session.models], name="compare", width=340)

        def on_compare(attr, old, new):
            other = None
            if new != "none":
                try:
                    other = Session(session.scenario, new)
                    for k, v in session.values.items():
                        if ".friction." not in k:
                            other.set(k, v)
                except (ValueError, KeyError) as exc:
                    error.text = escape(check_error(exc))
                    return
            error.text = ""
            state["compare"] = other
            redraw()
        others.on_change("value", on_compare)
        controls[:0] = [select, others]
    if out_dir is not None:
        button = Button(label=f"export traces and scenario to {out_dir}", width=340,
                        name="export")

        def on_export():
            try:
                written = export(session, out_dir)
            except OSError as exc:
                error.text = escape(check_error(exc))
                return
            error.text = escape("written: " + ", ".join(str(p) for p in written))
        button.on_click(on_export)
        controls.append(button)
    title = Div(text=f"<h2>{escape(session.scenario.name)}</h2>", width=1200)
    doc.add_root(column(title, row(column(*controls, error, metrics), holder)))
    doc.title = f"clutchsim explore: {session.scenario.name}"


def _attach_compare(fig, series):
    """Dashed lines on ``fig`` for the ``series`` (names) of a compared run, each in its
    series' colour and without a legend entry of its own; returns their (empty)
    ColumnDataSource."""
    from bokeh.models import ColumnDataSource

    from ..plot.interactive import PALETTE
    src = ColumnDataSource({"t": np.zeros(0), **{n: np.zeros(0, np.float32) for n in series}})
    for i, name in enumerate(series):
        fig.line("t", name, source=src, color=PALETTE[i % len(PALETTE)], line_width=1.2,
                 line_dash="dashed")
    return src


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


def free_port() -> int:
    """A TCP port free on 127.0.0.1 now (the system's choice)."""
    import socket
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def serve(session: Session, *, port: int = 0, open_browser: bool = True,
          out_dir: str | Path | None = None, on_start=None) -> None:
    """Run the explorer on ``http://127.0.0.1:PORT/`` until interrupted (``port`` 0: a
    free one).  Bound to the loopback interface only.  ``on_start(url)`` is called once
    the server listens.  OSError when the port is taken."""
    from bokeh.application import Application
    from bokeh.application.handlers.function import FunctionHandler
    from bokeh.server.server import Server

    if not port:
        port = free_port()
    for name in ("bokeh", "tornado.access"):     # no line a request on clutchsim's stderr
        logging.getLogger(name).setLevel(logging.WARNING)

    def build(doc):     # a session per page: two tabs do not share their values
        make_document(doc, Session(session.scenario, session.model), out_dir=out_dir)
    server = Server({"/": Application(FunctionHandler(build))}, port=port,
                    address="127.0.0.1",
                    allow_websocket_origin=[f"127.0.0.1:{port}", f"localhost:{port}"],
                    num_procs=1)
    actual = server.port
    server.start()
    url = f"http://127.0.0.1:{actual}/"
    if on_start is not None:
        on_start(url)
    if open_browser:
        server.io_loop.add_callback(server.show, "/")
    try:
        server.io_loop.start()
    finally:
        server.stop()
