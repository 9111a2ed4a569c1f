"""Figures of the actuation chain: static characteristics and the chain's signals in a run
(computed by :mod:`clutchsim.analysis.actuation`)."""

from __future__ import annotations

from ._style import new_figure

__all__ = ["plot_actuation", "plot_characteristics"]


def plot_characteristics(chars, *, ax=None):
    """Clamp force against travel or pressure, one panel per characteristic
    (:func:`clutchsim.analysis.actuation.static_characteristics`)."""
    if ax is None:
        fig, ax = new_figure(1, len(chars), figsize=(5.5 * len(chars), 4.0))
        axes = list(ax.ravel())
    else:
        fig, axes = ax.figure, [ax] * len(chars)
    for a, ch in zip(axes, chars):
        for label, x, f in ch.branches:
            a.plot(x, f, label=label)
        a.set_xlabel(ch.x_label)
        a.set_ylabel("clamp force [N]")
        a.set_title(f"{ch.component}: static characteristic", fontsize=10)
        if len(ch.branches) > 1:
            a.legend(loc="best", fontsize=8)
        a.grid(True, alpha=0.3)
    return fig, axes


def plot_actuation(result, panels, *, title: str = ""):
    """The actuation chain's signals of a run, one panel per group
    (:func:`clutchsim.analysis.actuation.actuation_signals`)."""
    fig, ax = new_figure(len(panels), 1, figsize=(9.0, 2.6 * len(panels)), sharex=True)
    axes = list(ax.ravel())
    for a, (what, unit, names) in zip(axes, panels):
        for name in names:
            a.plot(result.t, result[name], label=name)
        a.set_ylabel(f"[{unit}]" if unit else "")
        a.set_title(what, fontsize=10)
        a.legend(loc="best", fontsize=8)
        a.grid(True, alpha=0.3)
    axes[-1].set_xlabel("time [s]")
    fig.suptitle(title or f"{result.system}: actuation chain")
    return fig, axes
