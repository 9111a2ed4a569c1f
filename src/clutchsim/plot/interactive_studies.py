"""Interactive figures of studies (Bokeh): scatter panels of a sweep with linked selection,
distributions with their quantiles marked, indices with their intervals as error bars,
estimates converging with their bands, a driveline's modes, a map over a grid (stability
margin or a sweep's metric) and a frequency response.

Drawing only, as :mod:`clutchsim.plot.interactive`: the functions take arrays and names
with their units and return Bokeh models; what to draw is chosen by the caller
(:mod:`clutchsim.report.interactive_kinds`).  Bokeh is imported on use.
"""

from __future__ import annotations

import numpy as np

from .interactive import PALETTE, _legend_right

__all__ = ["OUTCOME_COLOURS", "band_figure", "bode_figures", "distribution_figure",
           "interval_figure", "map_figure", "modes_figure", "scatter_grid"]

#: the colour of an outcome in the scatter panels (others take the palette in turn)
OUTCOME_COLOURS = {"completed": "#0072b2", "stopped": "#56b4e9", "stalled": "#d55e00",
                   "chatter": "#cc79a7", "invariant_violated": "#e69f00"}
_TOOLS = "pan,box_zoom,wheel_zoom,reset,save"


def _axis(name: str, unit: str) -> str:
    return f"{name} [{unit}]" if unit and unit != "-" else name


def _fmt(unit: str) -> str:
    return f" {unit}" if unit and unit != "-" else ""


def _new(title: str, x_label: str, y_label: str, *, width: int, height: int, tools=_TOOLS,
         **kw):
    from bokeh.plotting import figure
    fig = figure(title=title, width=width, height=height, tools=tools, x_axis_label=x_label,
                 y_axis_label=y_label, **kw)
    fig.toolbar.logo = None
    return fig


def scatter_grid(data: dict, xs, ys, *, units: dict, colour_by: str = "outcome",
                 hover=(), width: int | None = None, height: int = 260):
    """A grid of scatter panels: each column of ``ys`` (rows of the grid) against each
    column of ``xs`` (columns of the grid), all drawn from one ColumnDataSource so that a
    box or lasso selection in one panel selects the same runs in all; the points coloured
    by the text column ``colour_by`` (legend in the first panel, a click hides an
    outcome).  ``data``: column name -> 1-D array (or list of str); ``units``: column ->
    unit; ``hover``: the columns each point's tooltip lists (plus the panel's x and y);
    ``width``: of a panel (default: about 880 px a row).  Panels of one row share the y
    range, of one column the x range; a panel's title is its metric.  Returns the grid."""
    from bokeh.layouts import gridplot
    from bokeh.models import ColumnDataSource, HoverTool
    from bokeh.transform import factor_cmap
    xs, ys = list(xs), list(ys)
    width = width or max(260, min(440, 880 // max(len(xs), 1)))
    source = ColumnDataSource({k: (np.asarray(v, dtype=float) if not _is_text(v) else
                                   [str(x) for x in v]) for k, v in data.items()})
    factors = list(dict.fromkeys(str(v) for v in data[colour_by]))
    colours = _factor_colours(factors)
    cmap = factor_cmap(colour_by, palette=colours, factors=factors)
    rows, x_ranges = [], {}
    for i, y in enumerate(ys):
        row, y_range = [], None
        for j, x in enumerate(xs):
            kw = {}
            if y_range is not None:
                kw["y_range"] = y_range
            if x in x_ranges:
                kw["x_range"] = x_ranges[x]
            fig = _new(y, _axis(x, units.get(x, "")),
                       _axis(y, units.get(y, "")), width=width, height=height,
                       tools=_TOOLS + ",box_select,lasso_select", **kw)
            first = i == 0 and j == 0
            r = fig.scatter(x, y, source=source, color=cmap, size=6, alpha=0.8,
                            selection_color=cmap, nonselection_alpha=0.12,
                            **({"legend_field": colour_by} if first else {}))
            tips = [(k, f"@{{{k}}}{{0.[0000]}}{_fmt(units.get(k, ''))}" if not
                     _is_text(data[k]) else f"@{{{k}}}")
                    for k in dict.fromkeys([*hover, x, y])]
            fig.add_tools(HoverTool(renderers=[r], tooltips=tips))
            if first:
                fig.legend[0].click_policy = "hide"
                fig.legend[0].label_text_font_size = "8pt"
                fig.legend[0].location = "top_left"
            y_range = y_range or fig.y_range
            x_ranges.setdefault(x, fig.x_range)
            row.append(fig)
        rows.append(row)
    return gridplot(rows, toolbar_location="right", merge_tools=True)


def _is_text(v) -> bool:
    return len(v) > 0 and isinstance(v[0], str) if isinstance(v, list) else \
        np.asarray(v).dtype.kind in "OUS"


def _factor_colours(factors) -> list[str]:
    spare = [c for c in PALETTE if c not in OUTCOME_COLOURS.values()] + list(PALETTE)
    out, k = [], 0
    for f in factors:
        if f in OUTCOME_COLOURS:
            out.append(OUTCOME_COLOURS[f])
        else:
            out.append(spare[k % len(spare)])
            k += 1
    return out


def distribution_figure(values, *, name: str, unit: str, marks=None, width: int = 440,
                        height: int = 300, max_points: int = 2000):
    """Histogram (runs, left axis) and empirical CDF (right axis, 0 to 1) of ``values``
    (NaN left out), with vertical lines at ``marks`` (``{"p05": value, ...}``), hover
    giving each bar's range and count and the CDF's value.  The CDF draws at most
    ``max_points`` points (every ``k``-th sorted value, the smallest and largest kept);
    the histogram counts every value.  Returns the figure."""
    from bokeh.models import ColumnDataSource, HoverTool, LinearAxis, Range1d
    v = np.asarray(values, dtype=float)
    v = np.sort(v[np.isfinite(v)])
    label = _axis(name, unit)
    fig = _new(f"{name}: {v.size} values", label, "runs", width=width, height=height)
    if not v.size:
        return fig
    bins = min(50, max(5, int(np.sqrt(v.size))))
    counts, edges = np.histogram(v, bins=bins)
    bars = fig.quad(top=counts, bottom=0, left=edges[:-1], right=edges[1:],
                    fill_color="#bbbbbb", line_color="white", legend_label="runs")
    fig.add_tools(HoverTool(renderers=[bars], tooltips=[
        ("from", f"@left{{0.[0000]}}{_fmt(unit)}"), ("to", f"@right{{0.[0000]}}{_fmt(unit)}"),
        ("runs", "@top")]))
    fig.y_range = Range1d(0, max(1, int(counts.max())) * 1.08)
    fig.extra_y_ranges = {"cdf": Range1d(0, 1.02)}
    fig.add_layout(LinearAxis(y_range_name="cdf", axis_label="CDF [-]"), "right")
    k = max(1, -(-v.size // max_points))
    rows = np.unique(np.r_[np.arange(0, v.size, k), v.size - 1])
    cdf = ColumnDataSource({"x": v[rows], "F": (rows + 1) / v.size})
    line = fig.step("x", "F", source=cdf, mode="after", y_range_name="cdf", color=PALETTE[0],
                    line_width=1.6, legend_label="CDF")
    fig.add_tools(HoverTool(renderers=[line], mode="vline", tooltips=[
        (name, f"@x{{0.[0000]}}{_fmt(unit)}"), ("CDF", "@F{0.000}")]))
    for mark, x in (marks or {}).items():
        if x is None or not np.isfinite(x):
            continue
        seg = fig.segment(x0=[x], x1=[x], y0=[0], y1=[1.02], y_range_name="cdf",
                          color="#b3261e", line_dash="dashed" if mark == "p50" else "dotted",
                          line_width=1.8, legend_label=f"{mark} = {x:.4g}{_fmt(unit)}")
        fig.add_tools(HoverTool(renderers=[seg], tooltips=[(mark, f"{x:.6g}{_fmt(unit)}")]))
    fig.legend[0].click_policy = "hide"
    fig.legend[0].label_text_font_size = "8pt"
    fig.legend[0].location = "top_left"
    fig.legend[0].background_fill_alpha = 0.6
    return fig


def interval_figure(labels, parts: dict, *, title: str, x_label: str, width: int = 440,
                    height: int | None = None):
    """Horizontal bars with error bars: ``parts`` = ``{part: (values, lo, hi)}`` (e.g.
    S1 and ST, each one value per label with its 95 % interval), one bar per label and
    part (dodged), hover giving the value and the interval.  Returns the figure."""
    from bokeh.models import ColumnDataSource, FactorRange, HoverTool, Whisker
    from bokeh.transform import dodge
    labels = [str(x) for x in labels]
    n = len(parts)
    height = height or max(180, 60 + 28 * len(labels) * max(n, 1))
    fig = _new(title, x_label, "", width=width, height=height,
               y_range=FactorRange(*reversed(labels)))
    bar = 0.8 / max(n, 1)
    for k, (part, (v, lo, hi)) in enumerate(parts.items()):
        offset = (k - (n - 1) / 2) * bar
        src = ColumnDataSource({"label": labels, "v": np.asarray(v, dtype=float),
                                "lo": np.asarray(lo, dtype=float),
                                "hi": np.asarray(hi, dtype=float)})
        y = dodge("label", -offset, range=fig.y_range)
        r = fig.hbar(y=y, right="v", height=bar * 0.9, source=src, legend_label=part,
                     color=PALETTE[k % len(PALETTE)], alpha=0.85)
        fig.add_layout(Whisker(source=src, base=y, lower="lo", upper="hi",
                               dimension="width", line_color="#333333"))
        fig.add_tools(HoverTool(renderers=[r], tooltips=[
            ("", "@label"), (part, "@v{0.000}"), ("95 % interval", "@lo{0.000} … @hi{0.000}")]))
    if fig.legend:
        _legend_right(fig)
    return fig


def band_figure(n, value, lo, hi, *, title: str, y_label: str, x_range=None,
                width: int = 900, height: int = 190):
    """An estimate against the number of runs ``n`` (log axis) with its band ``lo``–``hi``
    (an interval or the p05–p95 range), hover giving the three; ``x_range``: shared with
    other figures.  Returns the figure."""
    from bokeh.models import ColumnDataSource, HoverTool
    src = ColumnDataSource({k: np.asarray(a, dtype=float) for k, a in
                            (("n", n), ("v", value), ("lo", lo), ("hi", hi))})
    kw = {"x_range": x_range} if x_range is not None else {}
    fig = _new(title, "runs", y_label, width=width, height=height, x_axis_type="log", **kw)
    fig.varea(x="n", y1="lo", y2="hi", source=src, fill_color=PALETTE[0], fill_alpha=0.2)
    fig.line("n", "v", source=src, color=PALETTE[0], line_width=1.6)
    r = fig.scatter("n", "v", source=src, color=PALETTE[0], size=5)
    fig.add_tools(HoverTool(renderers=[r], tooltips=[
        ("runs", "@n{0}"), ("estimate", "@v{0.[0000]}"), ("band", "@lo{0.[0000]} … @hi{0.[0000]}")]))
    return fig


def modes_figure(modes, *, title: str, width: int = 900, height: int = 320):
    """A driveline's modes: damping ratio [-] against natural frequency [Hz], stable in
    blue, unstable in red, hover giving the growth rate [1/s] and the dominant states.
    ``modes``: ``[{"frequency_hz", "damping_ratio", "growth_rate_1_s", "stable",
    "dominant_states"}, ...]``.  Returns the figure."""
    from bokeh.models import ColumnDataSource, HoverTool, Span
    fig = _new(title, "natural frequency [Hz]", "damping ratio [-]", width=width,
               height=height)
    fig.add_layout(Span(location=0.0, dimension="width", line_color="#333333",
                        line_dash="dashed"))
    for stable, colour, word in ((True, PALETTE[0], "stable"), (False, "#b3261e", "unstable")):
        ms = [m for m in modes if bool(m.get("stable")) is stable]
        if not ms:
            continue
        src = ColumnDataSource({
            "f": [_num(m.get("frequency_hz")) for m in ms],
            "zeta": [_num(m.get("damping_ratio")) for m in ms],
            "growth": [_num(m.get("growth_rate_1_s")) for m in ms],
            "states": [", ".join(map(str, m.get("dominant_states") or [])) for m in ms]})
        r = fig.scatter("f", "zeta", source=src, size=9, color=colour, legend_label=word,
                        marker="circle" if stable else "x", line_width=2)
        fig.add_tools(HoverTool(renderers=[r], tooltips=[
            ("frequency", "@f{0.[000]} Hz"), ("damping ratio", "@zeta{0.[0000]}"),
            ("growth rate", "@growth{0.[0000]} 1/s"), ("dominant", "@states")]))
    if fig.legend:
        _legend_right(fig)
    return fig


def _num(v) -> float:
    return float(v) if isinstance(v, (int, float)) and not isinstance(v, bool) else np.nan


def map_figure(x, y, z, *, x_label: str, y_label: str, z_label: str, title: str,
               extra=None, diverging: bool = True, width: int = 760, height: int = 480):
    """A map over a grid: ``z[i, j]`` at ``(x[j], y[i])`` as coloured cells, a colour bar,
    and hover giving the point, ``z`` and the ``extra`` columns (``{name: (array like z,
    unit)}``); cells without a value (NaN: a run that failed) grey.  ``diverging``: a
    colour scale symmetric about 0, red below (a stability margin); else Viridis from the
    smallest to the largest value (a metric).  Returns the figure."""
    from bokeh.models import ColorBar, ColumnDataSource, HoverTool, LinearColorMapper
    from bokeh.palettes import RdBu11, Viridis256
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    z = np.asarray(z, dtype=float)
    X, Y = np.meshgrid(x, y)
    finite = z[np.isfinite(z)]
    if diverging:
        lim = float(np.abs(finite).max()) if finite.size else 1.0
        lim = lim if lim > 0 else 1.0
        palette, low, high = list(reversed(RdBu11)), -lim, lim
    else:
        low, high = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 1.0)
        palette, high = list(Viridis256), (high if high > low else low + 1.0)
    mapper = LinearColorMapper(palette=palette, low=low, high=high, nan_color="#dddddd")
    data = {"x": X.ravel(), "y": Y.ravel(), "z": z.ravel(),
            "w": np.broadcast_to(_cell(x), X.shape).ravel(),
            "h": np.broadcast_to(_cell(y)[:, None], X.shape).ravel()}
    tips = [(_name(x_label), "@x{0.[0000]}"), (_name(y_label), "@y{0.[0000]}"),
            (z_label, "@z{0.[0000]}")]
    for k, (name, (arr, unit)) in enumerate((extra or {}).items()):
        data[f"e{k}"] = np.asarray(arr, dtype=float).ravel()
        tips.append((name, f"@e{k}{{0.[0000]}}{_fmt(unit)}"))
    fig = _new(title, x_label, y_label, width=width, height=height)
    r = fig.rect("x", "y", "w", "h", source=ColumnDataSource(data),
                 fill_color={"field": "z", "transform": mapper}, line_color=None)
    fig.add_tools(HoverTool(renderers=[r], tooltips=tips))
    fig.add_layout(ColorBar(color_mapper=mapper, title=z_label), "right")
    return fig


def bode_figures(frequency_hz, magnitude, phase_deg, *, name: str, unit: str, peaks=(),
                 title: str = "", width: int = 900, height: int = 260):
    """A frequency response: ``|H|`` [``unit``] (log-log; a linear magnitude axis where it
    is 0 somewhere) over its phase [deg] (unwrapped along the grid), their frequency axes
    [Hz] linked, ``peaks`` (``[{"frequency_hz", "magnitude"}]``) marked in red, hover
    giving frequency, magnitude and phase.  ``name``: what H is (``"a_vehicle/throttle"``).
    Returns a column of the two figures."""
    from bokeh.layouts import column
    from bokeh.models import ColumnDataSource, HoverTool
    f = np.asarray(frequency_hz, dtype=float)
    mag = np.asarray(magnitude, dtype=float)
    phase = np.degrees(np.unwrap(np.radians(np.asarray(phase_deg, dtype=float))))
    src = ColumnDataSource({"f": f, "mag": mag, "phase": phase})
    tips = [("frequency", "@f{0.[000]} Hz"), (f"|{name}|", f"@mag{{0.[0000]}}{_fmt(unit)}"),
            ("phase", "@phase{0.[0]} deg")]
    top = _new(title, "frequency [Hz]", _axis(f"|{name}|", unit), width=width, height=height,
               x_axis_type="log", y_axis_type="log" if np.all(mag > 0) else "linear")
    r = top.line("f", "mag", source=src, color=PALETTE[0], line_width=1.6)
    top.add_tools(HoverTool(renderers=[r], mode="vline", tooltips=tips))
    pk = [p for p in peaks if isinstance(p, dict)]
    if pk:
        marks = ColumnDataSource({"f": [_num(p.get("frequency_hz")) for p in pk],
                                  "mag": [_num(p.get("magnitude")) for p in pk]})
        m = top.scatter("f", "mag", source=marks, marker="inverted_triangle", size=10,
                        color="#b3261e", legend_label="peak")
        top.add_tools(HoverTool(renderers=[m], tooltips=[
            ("peak", "@f{0.[000]} Hz"), (f"|{name}|", f"@mag{{0.[0000]}}{_fmt(unit)}")]))
        _legend_right(top)
    bottom = _new("", "frequency [Hz]", "phase [deg]", width=width, height=height - 40,
                  x_axis_type="log", x_range=top.x_range)
    r = bottom.line("f", "phase", source=src, color=PALETTE[1], line_width=1.6)
    bottom.add_tools(HoverTool(renderers=[r], mode="vline", tooltips=tips))
    return column(top, bottom)


def _cell(v: np.ndarray) -> np.ndarray:
    """The width of each grid cell (the spacing to its neighbours; 1 for a single value)."""
    if v.size < 2:
        return np.ones_like(v)
    return np.gradient(v)


def _name(label: str) -> str:
    return label.rsplit(" [", 1)[0]
