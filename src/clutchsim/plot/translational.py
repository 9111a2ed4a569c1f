"""The figure of a translational run: positions, velocities and friction forces of its
masses (docs/translational.md)."""

from __future__ import annotations

from ._style import new_figure

__all__ = ["motion_panels", "plot_motion"]


def motion_panels(result) -> list[tuple[str, str, list[str]]]:
    """What :func:`plot_motion` draws: ``(title, y label, [signal, ...])`` per panel: the
    positions ``s_<mass>`` [m], the velocities ``v_<mass>`` [m/s] and the friction forces
    ``F_<element>`` [N] (elements with a ``capacity_<element>``)."""
    sig = result.signals
    speeds = [n for n in sig if n.startswith("v_") and not n.startswith("v_slip_")]
    panels = [("positions", "position [m]", [n for n in sig if n.startswith("s_")]),
              ("velocities", "velocity [m/s]", speeds),
              ("friction forces", "force [N]",
               [f"F_{n[9:]}" for n in sig if n.startswith("capacity_") and f"F_{n[9:]}" in sig])]
    return [p for p in panels if p[2]]


def plot_motion(result, *, title: str = ""):
    """One panel per kind of signal of :func:`motion_panels`; returns ``(figure, axes)``."""
    panels = motion_panels(result) or [("velocities", "velocity [m/s]", [])]
    fig, ax = new_figure(len(panels), 1, figsize=(9.0, 2.8 * len(panels) + 0.6), sharex=True)
    for a, (head, ylabel, names) in zip(ax[:, 0], panels):
        for n in names:
            a.plot(result.t, result[n], label=n)
        a.set_title(head)
        a.set_ylabel(ylabel)
        if names:
            a.legend(loc="best", fontsize=8)
        a.grid(True, alpha=0.3)
    ax[-1, 0].set_xlabel("time [s]")
    fig.suptitle(title or f"{result.system} ({result.status})")
    return fig, ax
