"""Figure of a judder analysis: the modes in the complex plane and their damping."""

from __future__ import annotations

import math

from ._style import new_figure, save_png

__all__ = ["plot_modes"]


def plot_modes(result, path=None):
    """Two panels of a :class:`~clutchsim.analysis.JudderResult`: eigenvalues (growth rate
    against damped frequency, unstable ones in red) and damping ratio against natural
    frequency of the oscillatory modes.  Saved to ``path`` (PNG) when given; returns
    ``(figure, axes)``."""
    fig, ax = new_figure(1, 2, figsize=(11.0, 4.5))
    a = ax[0, 0]
    for m in result.modes:
        colour = "tab:blue" if m.stable else "tab:red"
        a.plot(m.growth_rate_1_s, abs(m.eigenvalue.imag) / (2.0 * math.pi), "x", color=colour)
    a.axvline(0.0, color="k", lw=0.8)
    a.set_xlabel("growth rate Re λ [1/s]")
    a.set_ylabel("damped frequency |Im λ|/2π [Hz]")
    a.set_title(f"modes at t = {result.point.t_s:g} s ({result.model})")
    a = ax[0, 1]
    osc = [m for m in result.modes if m.frequency_hz > 0.0]
    if osc:
        a.semilogx([m.frequency_hz for m in osc], [m.damping_ratio for m in osc], "o")
        for m in osc:
            a.annotate(m.dominant_states[0] if m.dominant_states else "",
                       (m.frequency_hz, m.damping_ratio), fontsize=7,
                       textcoords="offset points", xytext=(4, 4))
    a.axhline(0.0, color="k", lw=0.8)
    a.set_xlabel("natural frequency [Hz]")
    a.set_ylabel("damping ratio [-]")
    a.set_title("oscillatory modes (below 0: judder)")
    if path is not None:
        save_png(fig, path)
    return fig, ax
