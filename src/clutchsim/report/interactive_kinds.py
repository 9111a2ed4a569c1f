"""Interactive figures of the output directories that are not runs: sweeps, uncertainty
studies, durability studies, judder analyses and fits (``clutchsim report DIR
--interactive``).  Each reads the data files its command wrote (nothing is simulated
again) and returns ``[(title, Bokeh layout), ...]`` for :mod:`clutchsim.report.interactive`.

* **sweep** (``results.parquet``): every metric against every swept parameter, one panel
  each, the runs coloured by outcome, hover giving the run, its parameter values and its
  outcome; the panels share one data source, so a box or lasso selection in one selects
  the same runs in all; histograms with the empirical CDF of the main metrics (completed
  runs); a 2-D grid sweep, its main metrics as maps over the grid.  Replaces
  ``scatter_*.png``, ``histograms.png`` and ``heatmap_*.png``.
* **uq** (``uq.json``, ``results.parquet``): histogram and empirical CDF of every metric
  with the study's p05/p50/p95 marked; Sobol' S1 and ST (Morris mu*) per input with their
  95 % intervals as error bars; the convergence of the estimates against the number of
  runs.  Replaces ``uq_distributions.png``, ``uq_sensitivity.png`` and
  ``uq_convergence.png``; the probabilities stay a table (and ``uq_probabilities.png``).
* **durability** (``durability.csv``): peak temperature, friction work, wear, clamp force
  and capacity against the start number, linked.  Replaces ``durability.png``.
* **judder** (``judder.json``, ``judder_map.json``, ``frf.json``): the modes (damping
  ratio against natural frequency, unstable ones in red), the stability map (smallest
  damping ratio over the grid) and the frequency response (magnitude over phase, log
  frequency axis, peaks marked).  Replaces ``judder.png``, ``judder_map.png`` and
  ``frf.png``.
* **fit** (``traces.csv``): measured and simulated output, and the residual, against
  time with linked time axes, in the output's unit (``output_unit`` of fit.json).
  Replaces ``fit.png`` and ``residuals.png``.

Large tables are drawn downsampled (:data:`MAX_ROWS` runs of a sweep, :data:`MAX_POINTS`
rows of a trace); the data files keep every row.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

__all__ = ["KINDS", "MAX_PANELS", "MAX_ROWS", "directory_kind", "kind_figures"]

#: the most runs of a sweep drawn in its scatter panels (runs that did not complete first)
MAX_ROWS = 5000
#: the most scatter panels of a sweep (metrics x swept parameters; main metrics first)
MAX_PANELS = 60
#: the most rows of a trace drawn (as a run's, :data:`clutchsim.report.interactive.MAX_POINTS`)
MAX_POINTS = 2500
#: statistics of the solver, left out of the scatter panels (they are not results)
_SOLVER = ("steps", "rhs_evals", "events", "min_step_s", "rejected", "wall_s")
#: the file that tells a directory's kind, in the order they are looked for
_KIND_FILE = (("uq", "uq.json"), ("sweep", "sweep.json"), ("durability", "durability.csv"),
              ("judder", "judder.json"), ("judder", "judder_map.json"),
              ("judder", "frf.json"), ("fit", "traces.csv"))


def directory_kind(directory) -> str | None:
    """The kind of a study directory (``"sweep"``, ``"uq"``, ``"durability"``,
    ``"judder"``, ``"fit"``) from the files in it, or None (a run, a bench, ...)."""
    d = Path(directory)
    for kind, name in _KIND_FILE:
        if (d / name).is_file() and (kind != "fit" or (d / "fit.json").is_file()):
            return kind
    return None


def _main_first(names) -> list[str]:
    from ..plot.sweep import MAIN_METRICS
    names = list(names)
    return [m for m in MAIN_METRICS if m in names] + [m for m in names if m not in MAIN_METRICS]


def _shown_rows(ok: np.ndarray, limit: int) -> np.ndarray:
    """Indices of the runs drawn: all when at most ``limit``, else the runs that did not
    complete (up to half of ``limit``) and evenly spaced completed ones."""
    n = ok.size
    if n <= limit:
        return np.arange(n)
    bad = np.flatnonzero(~ok)[: limit // 2]
    good = np.flatnonzero(ok)
    k = limit - bad.size
    pick = good[np.unique(np.linspace(0, good.size - 1, k).round().astype(int))] \
        if good.size else good
    return np.sort(np.concatenate([bad, pick]))


def sweep_figures(d: Path) -> list:
    from ..plot.interactive_studies import distribution_figure, scatter_grid
    from ..studies.sweeps import read_results
    table = read_results(d)
    units = table.attrs.get("units", {})
    manifest = table.attrs.get("sweep", {})
    if not manifest:
        manifest = json.loads((d / "sweep.json").read_text(encoding="utf-8"))
    keys = [k for k in manifest.get("keys", []) if k in table.columns]
    metrics = [m for m in manifest.get("metrics", []) if m in table.columns
               and m not in _SOLVER and table[m].dtype.kind in "fiu"
               and np.isfinite(table[m].to_numpy(dtype=float, na_value=np.nan)).any()]
    metrics = _main_first(metrics)[: max(1, MAX_PANELS // max(len(keys), 1))]
    if not keys or not metrics or table.empty:
        return []
    ok = (table["status"] == "completed").to_numpy()
    out = _heat_maps(table, manifest, metrics, units)
    rows = _shown_rows(ok, MAX_ROWS)
    shown = table.iloc[rows]
    data = {"run": shown["run"].to_numpy(dtype=float), "outcome": list(shown["outcome"])}
    for c in (*keys, *metrics):
        data[c] = shown[c].to_numpy(dtype=float, na_value=np.nan)
    note = "" if rows.size == len(table) else \
        f" ({rows.size:,} of {len(table):,} runs drawn; results.parquet holds all)"
    out.append(((f"{len(metrics)} metrics against {len(keys)} swept "
                 f"parameter{'s' if len(keys) > 1 else ''}: {len(table):,} runs{note}; "
                 "select runs with the box or lasso tool"),
                scatter_grid(data, keys, metrics, units=units,
                             hover=("run", *keys, "outcome"))))
    from ..plot.sweep import MAIN_METRICS
    hist = [m for m in MAIN_METRICS if m in metrics]
    if hist:
        figs = [distribution_figure(table[m][ok].to_numpy(dtype=float, na_value=np.nan),
                                    name=m, unit=units.get(m, "")) for m in hist]
        out.append((f"distributions over the {int(ok.sum()):,} completed runs", _grid(figs)))
    return out


def _heat_maps(table, manifest: dict, metrics, units: dict) -> list:
    """A 2-D grid sweep (two grid keys, nothing sampled): the main metrics as coloured maps
    over the grid (as ``heatmap_*.png``; runs that did not complete grey), hover giving
    the point and the metric."""
    from ..plot.interactive_studies import _axis, map_figure
    from ..plot.sweep import MAIN_METRICS
    grid = [k for k in manifest.get("grid_keys") or [] if k in table.columns]
    if len(grid) != 2 or manifest.get("random_keys"):
        return []
    x, y = grid
    xv, yv = (table[k].to_numpy(dtype=float) for k in grid)
    xs, ys = np.unique(xv), np.unique(yv)
    ix, iy = np.searchsorted(xs, xv), np.searchsorted(ys, yv)
    ok = (table["status"] == "completed").to_numpy()
    out = []
    for m in [m for m in MAIN_METRICS if m in metrics][:3]:
        z = np.full((ys.size, xs.size), np.nan)
        z[iy[ok], ix[ok]] = table[m].to_numpy(dtype=float, na_value=np.nan)[ok]
        label = _axis(m, units.get(m, ""))
        fig = map_figure(xs, ys, z, x_label=_axis(x, units.get(x, "")),
                         y_label=_axis(y, units.get(y, "")), z_label=label,
                         title=f"{m} over {x} × {y} (grey: no completed run)",
                         diverging=False)
        out.append((f"{label} over the grid of {x} and {y}", fig))
    return out


def _grid(figs, ncols: int = 2):
    from bokeh.layouts import gridplot
    rows = [figs[i:i + ncols] for i in range(0, len(figs), ncols)]
    return gridplot(rows, toolbar_location="right", merge_tools=True)


def uq_figures(d: Path) -> list:
    from ..plot.interactive_studies import band_figure, distribution_figure, interval_figure
    from ..studies.sweeps import read_results
    doc = json.loads((d / "uq.json").read_text(encoding="utf-8"))
    out = []
    quantiles = doc.get("quantiles") or {}
    units = {}
    if (d / "results.parquet").is_file():
        table = read_results(d)
        units = table.attrs.get("units", {})
        metrics = [m for m in _main_first(quantiles) if m in table.columns
                   and m not in _SOLVER and table[m].dtype.kind in "fiu"]
        figs = []
        for m in metrics:
            v = table[m].to_numpy(dtype=float, na_value=np.nan)
            if not np.isfinite(v).any():
                continue
            q = quantiles.get(m) or {}
            figs.append(distribution_figure(
                v, name=m, unit=units.get(m, ""),
                marks={k: q.get(k) for k in ("p05", "p50", "p95")}))
        if figs:
            out.append(((f"distributions of {len(figs)} metrics over {len(table):,} runs "
                        "(p05, p50, p95 in red)"), _grid(figs)))
    for what, parts in (("sobol", ("S1", "ST")), ("morris", ("mu_star",))):
        sens = doc.get(what)
        if not isinstance(sens, dict) or not sens:
            continue
        figs = []
        for output in _main_first(sens):
            per = sens[output]
            inputs = list(per)
            try:
                groups = {p: ([per[k][p] for k in inputs],
                              [per[k][f"{p}_ci95"][0] for k in inputs],
                              [per[k][f"{p}_ci95"][1] for k in inputs]) for p in parts}
            except (KeyError, TypeError, IndexError):
                continue
            label = "index [-]" if what == "sobol" else f"mu* [{units.get(output, '-')}]"
            figs.append(interval_figure(inputs, groups, title=output, x_label=label))
        if figs:
            title = ("Sobol' indices S1 and ST with their 95 % intervals" if what == "sobol"
                     else "Morris mu* with its 95 % interval")
            out.append((title, _grid(figs)))
    conv = doc.get("convergence")
    if isinstance(conv, dict) and conv:
        names = _convergence_names(doc, conv)
        figs, x_range = [], None
        for name in names:
            c = conv[name]
            metric = name[name.find("(") + 1:-1] if name.startswith("p50(") else ""
            unit = units.get(metric, "-") if metric else "-"
            fig = band_figure(c["n"], c["value"], c["lo"], c["hi"], title=name,
                              y_label=f"{name} [{unit}]", x_range=x_range)
            x_range = x_range or fig.x_range
            figs.append(fig)
        if figs:
            from bokeh.layouts import column
            out.append((("convergence against the number of runs (band: the 95 % interval "
                        "of a probability or index, the p05–p95 range of a median)"),
                        column(*figs)))
    return out


def _convergence_names(doc: dict, conv: dict) -> list[str]:
    """The estimates whose convergence is drawn: the probabilities of the events that
    happened, the medians of the main metrics, the total indices of the first output."""
    probs = doc.get("probabilities") or {}
    names = [n for n in conv if n.startswith("P(")
             and (probs.get(n[2:-1]) or {}).get("count", 1) > 0]
    names += [f"p50({m})" for m in _main_first([n[4:-1] for n in conv
                                                if n.startswith("p50(")])[:4]]
    sobol = doc.get("sobol")
    if isinstance(sobol, dict) and sobol:
        first = _main_first(sobol)[0]
        names += [n for n in conv if n.startswith(f"ST({first};")]
    return [n for n in dict.fromkeys(names) if n in conv and isinstance(conv[n], dict)
            and {"n", "value", "lo", "hi"} <= set(conv[n])][:12]


#: durability.csv columns drawn: column -> (title, display unit, factor)
_DURABILITY = {"peak_theta_C": ("peak temperature", "°C", 1.0),
               "friction_work_J": ("friction work", "kJ", 1e-3),
               "wear_m": ("wear", "mm", 1e3),
               "clamp_force_N": ("clamp force", "N", 1.0),
               "capacity_Nm": ("capacity", "N·m", 1.0)}


def durability_figures(d: Path) -> list:
    import pandas as pd

    from ..plot.interactive import traces_column
    frame = pd.read_csv(d / "durability.csv", skiprows=[1])
    if "cycle" not in frame.columns or frame.empty:
        return []
    groups, units = [], {}
    for col, (title, unit, factor) in _DURABILITY.items():
        if col in frame.columns:
            groups.append((f"{title} [{unit}]", {title: frame[col].to_numpy(float) * factor}))
            units[title] = unit
    if not groups:
        return []
    layout, _ = traces_column(frame["cycle"].to_numpy(float), groups, units=units,
                              t_name="start", x_label="start [-]", markers=True, height=200,
                              max_points=MAX_POINTS)
    n = len(frame)
    return [(f"per start: {n} recorded starts (between them the study extrapolates)",
             layout)]


def judder_figures(d: Path) -> list:
    from ..plot.interactive_studies import map_figure, modes_figure
    out = []
    p = d / "judder.json"
    if p.is_file():
        doc = json.loads(p.read_text(encoding="utf-8"))
        modes = [m for m in doc.get("modes") or [] if isinstance(m, dict)]
        t = (doc.get("operating_point") or {}).get("t_s")
        at = f" at t = {t:g} s" if isinstance(t, (int, float)) else ""
        if modes:
            out.append((f"modes of {doc.get('model', 'the driveline')}{at}",
                        modes_figure(modes, title=f"{len(modes)} modes{at} (below the "
                                     "dashed line: unstable)")))
    p = d / "judder_map.json"
    if p.is_file():
        doc = json.loads(p.read_text(encoding="utf-8"))
        fig = _map(doc, map_figure)
        if fig is not None:
            out.append(((f"stability map of {doc.get('model', 'the driveline')} at t = "
                        f"{doc.get('t_s', 0):g} s"), fig))
    p = d / "frf.json"
    if p.is_file():
        out += _frf(json.loads(p.read_text(encoding="utf-8")))
    return out


def _frf(doc: dict) -> list:
    """The frequency response of ``frf.json`` (``clutchsim judder --frf``): magnitude over
    phase against frequency, the peaks marked."""
    from ..plot.interactive_studies import bode_figures
    f, mag, phase = (np.asarray(doc.get(k) or [], dtype=float)
                     for k in ("frequency_hz", "magnitude", "phase_deg"))
    if not f.size or not f.size == mag.size == phase.size:
        return []
    name = f"{doc.get('output', 'output')}/{doc.get('input', 'input')}"
    at = f" at t = {doc['t_s']:g} s" if isinstance(doc.get("t_s"), (int, float)) else ""
    warned = f"; {len(doc['warnings'])} warning(s), see frf.json" if doc.get("warnings") else ""
    title = f"frequency response {name} of {doc.get('model', 'the driveline')}{at}"
    return [(title + warned, bode_figures(f, mag, phase, name=name, unit=str(doc.get("unit", "")),
                                          peaks=doc.get("peaks") or [], title=title))]


def _map(doc: dict, map_figure):
    """The judder map of ``judder_map.json``: a coloured grid (two keys) or the margin
    against the one key."""
    from ..plot.interactive import traces_column
    points = [p for p in doc.get("points") or [] if isinstance(p, dict)]
    xk = (doc.get("x") or {}).get("key")
    yk = (doc.get("y") or {}).get("key") if isinstance(doc.get("y"), dict) else None
    if not points or xk is None:
        return None
    xs = np.asarray((doc.get("x") or {}).get("values") or [], dtype=float)
    if yk is None:
        pts = sorted(points, key=lambda p: p.get(xk, 0.0))
        x = np.array([p.get(xk, np.nan) for p in pts], dtype=float)
        z = np.array([_num(p.get("damping_ratio")) for p in pts])
        layout, _ = traces_column(x, [("smallest damping ratio [-]", {"damping_ratio": z})],
                                  units={"damping_ratio": "-"}, t_name="x",
                                  x_label=f"{xk} [-]", markers=True)
        return layout
    ys = np.asarray(doc["y"].get("values") or [], dtype=float)
    grids = {k: np.full((ys.size, xs.size), np.nan) for k in
             ("damping_ratio", "frequency_hz", "growth_rate_1_s")}
    for p in points:
        i = int(np.argmin(np.abs(ys - _num(p.get(yk)))))
        j = int(np.argmin(np.abs(xs - _num(p.get(xk)))))
        for k, g in grids.items():
            g[i, j] = _num(p.get(k))
    unstable = sum(1 for p in points if p.get("stable") is False)
    return map_figure(xs, ys, grids["damping_ratio"], x_label=xk, y_label=yk,
                      z_label="smallest damping ratio [-]",
                      title=f"judder margin: {len(points)} points, {unstable} unstable "
                      "(red: damping ratio < 0)",
                      extra={"frequency": (grids["frequency_hz"], "Hz"),
                             "growth rate": (grids["growth_rate_1_s"], "1/s")})


def _num(v) -> float:
    return float(v) if isinstance(v, (int, float)) and not isinstance(v, bool) else np.nan


def fit_figures(d: Path) -> list:
    import pandas as pd

    from ..plot.interactive import traces_column
    frame = pd.read_csv(d / "traces.csv")
    if not {"t", "measured", "simulated", "residual"} <= set(frame.columns) or frame.empty:
        return []
    doc = json.loads((d / "fit.json").read_text(encoding="utf-8"))
    output = str(doc.get("output", "output"))
    unit = doc.get("output_unit")
    col = lambda c: frame[c].to_numpy(float)
    groups = [(f"{output}: measured and simulated", {"measured": col("measured"),
                                                     "simulated": col("simulated")}),
              (f"{output}: residual (measured − simulated)", {"residual": col("residual")})]
    units = dict.fromkeys(("measured", "simulated", "residual"), unit or "")
    layout, _ = traces_column(col("t"), groups, units=units, max_points=MAX_POINTS,
                              height=240)
    drawn = min(len(frame), MAX_POINTS)
    said = f"{output} in {unit}" if unit else (
        f"{output} (its unit: the data file's; fit.json of this directory does not record "
        "it)")
    return [((f"fit of {doc.get('model', '?')}: {said} against time [s] ({drawn:,} of "
             f"{len(frame):,} rows drawn; traces.csv holds all)"), layout)]


#: kind -> (figures of the directory, PNGs (name prefixes) the figures replace, a note)
KINDS = {
    "sweep": (sweep_figures, ("scatter_", "histograms.png", "heatmap_"),
              ("Box or lasso select runs in one panel to see them in all; hover a point for "
              "its run, parameters and outcome; click an outcome in the legend to hide it.")),
    "uq": (uq_figures, ("uq_distributions.png", "uq_sensitivity.png",
                        "uq_convergence.png"),
           ("Hover a bar, a point or a quantile line for its values; click a legend entry to "
           "hide it.")),
    "durability": (durability_figures, ("durability.png",),
                   "Drag to zoom (the start axes are linked), hover for the values."),
    "judder": (judder_figures, ("judder.png", "judder_map.png", "frf.png"),
               ("Hover a mode, a map cell or the frequency response for its values (the "
                "magnitude and phase share their frequency axis).")),
    "fit": (fit_figures, ("fit.png", "residuals.png"),
            ("Drag to zoom (the time axes are linked), hover for the values, click a legend "
            "entry to hide its line.")),
}


def kind_figures(directory, kind: str) -> list:
    """The interactive figures of a study directory of ``kind`` (a key of :data:`KINDS`):
    ``[(title, Bokeh layout), ...]``."""
    return KINDS[kind][0](Path(directory))
