"""Figures of the friction benchmarks: one figure per benchmark, one panel per regime.

Computing is done by :mod:`clutchsim.benchmarks`; these functions only draw a
:class:`~clutchsim.benchmarks.BenchmarkResult`.  Every legend entry names the model and
its parameter set; every axis carries its unit.  No pyplot global state is used.
"""

from __future__ import annotations

import math

import numpy as np

from ._style import new_figure

__all__ = ["PLOTTERS", "plot_benchmark"]


def _ok(result, label, run):
    res = result.runs.get(label, {}).get(run)
    return res if res is not None and res.status != "failed" else None


def _runs(result, run):
    """``(label, description, Result)`` of each model whose run ``run`` did not fail."""
    for label, desc in result.models.items():
        res = _ok(result, label, run)
        if res is not None:
            yield label, desc, res


def _legend(ax, **kw):
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize="small", **kw)


def _finish(axes, **kw):
    """A grid on each of ``axes`` and its legend (``kw``: the legend's options)."""
    for ax in axes:
        ax.grid(alpha=0.3)
        _legend(ax, **kw)


def plot_curves(result, fig_axes=None):
    fig, axes = fig_axes or new_figure(1, 3, figsize=(15.0, 4.8))
    a, b, c = axes[0]
    for label, desc in result.models.items():
        pre, sl = _ok(result, label, "presliding"), _ok(result, label, "sliding")
        if pre is not None:
            a.plot(pre["phi"] * 1e6, pre["F"], label=desc)
        if sl is not None:
            late = sl.t >= 1.0   # after the start-up from rest at v = omega0
            b.plot(sl["v"][late] * 1e3, sl["F"][late], label=desc)
    a.set(title="(a) model (6), |v| < ω0: force vs ∫v dt (seed Fig. 1)",
          xlabel="∫v dt (state phi) [µm]", ylabel="friction force F [N]")
    b.set(title="(b) model (6), v ≥ ω0: force vs slip velocity (seed Fig. 2)",
          xlabel="slip velocity v [mm/s]", ylabel="friction force F [N]")
    v = np.asarray(result.extra["velocity"])
    for label, desc in result.models.items():
        c.plot(v, result.extra["static"][label], label=desc)
    c.set_xscale("log")
    c.set_ylim(0.0, 2.0)
    c.set(title="(c) steady-state (static) curves F_ss(v)", xlabel="slip velocity v [m/s]",
          ylabel="steady sliding force F_ss [N]")
    _finish((a, b, c))
    if not a.lines:
        a.text(0.5, 0.5, "no mykhailevych2020 model selected", ha="center",
               transform=a.transAxes)
    return fig, axes


def plot_drift(result, fig_axes=None):
    fig, axes = fig_axes or new_figure(1, 2, figsize=(14.0, 5.0))
    for ax, run, title in ((axes[0][0], "D1", "D1: u = 0.5 + 0.4·sin(2πt) N"),
                           (axes[0][1], "D2", ("D2: 1.6 N for 0.5 s, biased sine to 20 s, "
                                               "then 0 N"))):
        for label, desc, res in _runs(result, run):
            m = result.metrics[label][run]
            ax.plot(res.t, res["x"] * 1e6,
                    label=f"{desc}: {m['drift_per_cycle_m'] * 1e6:.3g} µm/cycle")
        ax.set_yscale("symlog", linthresh=1.0)
        ax.set(title=title, xlabel="time t [s]",
               ylabel="displacement x [µm] (linear below 1 µm, log above)")
        _finish((ax,), loc="upper left" if run == "D1" else "center right")
    return fig, axes


def plot_hysteresis(result, fig_axes=None):
    regimes = list(result.extra["amplitudes"])
    fig, axes = fig_axes or new_figure(len(regimes), 2, figsize=(13.0, 4.6 * len(regimes)))
    for i, regime in enumerate(regimes):
        amp = result.extra["amplitudes"][regime]
        xs, xu = (1e6, "µm") if amp < 1e-4 else (1e3, "mm")
        ax_x, ax_v = axes[i]
        for label, desc, res in _runs(result, regime):
            e = result.metrics[label][regime]["loop_energy_J"]
            last = res.t >= res.t[-1] - result.extra["period"] - 1e-12   # last cycle only
            ax_x.plot(res["x"][last] * xs, res["F"][last], label=f"{desc}: {e:.3g} J/cycle")
            ax_v.plot(res["v"][last] * 1e3, res["F"][last], label=desc)
        ax_x.set(title=f"{regime}: force vs displacement (x amplitude {amp * xs:g} {xu})",
                 xlabel=f"displacement x [{xu}]", ylabel="friction force F [N]")
        ax_v.set(title=f"{regime}: force vs velocity", xlabel="velocity v [mm/s]",
                 ylabel="friction force F [N]")
        _finish((ax_x, ax_v))
    return fig, axes


def plot_presliding(result, fig_axes=None):
    fig, axes = fig_axes or new_figure(1, 2, figsize=(13.0, 5.0))
    a, b = axes[0]
    for _, desc, res in _runs(result, "presliding"):
        a.plot(res["x"] * 1e6, res["F_ext"], label=desc)
        b.plot(res.t, res["x"] * 1e6, label=desc)
    a.set(title="applied force vs pre-sliding displacement", xlabel="displacement x [µm]",
          ylabel="applied force u [N]")
    b.set(title="displacement during the force cycle", xlabel="time t [s]",
          ylabel="displacement x [µm]")
    _finish((a, b))
    return fig, axes


def plot_lag(result, fig_axes=None):
    omegas = result.extra["omegas"]
    fig, axes = fig_axes or new_figure(1, len(omegas), figsize=(5.0 * len(omegas), 4.8),
                                       sharey=True)
    for ax, omega in zip(axes[0], omegas):
        period = 2 * math.pi / omega
        for _, desc, res in _runs(result, f"omega={omega:g}"):
            last = res.t >= res.t[-1] - period - 1e-12
            ax.plot(res["v"][last] * 1e3, res["F"][last], label=desc)
        ax.set(title=f"ω = {omega:g} rad/s", xlabel="velocity v [mm/s]")
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel("friction force F [N]")
    _legend(axes[0][0])
    return fig, axes


def plot_breakaway(result, fig_axes=None):
    fig, axes = fig_axes or new_figure(1, 2, figsize=(13.0, 5.0))
    a, b = axes[0]
    rates = result.extra["rates"]
    for label, desc in result.models.items():
        m = result.metrics[label]
        if "breakaway" in m:
            pairs = np.array(m["breakaway"], dtype=float)
            a.plot(pairs[:, 0], pairs[:, 1], "o-", label=desc)
        for rate in (rates[0], rates[-1]):
            res = _ok(result, label, f"r={rate:g}")
            if res is not None:
                b.plot(res["F_ext"], res["F"], label=f"{desc}, {rate:g} N/s")
    a.set_xscale("log")
    a.set(title="break-away force (first maximum of F) vs force rate",
          xlabel="force rate r [N/s]", ylabel="break-away force [N]")
    b.set(title="friction force during the ramp", xlabel="applied force u = r·t [N]",
          ylabel="friction force F [N]")
    _finish((a, b))
    return fig, axes


def plot_stick_slip(result, fig_axes=None):
    fig, axes = fig_axes or new_figure(2, 1, figsize=(12.0, 7.5), sharex=True)
    a, b = axes[0][0], axes[1][0]
    for _, desc, res in _runs(result, "stick-slip"):
        a.plot(res.t, res["F_spring"], label=desc)
        b.plot(res.t, res["v"], label=desc)
    a.set(title="spring force (stick: rising, slip: falling)", ylabel="spring force [N]")
    b.set(title="velocity of the mass", xlabel="time t [s]", ylabel="velocity v [m/s]")
    _finish((a, b), loc="upper left")
    return fig, axes


def plot_coulomb_analytic(result, fig_axes=None):
    fig, axes = fig_axes or new_figure(1, 2, figsize=(13.0, 5.0))
    a, b = axes[0]
    for _, desc, res in _runs(result, "two-mass"):
        a.plot(res.t, res["x1"], label=f"x1 (mass with friction), {desc}")
        a.plot(res.t, res["x2"], "--", label=f"x2 (pushed mass), {desc}")
        b.plot(res.t, res["F"], label=f"friction force, {desc}")
        b.plot(res.t, res["F_spring"], "--", label=f"spring force, {desc}")
    t1 = result.metrics[next(iter(result.models))].get("stick_time_analytic_s")
    if t1 is not None:
        for ax in (a, b):
            ax.axvline(t1, color="k", lw=0.8, ls=":", label=f"analytic t1 = {t1:.6f} s")
    _finish((a, b))
    a.set(title="positions", xlabel="time t [s]", ylabel="position [m]")
    b.set(title="forces on mass 1", xlabel="time t [s]", ylabel="force [N]")
    return fig, axes


#: benchmark name -> plotting function ``(result, fig_axes=None) -> (fig, axes)``
PLOTTERS = {
    "curves": plot_curves, "drift": plot_drift, "hysteresis": plot_hysteresis,
    "presliding": plot_presliding, "lag": plot_lag, "breakaway": plot_breakaway,
    "stick-slip": plot_stick_slip, "coulomb-analytic": plot_coulomb_analytic,
}


def plot_benchmark(result):
    """The figure of a :class:`~clutchsim.benchmarks.BenchmarkResult`.

    Returns
    -------
    (Figure, ndarray of Axes)
    """
    try:
        plotter = PLOTTERS[result.benchmark]
    except KeyError:
        raise ValueError(f"no figure for benchmark {result.benchmark!r}; known: "
                         f"{', '.join(PLOTTERS)}") from None
    fig, axes = plotter(result)
    fig.suptitle(f"clutchsim benchmark '{result.benchmark}': {result.protocol}",
                 fontsize="small", wrap=True)
    return fig, axes
