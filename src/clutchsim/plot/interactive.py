"""Interactive figures (Bokeh, optional extra ``explore``): time traces of a run with
linked time axes, hover values with units, zoom, pan and series toggled from the legend.

Drawing only: the functions take arrays (time [s] and named series with their units) and
return Bokeh models; what to plot is chosen by the caller (the interactive report,
:mod:`clutchsim.report.interactive`, and the launch explorer, :mod:`clutchsim.explore`).
Bokeh is imported on use, so that importing this module never needs it.
"""

from __future__ import annotations

import numpy as np

__all__ = ["BOKEH_EXTRA", "DISPLAY_UNITS", "GROUP_TITLES", "PALETTE", "display_rows",
           "overlay_figure", "require_bokeh", "split_label", "trace_figure", "traces_column",
           "unit_groups"]

#: the extra that installs Bokeh
BOKEH_EXTRA = "explore"
#: line colours, in order (colour-blind safe, as the PNG figures)
PALETTE = ("#0072b2", "#d55e00", "#009e73", "#cc79a7", "#e69f00", "#56b4e9", "#000000",
           "#f0e442")
_TOOLS = "xpan,xwheel_zoom,box_zoom,reset,save"


def require_bokeh():
    """The ``bokeh`` module, or ModuleNotFoundError naming the extra that installs it."""
    try:
        import bokeh
    except ModuleNotFoundError:
        raise ModuleNotFoundError(
            f"interactive figures need Bokeh: pip install 'clutchsim[{BOKEH_EXTRA}]'",
            name="bokeh") from None
    return bokeh


def display_rows(t, columns, max_points: int) -> np.ndarray:
    """Indices of the rows of a run to draw: every row when there are at most
    ``max_points``, else, in each of equal buckets of rows, the rows where some series of
    ``columns`` (a sequence of 1-D arrays as long as ``t``) is smallest or largest, plus
    the first and last row, with as many buckets as keep at most ``max_points`` rows.
    Each drawn point is a sample of the run (no interpolation) and peaks survive."""
    n = len(t)
    if n <= max_points:
        return np.arange(n)
    cols = np.array([np.asarray(c, dtype=float) for c in columns]).reshape(-1, n)
    buckets = max(max_points // 2 - 1, 1)
    while True:
        rows = _extreme_rows(cols, n, buckets)
        if len(rows) <= max_points or buckets == 1:
            return rows[:max_points] if len(rows) > max_points else rows
        buckets = max(int(buckets * max_points / len(rows) * 0.95), 1)


def _extreme_rows(cols: np.ndarray, n: int, buckets: int) -> np.ndarray:
    """First, last, and each series' smallest and largest row in each of ``buckets``
    equal buckets of rows (NaN never chosen over a number)."""
    size = -(-n // buckets)
    padded = np.full((cols.shape[0], buckets * size), np.nan)
    padded[:, :n] = cols
    blocks = padded.reshape(cols.shape[0], buckets, size)
    finite = np.isfinite(blocks)
    lo = np.where(finite, blocks, np.inf).argmin(axis=2)
    hi = np.where(finite, blocks, -np.inf).argmax(axis=2)
    start = (np.arange(buckets) * size)[None, :]
    rows = np.concatenate([(lo + start).ravel(), (hi + start).ravel(), [0, n - 1]])
    return np.unique(rows[rows < n])


def trace_figure(source, t_name: str, series, *, title: str, unit: str, x_range=None,
                 height: int = 220, width: int = 900, dashed=(), x_label: str = "t [s]",
                 markers: bool = False):
    """One figure: the columns ``series`` (names in ``source``, a Bokeh ColumnDataSource
    with the time column ``t_name``) against time, with hover values in ``unit``, the
    legend toggling each line, and ``x_range`` shared with other figures (None: its own).
    ``dashed``: names drawn dashed (a second model overlaid).  ``x_label``: the x axis as
    ``"name [unit]"`` (hover shows the x value with that name and unit); ``markers``: a
    dot at each point too.  Returns the figure."""
    from bokeh.models import HoverTool
    from bokeh.plotting import figure
    kw = {"x_range": x_range} if x_range is not None else {}
    fig = figure(title=title, height=height, width=width, tools=_TOOLS,
                 active_drag="box_zoom", active_scroll="xwheel_zoom",
                 x_axis_label=x_label, y_axis_label=f"[{unit}]" if unit else "", **kw)
    fig.toolbar.logo = None
    x_name, x_unit = split_label(x_label)
    x_fmt = "0.000" if x_unit == "s" else "0.[000]"
    for i, name in enumerate(series):
        color = PALETTE[i % len(PALETTE)]
        r = fig.line(t_name, name, source=source, color=color,
                     line_width=1.6, line_dash="dashed" if name in dashed else "solid",
                     legend_label=name)
        if markers:
            fig.scatter(t_name, name, source=source, color=color, size=4, legend_label=name)
        fig.add_tools(HoverTool(renderers=[r], mode="vline", tooltips=[
            (name, f"@{{{name}}}{{0.[000]}} {unit}"),
            (x_name, f"@{{{t_name}}}{{{x_fmt}}} {x_unit}".rstrip())]))
    if fig.legend:
        _legend_right(fig)
    return fig


def _legend_right(fig) -> None:
    """The legend beside the plot, compact (a line an entry of ~13 px), click hides."""
    legend = fig.legend[0]
    legend.click_policy = "hide"
    legend.label_text_font_size = "8pt"
    legend.label_height = legend.glyph_height = 11
    legend.spacing = 0
    legend.padding = 4
    legend.margin = 4
    fig.add_layout(legend, "right")


def overlay_figure(runs, *, title: str, unit: str, height: int = 300, width: int = 900):
    """Several runs on one axis: ``runs`` = ``{label: (t [s], {series name: 1-D array})}``,
    each run its own data (their time grids may differ), the first drawn solid, the others
    dashed, hover naming the run.  Returns the figure."""
    from bokeh.models import ColumnDataSource, HoverTool
    from bokeh.plotting import figure
    fig = figure(title=title, height=height, width=width, tools=_TOOLS,
                 active_drag="box_zoom", active_scroll="xwheel_zoom", x_axis_label="t [s]",
                 y_axis_label=f"[{unit}]")
    fig.toolbar.logo = None
    for k, (label, (t, cols)) in enumerate(runs.items()):
        src = ColumnDataSource({"t": np.asarray(t, dtype=float),
                                **{n: np.asarray(v, dtype=np.float32) for n, v in cols.items()}})
        for i, name in enumerate(cols):
            r = fig.line("t", name, source=src, color=PALETTE[i % len(PALETTE)],
                         line_width=1.6, line_dash="solid" if k == 0 else "dashed",
                         legend_label=f"{name} ({label})")
            fig.add_tools(HoverTool(renderers=[r], mode="vline", tooltips=[
                (f"{name} ({label})", f"@{{{name}}}{{0.[000]}} {unit}"),
                ("t", "@t{0.000} s")]))
    _legend_right(fig)
    return fig


def traces_column(t, groups, *, units, title: str = "", max_points: int | None = None,
                  t_name: str = "t", height: int = 220, width: int = 900, dashed=(),
                  x_label: str = "t [s]", markers: bool = False):
    """Figures of one run, one per group, their time axes linked.

    ``t``: time [s]; ``groups``: ``[(title, {series name: 1-D array}), ...]``; ``units``:
    series name -> unit (one unit a group); ``max_points``: draw at most this many rows
    (:func:`display_rows`; None: all); ``x_label``, ``markers``: as
    :func:`trace_figure`.  Returns ``(layout, source)``: a Bokeh column of
    the figures and the ColumnDataSource they share (replace its ``data`` to redraw)."""
    from bokeh.layouts import column
    from bokeh.models import ColumnDataSource, Div
    data = {t_name: np.asarray(t, dtype=float)}
    for _, cols in groups:
        data.update({k: np.asarray(v, dtype=float) for k, v in cols.items()})
    if max_points is not None:
        rows = display_rows(data[t_name], [v for k, v in data.items() if k != t_name],
                            max_points)
        data = {k: v[rows] for k, v in data.items()}
    source = ColumnDataSource({k: v.astype(np.float32) if k != t_name else v
                               for k, v in data.items()})
    figs, x_range = [], None
    for gtitle, cols in groups:
        names = list(cols)
        unit = units.get(names[0], "") if names else ""
        fig = trace_figure(source, t_name, names, title=gtitle, unit=unit, x_range=x_range,
                           height=height, width=width, dashed=dashed, x_label=x_label,
                           markers=markers)
        x_range = x_range or fig.x_range
        figs.append(fig)
    items = ([Div(text=f"<h3>{_escape(title)}</h3>")] if title else []) + figs
    return column(*items), source


def split_label(text: str) -> tuple[str, str]:
    """``("t", "s")`` from ``"t [s]"`` (a label or a data file's column name);
    ``(text, "")`` without a unit."""
    text = str(text)
    if text.endswith("]") and " [" in text:
        name, unit = text[:-1].rsplit(" [", 1)
        return name, unit
    return text, ""


def _escape(text: str) -> str:
    from html import escape
    return escape(str(text))


#: units drawn in another unit: unit -> (display unit, factor)
DISPLAY_UNITS = {"rad/s": ("rpm", 30.0 / np.pi), "W": ("kW", 1e-3)}
#: titles of the groups of :func:`unit_groups`, by display unit, in drawing order
GROUP_TITLES = {"rpm": "speeds", "N·m": "torques", "kW": "power", "m/s²": "acceleration",
                "m/s": "speed", "°C": "temperatures", "J": "energy", "N": "forces",
                "m": "travel", "-": "commands and ratios"}


def unit_groups(units: dict, *, skip=("rad",)) -> list[tuple[str, str, list[str], float]]:
    """The series of a run grouped by unit for drawing: ``[(title, display unit, names,
    factor), ...]`` (a series is drawn as ``value * factor``: rad/s as rpm, W as kW),
    the groups of :data:`GROUP_TITLES` first, in that order; ``skip``: units not drawn
    (angles)."""
    groups: dict = {}
    for name, unit in units.items():
        if unit in skip:
            continue
        shown, factor = DISPLAY_UNITS.get(unit, (unit, 1.0))
        groups.setdefault((shown, factor), []).append(name)
    order = list(GROUP_TITLES)
    keys = sorted(groups, key=lambda k: (order.index(k[0]) if k[0] in order else len(order),
                                         k[0]))
    return [(GROUP_TITLES.get(u, u or "other"), u, groups[(u, f)], f) for u, f in keys]
