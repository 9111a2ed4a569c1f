"""Figures of a sweep: heat maps over 2-D grids, histograms and scatter for samples."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ._style import new_figure, save_png

__all__ = ["plot_heatmap", "plot_histograms", "plot_scatter", "write_figures"]

#: metrics shown by default, most telling first
MAIN_METRICS = ("lockup_time_s", "slip_energy_J", "peak_heat_node_temp_C", "jerk_peak_mps3",
                "vdv_mps175", "engine_speed_min_rpm")


def _label(table, col: str) -> str:
    unit = table.attrs.get("units", {}).get(col, "")
    return f"{col} [{unit}]" if unit and unit != "-" else col


def plot_heatmap(table, x: str, y: str, metric: str):
    """``metric`` over the grid of ``x`` and ``y`` (failed runs blank); ``(fig, ax)``."""
    xs, ys = np.unique(table[x]), np.unique(table[y])
    grid = np.full((ys.size, xs.size), np.nan)
    ix, iy = np.searchsorted(xs, table[x]), np.searchsorted(ys, table[y])
    vals = table[metric].to_numpy(dtype=float, na_value=np.nan)
    grid[iy, ix] = vals
    fig, ax = new_figure(figsize=(7.0, 5.5))
    a = ax[0, 0]
    mesh = a.pcolormesh(_edges(xs), _edges(ys), np.ma.masked_invalid(grid), shading="flat")
    fig.colorbar(mesh, ax=a, label=_label(table, metric))
    bad = table["status"] != "completed"
    if bad.any():
        a.plot(table[x][bad], table[y][bad], "kx", label="did not complete")
        a.legend(loc="best", fontsize=8)
    a.set_xlabel(_label(table, x))
    a.set_ylabel(_label(table, y))
    a.set_title(f"{metric} over {x} × {y}")
    return fig, ax


def _edges(v: np.ndarray) -> np.ndarray:
    if v.size == 1:
        return np.array([v[0] - 0.5, v[0] + 0.5])
    mid = 0.5 * (v[1:] + v[:-1])
    return np.concatenate([[2 * v[0] - mid[0]], mid, [2 * v[-1] - mid[-1]]])


def plot_histograms(table, metrics):
    """One histogram per metric over the completed runs; ``(fig, axes)``."""
    metrics = list(metrics)
    ok = table["status"] == "completed"
    fig, ax = new_figure(1, len(metrics), figsize=(3.6 * len(metrics), 3.6))
    for a, m in zip(ax[0], metrics):
        v = table[m][ok].to_numpy(dtype=float, na_value=np.nan)
        v = v[np.isfinite(v)]
        if v.size:
            a.hist(v, bins=min(40, max(5, int(np.sqrt(v.size)))))
        a.set_xlabel(_label(table, m))
        a.grid(True, alpha=0.3)
    ax[0, 0].set_ylabel("runs")
    fig.suptitle(f"{int(ok.sum())} of {len(table)} runs completed")
    return fig, ax


def plot_scatter(table, inputs, metric: str):
    """``metric`` against each varied input (failed runs marked); ``(fig, axes)``."""
    inputs = list(inputs)
    ok = table["status"] == "completed"
    fig, ax = new_figure(1, len(inputs), figsize=(3.8 * len(inputs), 3.6), sharey=True)
    for a, k in zip(ax[0], inputs):
        a.plot(table[k][ok], table[metric][ok], ".", ms=3)
        if (~ok).any():
            lo = np.nanmin(table[metric][ok]) if ok.any() else 0.0
            a.plot(table[k][~ok], np.full(int((~ok).sum()), lo), "rx", ms=4,
                   label="did not complete")
            a.legend(loc="best", fontsize=8)
        a.set_xlabel(_label(table, k))
        a.grid(True, alpha=0.3)
    ax[0, 0].set_ylabel(_label(table, metric))
    return fig, ax


def write_figures(path, table, manifest) -> list[Path]:
    """The figures that fit the design, written into ``path``; the list of files."""
    path = Path(path)
    metrics = [m for m in MAIN_METRICS if m in table.columns]
    grid, rand = manifest.get("grid_keys", []), manifest.get("random_keys", [])
    files = []
    if not metrics or table.empty:
        return files
    if len(grid) == 2 and not rand:
        for m in metrics[:3]:
            fig, _ = plot_heatmap(table, grid[0], grid[1], m)
            files.append(save_png(fig, path / f"heatmap_{m}.png"))
    if rand or len(grid) != 2:
        fig, _ = plot_histograms(table, metrics)
        files.append(save_png(fig, path / "histograms.png"))
        fig, _ = plot_scatter(table, manifest.get("keys", grid + rand), metrics[0])
        files.append(save_png(fig, path / f"scatter_{metrics[0]}.png"))
    return files
