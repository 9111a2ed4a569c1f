"""Figures of a parameter fit: measured against simulated output, and the residuals."""

from __future__ import annotations

import numpy as np

from ._style import new_figure

__all__ = ["plot_fit", "plot_loop", "plot_residuals"]


def _traces(result):
    out = [("fit", result.fit_trace)]
    out += [(f"validation {k + 1}", tr) for k, tr in enumerate(result.validation)]
    return out


def _label(tr) -> str:
    name = str(tr.source).replace("\\", "/").rsplit("/", 1)[-1]
    return f"{name}  (NRMSE {tr.nrmse:.3g})"


def plot_fit(result, *, unit: str = "", figsize=None):
    """Measured and simulated output over time, one panel per record.

    When the traces carry a reference (EMPS: ``q_ref``) the panels show output minus
    reference, the tracking error (the position itself hides every difference).

    Returns
    -------
    (Figure, ndarray of Axes, list of Line2D)
    """
    traces = _traces(result)
    fig, axes = new_figure(len(traces), 1, figsize=figsize or (9.0, 2.8 * len(traces) + 0.6))
    lines = []
    for ax, (what, tr) in zip(axes[:, 0], traces):
        meas, sim = tr.measured, tr.simulated
        ylabel = f"{result.output} [{unit}]" if unit else result.output
        if tr.reference is not None:
            ylabel = f"{result.output} − {result.input}" + (f" [{unit}]" if unit else "")
            meas, sim = meas - tr.reference, sim - tr.reference
        lines += ax.plot(tr.t, meas, lw=0.8, color="0.2", label="measured")
        lines += ax.plot(tr.t, sim, lw=0.8, color="C3", alpha=0.85,
                         label=f"simulated ({result.model_name})")
        ax.set_title(f"{what}: {_label(tr)}", fontsize=9)
        ax.set_ylabel(ylabel)
        ax.legend(loc="upper right", fontsize=8)
    axes[-1, 0].set_xlabel("time [s]")
    return fig, axes, lines


def plot_residuals(result, *, unit: str = "", figsize=None):
    """Residuals (simulated − measured) over time and their histogram, per record.

    Returns
    -------
    (Figure, ndarray of Axes, list of artists)
    """
    traces = _traces(result)
    fig, axes = new_figure(len(traces), 2, figsize=figsize or (10.0, 2.6 * len(traces) + 0.6),
                           width_ratios=[3, 1])
    artists = []
    for row, (what, tr) in enumerate(traces):
        r = tr.residual
        ax, axh = axes[row, 0], axes[row, 1]
        artists += ax.plot(tr.t, r, lw=0.6, color="C0")
        ax.axhline(0.0, color="0.5", lw=0.6)
        ax.set_title(f"{what}: residual, RMS {np.sqrt(np.mean(r ** 2)):.3g}"
                     + (f" {unit}" if unit else ""), fontsize=9)
        ax.set_ylabel("sim − meas" + (f" [{unit}]" if unit else ""))
        _, _, patches = axh.hist(r, bins=60, color="C0", orientation="horizontal")
        artists += list(patches)
        axh.set_xlabel("count")
    axes[-1, 0].set_xlabel("time [s]")
    return fig, axes, artists


def plot_loop(trace, x, *, ax=None, x_unit: str = "m", f_unit: str = "N", title: str = ""):
    """Force against displacement (hysteresis loop), measured and simulated.

    Parameters
    ----------
    trace : Trace
        A fit or validation trace whose output is a force.
    x : array_like
        Displacement on the trace's time grid.
    ax : Axes, optional
        Draw into this axes (default: a new figure).

    Returns
    -------
    (Figure, Axes, list of Line2D)
    """
    if ax is None:
        fig, axes = new_figure(figsize=(5.0, 4.0))
        ax = axes[0, 0]
    else:
        fig = ax.figure
    lines = ax.plot(x, trace.measured, lw=0.7, color="0.2", label="measured")
    lines += ax.plot(x, trace.simulated, lw=0.7, color="C3", alpha=0.85, label="simulated")
    ax.set_xlabel(f"displacement [{x_unit}]")
    ax.set_ylabel(f"force [{f_unit}]")
    ax.set_title(title or f"NRMSE {trace.nrmse:.3g}", fontsize=9)
    ax.legend(loc="upper left", fontsize=7)
    return fig, ax, lines
