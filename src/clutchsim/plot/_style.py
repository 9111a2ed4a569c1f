"""Shared figure helpers: a non-interactive backend and atomic PNG writing."""

from __future__ import annotations

from pathlib import Path


def new_figure(nrows=1, ncols=1, *, figsize=(8.0, 5.0), **kw):
    """A figure with no global pyplot state (safe in threads and without a display)."""
    from matplotlib.figure import Figure
    fig = Figure(figsize=figsize, layout="constrained")
    axes = fig.subplots(nrows, ncols, squeeze=False, **kw)
    return fig, axes


def save_png(fig, path: str | Path, *, dpi: int = 130) -> Path:
    """Save a figure as PNG atomically (temporary name, then rename)."""
    from .._util import atomic_write
    return atomic_write(path, lambda p: fig.savefig(p, format="png", dpi=dpi))
