"""The interactive report (``clutchsim report DIR --interactive``): the report of an output
directory with its time series as interactive figures (Bokeh: zoom, pan, hover values with
units, linked time axes across the traces of one run, series toggled from the legend),
still one self-contained HTML file: Bokeh's JavaScript is inlined and the page fetches
nothing (its Content-Security-Policy allows its own inline scripts only).

Per run (``timeseries[_MODEL].csv`` or ``.parquet``): one figure per unit (speeds in rpm,
torques, slip power in kW, accelerations raw and ISO-weighted, temperatures, energy flow,
commands), the engine's torque against its full-load torque at the same speed
(``T_engine``, ``T_full_load``: the torque reserve), a lock-up zoom panel (the speeds from 0.1 s before to 0.1 s after the lock-up
time of ``summary.json``) and, with several models, their speeds overlaid on one axis.
To keep the file small the figures draw at most :data:`MAX_POINTS` rows of a run
(:func:`clutchsim.plot.interactive.display_rows`: samples of the run, peaks kept); the
full series stay in the data files.  The PNG figures of the traces (:data:`REPLACED`)
stay in the directory for printing, the other PNGs stay in the page; the metrics,
parameters, scenario and file tables are those of the static report.
A default launch (``clutchsim run``, its two models) gives a file of about 2.1 MB (1.3 MB
of it Bokeh's library).
"""

from __future__ import annotations

import json
from dataclasses import replace
from html import escape
from pathlib import Path

import numpy as np

from ..plot.interactive import split_label
from .build import _write
from .gather import REPORT_NAME, gather
from .html import render

__all__ = ["MAX_POINTS", "REPLACED", "ZOOM_S", "build_interactive_report", "interactive_figures",
           "read_series"]

#: the most rows of one run the figures draw (the data files keep every row)
MAX_POINTS = 2500
#: PNG figures of the time series that the interactive figures replace in the page (the
#: others, e.g. an actuation chain's characteristics, stay)
REPLACED = ("launch_", "comparison.png", "network_")
#: the engine's torque and its full-load torque at the same speed (its own figure)
ENGINE_LOAD = ("T_engine", "T_full_load")
#: the lock-up zoom panel: this long before and after the lock-up time [s]
ZOOM_S = 0.1


def read_series(path: Path) -> tuple[np.ndarray, dict, dict]:
    """``(t [s], {name: array}, {name: unit})`` of a ``timeseries*.csv`` / ``.parquet``
    file (columns ``name [unit]``, the time ``time [s]``)."""
    import pandas as pd
    frame = pd.read_parquet(path) if path.suffix == ".parquet" else pd.read_csv(path)
    cols, units = {}, {}
    for c in frame.columns:
        name, unit = split_label(c)
        if not np.issubdtype(frame[c].dtype, np.number):
            continue
        cols[name], units[name] = frame[c].to_numpy(dtype=float), unit
    key = next((k for k in ("time", "t") if k in cols), None)
    if key is None:
        raise ValueError(f"{path.name}: no time column 'time [s]'")
    t = cols.pop(key)
    units.pop(key)
    return t, cols, units


def _runs(d: Path) -> dict[str, Path]:
    """model (or run) label -> its time-series file (Parquet preferred: exact values)."""
    found: dict = {}
    for p in sorted(d.glob("timeseries*.*")):
        if p.suffix not in (".csv", ".parquet") or not p.is_file():
            continue
        label = p.stem[len("timeseries_"):] if p.stem.startswith("timeseries_") else "run"
        if label not in found or p.suffix == ".parquet":
            found[label] = p
    return found


def _lockup_times(d: Path) -> dict:
    try:
        doc = json.loads((d / "summary.json").read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}
    models = doc.get("models") if isinstance(doc, dict) else None
    if not isinstance(models, dict):
        return {}
    out = {}
    for name, m in models.items():
        t = m.get("lockup_time_s") if isinstance(m, dict) else None
        if isinstance(t, (int, float)) and not isinstance(t, bool) and np.isfinite(t):
            out[name] = float(t)
    return out


def interactive_figures(directory: str | Path, *, max_points: int = MAX_POINTS) -> list:
    """The interactive figures of an output directory: ``[(title, Bokeh layout), ...]``,
    one column of linked figures per run, its lock-up zoom panel, and the overlay of the
    models' speeds (see the module docstring)."""
    from bokeh.models import ColumnDataSource, Range1d

    from ..plot.interactive import (
        display_rows,
        overlay_figure,
        trace_figure,
        traces_column,
        unit_groups,
    )
    d = Path(directory)
    runs = _runs(d)
    lockup = _lockup_times(d)
    out, speeds = [], {}
    for label, path in runs.items():
        t, cols, units = read_series(path)
        groups, shown = [], {}
        for title, unit, names, factor in unit_groups(units):
            groups.append((f"{title} [{unit}]", {n: cols[n] * factor for n in names}))
            shown.update({n: unit for n in names})
            if title == "speeds":
                speeds[label] = (t, {n: cols[n] * factor for n in names})
        if not groups:
            continue
        layout, _ = traces_column(t, groups, units=shown, max_points=max_points, height=200)
        out.append((f"{label}: {path.name}", layout))
        if all(n in cols for n in ENGINE_LOAD):
            # the engine's torque under its full-load curve (T_full_load: what it would give
            # at that speed at full throttle), the torque reserve a driver or controller has
            rows = display_rows(t, [cols[n] for n in ENGINE_LOAD], max_points)
            src = ColumnDataSource({"t": t[rows], **{n: cols[n][rows].astype(np.float32)
                                                     for n in ENGINE_LOAD}})
            out.append((f"{label}: engine torque and its full-load curve", trace_figure(
                src, "t", list(ENGINE_LOAD), title=f"{label}: engine torque against its "
                "full-load torque at the same speed", unit="N·m", height=220)))
        tl = lockup.get(label)
        if tl is not None and label in speeds:
            ts, sp = speeds[label]
            window = (ts >= tl - ZOOM_S) & (ts <= tl + ZOOM_S)
            src = ColumnDataSource({"t": ts[window],
                                    **{k: v[window].astype(np.float32) for k, v in sp.items()}})
            fig = trace_figure(src, "t", list(sp), title=f"{label}: lock-up at {tl:.3f} s "
                               f"(± {ZOOM_S} s)", unit="rpm", height=240,
                               x_range=Range1d(tl - ZOOM_S, tl + ZOOM_S))
            out.append((f"{label}: lock-up zoom", fig))
    if len(speeds) > 1:
        shown = {}
        for label, (ts, sp) in speeds.items():
            rows = display_rows(ts, list(sp.values()), max_points)
            shown[label] = (ts[rows], {n: v[rows] for n, v in sp.items()})
        out.append(("models compared", overlay_figure(
            shown, title="models compared: speeds (the first solid, the others dashed)",
            unit="rpm")))
    return out


def _bokeh_parts(figures, note: str | None = None) -> tuple[str, str]:
    """``(head, body)``: the inlined Bokeh library and the figures' script, and their
    ``div``\\ s under headings after ``note`` (default: how to use a run's figures)."""
    from bokeh.embed import components
    from bokeh.resources import Resources
    script, divs = components([f for _, f in figures])
    head = Resources(mode="inline", components=["bokeh"]).render_js() + script
    body = "".join(f"<h3>{escape(title)}</h3>{div}" for (title, _), div in zip(figures, divs))
    if note is None:
        note = ("Drag to zoom, wheel to zoom time, click a legend entry to hide its line; "
                f"at most {MAX_POINTS:,} rows of a run are drawn (the data files hold every "
                "row).")
    return head, f"<p>{escape(note)}</p>" + body


def build_interactive_report(out_dir: str | Path, *, title: str | None = None,
                             max_points: int = MAX_POINTS) -> Path:
    """Write ``out_dir/report.html`` with interactive figures (see the module docstring;
    sweeps, UQ, durability, judder and fit directories: :mod:`.interactive_kinds`)
    atomically; returns its path.  A directory with nothing to draw interactively gets
    the static report.  Raises as :func:`clutchsim.report.build_report`."""
    from .._util import atomic_write
    from .interactive_kinds import KINDS, directory_kind, kind_figures
    data = gather(out_dir, title=title)
    kind = directory_kind(out_dir)
    if kind is not None:
        replaced, note = KINDS[kind][1], KINDS[kind][2]
        try:
            figures = kind_figures(out_dir, kind)
        except (OSError, ValueError, KeyError, TypeError, IndexError) as exc:
            # a damaged data file: the static figures, and the page says why
            figures = []
            data.problems.append(f"the interactive figures of this {kind} directory could "
                                 f"not be drawn ({type(exc).__name__}: {exc}); the static "
                                 "figures are shown")
    else:
        figures = interactive_figures(out_dir, max_points=max_points)
        replaced, note = REPLACED, None
    if figures:     # the PNGs the figures replace stay in the directory, for printing
        kept = [f for f in data.figures if not f.name.startswith(replaced)]
        page = render(replace(data, figures=kept), interactive=_bokeh_parts(figures, note))
    else:
        page = render(data)
    return atomic_write(Path(out_dir) / REPORT_NAME, lambda p: _write(Path(p), page))
