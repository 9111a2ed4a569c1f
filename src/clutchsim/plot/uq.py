"""Figures of an uncertainty study: distributions (histogram and CDF) of the main metrics,
the probability of each event with its interval, sensitivity bars with their intervals,
and the convergence of the estimates against the number of runs."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ._style import new_figure, save_png
from .sweep import MAIN_METRICS

__all__ = ["plot_convergence", "plot_distributions", "plot_probabilities",
           "plot_sensitivity", "write_figures"]


def _label(result, name: str) -> str:
    unit = result.units.get(name, "")
    return f"{name} [{unit}]" if unit and unit != "-" else name


def plot_distributions(result, columns: dict, metrics):
    """Histogram (left axis) and empirical CDF (right axis) of each metric, with the study's
    p05/p50/p95 marked; ``(fig, axes)``."""
    metrics = list(metrics)
    fig, ax = new_figure(1, len(metrics), figsize=(3.8 * len(metrics), 3.6))
    for a, m in zip(ax[0], metrics):
        v = columns[m][np.isfinite(columns[m])]
        if v.size:
            a.hist(v, bins=min(50, max(5, int(np.sqrt(v.size)))), color="0.75")
            c = a.twinx()
            s = np.sort(v)
            c.plot(s, np.arange(1, s.size + 1) / s.size, "C0-")
            c.set_ylim(0, 1)
            c.set_ylabel("CDF")
            q = result.quantiles.get(m, {})
            for name, style in (("p05", ":"), ("p50", "--"), ("p95", ":")):
                if q.get(name) is not None:
                    a.axvline(q[name], color="C3", ls=style)
        a.set_xlabel(_label(result, m))
        a.grid(True, alpha=0.3)
    ax[0, 0].set_ylabel("runs")
    fig.suptitle(f"{result.method}: {result.samples} runs (p05, p50, p95 in red)")
    return fig, ax


def plot_probabilities(result):
    """The probability of each event with its 95 % interval (log scale; events that never
    happened show their upper bound); ``(fig, axes)``."""
    names = list(result.probabilities)
    p = np.array([result.probabilities[n]["p"] for n in names], dtype=float)
    lo = np.array([result.probabilities[n]["ci95"][0] for n in names], dtype=float)
    hi = np.array([result.probabilities[n]["ci95"][1] for n in names], dtype=float)
    fig, ax = new_figure(figsize=(7.5, 0.35 * len(names) + 1.5))
    a = ax[0, 0]
    y = np.arange(len(names))
    floor = min(0.5 / max(result.samples, 1), float(np.min(hi[hi > 0])) if (hi > 0).any()
                else 1e-6)
    shown = np.maximum(p, floor)
    a.errorbar(shown, y, xerr=[shown - np.maximum(lo, floor), np.maximum(hi - shown, 0)],
               fmt="o", capsize=3)
    a.set_xscale("log")
    a.set_yticks(y, [f"{n} ({result.probabilities[n]['count']})" for n in names])
    a.set_xlabel("probability (95 % Clopper–Pearson interval; count of runs)")
    a.invert_yaxis()
    a.grid(True, alpha=0.3, which="both")
    return fig, ax


def plot_sensitivity(result, outputs):
    """Sobol' S1 and ST (or Morris mu*) per input for each output, with their 95 %
    intervals; ``(fig, axes)``."""
    sens = result.sobol if result.sobol is not None else result.morris
    outputs = list(outputs)
    keys = list(result.inputs)
    fig, ax = new_figure(1, len(outputs), figsize=(3.6 * len(outputs) + 1.0, 3.8),
                         sharey=True)
    y = np.arange(len(keys))
    parts = (("S1", -0.18), ("ST", 0.18)) if result.sobol is not None else \
        (("mu_star", 0.0),)
    for a, name in zip(ax[0], outputs):
        for part, dy in parts:
            v = np.array([sens[name][k][part] for k in keys], dtype=float)
            ci = np.array([sens[name][k][f"{part}_ci95"] for k in keys], dtype=float)
            a.barh(y + dy, v, height=0.34 if len(parts) > 1 else 0.6, label=part,
                   xerr=[v - ci[:, 0], ci[:, 1] - v], capsize=2)
        a.set_title(name, fontsize=9)
        a.grid(True, alpha=0.3)
        a.set_xlabel("index" if result.sobol is not None else "mu* (per level step)")
    ax[0, 0].set_yticks(y, keys)
    ax[0, 0].invert_yaxis()
    ax[0, 0].legend(loc="best", fontsize=8)
    return fig, ax


def plot_convergence(result, names):
    """Each estimate (and its interval or p05–p95 band) against the number of runs;
    ``(fig, axes)``."""
    names = list(names)
    fig, ax = new_figure(len(names), 1, figsize=(7.0, 2.2 * len(names) + 0.5), sharex=True)
    for a, name in zip(ax[:, 0], names):
        c = result.convergence[name]
        n = np.asarray(c["n"], dtype=float)
        v, lo, hi = (np.asarray(c[k], dtype=float) for k in ("value", "lo", "hi"))
        a.fill_between(n, lo, hi, alpha=0.25)
        a.plot(n, v, "o-", ms=3)
        a.set_ylabel(name, fontsize=8)
        a.set_xscale("log")
        a.grid(True, alpha=0.3, which="both")
    ax[-1, 0].set_xlabel("runs")
    return fig, ax


def write_figures(path, result, columns: dict) -> list[Path]:
    """The study's figures in ``path``; the list of files."""
    path = Path(path)
    files = []
    metrics = [m for m in MAIN_METRICS if m in columns and np.isfinite(columns[m]).any()]
    if metrics:
        fig, _ = plot_distributions(result, columns, metrics[:4])
        files.append(save_png(fig, path / "uq_distributions.png"))
    fig, _ = plot_probabilities(result)
    files.append(save_png(fig, path / "uq_probabilities.png"))
    sens = result.sobol if result.sobol is not None else result.morris
    if sens:
        outputs = [m for m in (*MAIN_METRICS, *sens) if m in sens]
        outputs = list(dict.fromkeys(outputs))[:4]
        fig, _ = plot_sensitivity(result, outputs)
        files.append(save_png(fig, path / "uq_sensitivity.png"))
    conv = [n for n in result.convergence if n.startswith("P(") and n != "P(completed)"][:3]
    conv += [f"p50({m})" for m in metrics[:2] if f"p50({m})" in result.convergence]
    if result.sobol:
        first = next(iter(result.sobol))
        conv += [n for n in result.convergence if n.startswith(f"ST({first};")][:3]
    if conv:
        fig, _ = plot_convergence(result, conv)
        files.append(save_png(fig, path / "uq_convergence.png"))
    return files
