"""Figure of a judder analysis: the modes in the complex plane and their damping."""

from __future__ import annotations

import math

from ._style import new_figure, save_png

__all__ = ["plot_frf", "plot_map", "plot_modes"]


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
        from matplotlib.ticker import NullFormatter
        a.xaxis.set_minor_formatter(NullFormatter())   # decade labels only
    a.axhline(0.0, color="k", lw=0.8)
    a.set_xlabel("natural frequency [Hz]")
    a.set_ylabel("damping ratio [-]")
    a.set_title("oscillatory modes (below 0: judder)")
    if path is not None:
        save_png(fig, path)
    return fig, ax


def plot_map(jmap, path=None):
    """A :class:`~clutchsim.analysis.JudderMap`: the judder margin (smallest damping ratio
    of the oscillatory modes) over the grid, unstable points marked, the computed boundary
    (damping ratio 0) and, where the map names a driveline-damping axis, the classic
    boundary ``c + dT/dω = 0``.  Saved to ``path`` (PNG) when given; returns
    ``(figure, axes)``."""
    import numpy as np
    fig, ax = new_figure(1, 1, figsize=(7.5, 5.5))
    a = ax[0, 0]
    z = jmap.damping_ratio
    lim = float(np.nanmax(np.abs(z))) if np.any(np.isfinite(z)) else 1.0
    lim = lim if lim > 0 else 1.0
    X, Y = np.meshgrid(jmap.x, jmap.y)
    if jmap.x.size > 1 and jmap.y.size > 1:
        mesh = a.pcolormesh(X, Y, z, cmap="RdBu", vmin=-lim, vmax=lim, shading="nearest")
        fig.colorbar(mesh, ax=a, label="smallest damping ratio [-]")
        if np.nanmin(z) < 0 < np.nanmax(z):
            a.contour(X, Y, z, levels=[0.0], colors="k", linewidths=1.5)
        if jmap.classic is not None and np.any(np.isfinite(jmap.friction_slope_Nms)):
            c = X if jmap.classic == "x" else Y
            g = c + jmap.friction_slope_Nms
            if np.nanmin(g) < 0 < np.nanmax(g):
                a.contour(X, Y, g, levels=[0.0], colors="tab:red", linestyles="--")
    bad = ~jmap.stable
    a.plot(X[bad], Y[bad], "x", color="tab:red", label="unstable")
    a.plot(X[~bad], Y[~bad], ".", color="tab:blue", label="stable")
    a.set_xlabel(jmap.x_key)
    a.set_ylabel(jmap.y_key)
    title = f"judder margin at t = {jmap.t_s:g} s ({jmap.model}); black: ζ = 0"
    if jmap.classic is not None:
        title += "; red dashed: c + dT/dω = 0"
    a.set_title(title, fontsize=9)
    a.legend(loc="best", fontsize=8)
    if path is not None:
        save_png(fig, path)
    return fig, ax


def plot_frf(fr, path=None):
    """Bode diagram of a :class:`~clutchsim.analysis.FrequencyResponse`: ``|H|`` (log-log,
    the peaks marked) over the phase (unwrapped along the grid, so that it reads as a curve)
    [deg].  Saved to ``path`` (PNG) when given; returns ``(figure, axes)``."""
    import numpy as np
    fig, ax = new_figure(2, 1, figsize=(8.0, 6.5), sharex=True)
    a = ax[0, 0]
    mag = fr.magnitude
    if np.all(mag > 0):
        a.loglog(fr.frequency_hz, mag)
    else:                                   # a zero response somewhere: a linear axis
        a.semilogx(fr.frequency_hz, mag)
    for p in fr.peaks:
        a.plot(p.frequency_hz, p.magnitude, "v", color="tab:red")
        a.annotate(f"{p.frequency_hz:.4g} Hz", (p.frequency_hz, p.magnitude), fontsize=7,
                   textcoords="offset points", xytext=(4, 4))
    a.set_ylabel(f"|{fr.output}/{fr.input}| [{fr.unit}]")
    title = f"frequency response at t = {fr.t_s:g} s ({fr.model})"
    if fr.warnings:
        title += f"; {len(fr.warnings)} warning(s), see the JSON"
    a.set_title(title, fontsize=9)
    a.grid(True, which="both", lw=0.3)
    a = ax[1, 0]
    a.semilogx(fr.frequency_hz, np.degrees(np.unwrap(np.angle(fr.response))))
    a.set_xlabel("frequency [Hz]")
    a.set_ylabel("phase [deg]")
    a.grid(True, which="both", lw=0.3)
    if path is not None:
        save_png(fig, path)
    return fig, ax
