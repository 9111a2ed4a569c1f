"""Figures of a driveline run: speeds, clutch torque, slip, temperature, vehicle motion."""

from __future__ import annotations

import math

from ._style import new_figure

__all__ = ["plot_comparison", "plot_launch"]

_RPM = 30.0 / math.pi


#: the disc dashed: after lock-up it runs at the engine's speed and would hide its line
_LINE = {"omega_disc": "--"}


def plot_launch(result, *, clutch: str = "clutch", title: str = "", **kw):
    """Six panels of one run; returns ``(figure, axes)``.  Unknown keywords raise."""
    if kw:
        raise TypeError(f"plot_launch: unknown keyword(s) {', '.join(kw)}")
    fig, ax = new_figure(3, 2, figsize=(11.0, 9.0), sharex=True)
    t = result.t
    a = ax[0, 0]
    for name in result.signals:
        if name.startswith("omega_") and name in ("omega_engine", "omega_disc", "omega_wheels"):
            a.plot(t, result[name] * _RPM, _LINE.get(name, "-"), label=name[6:])
    a.set_ylabel("speed [rpm]")
    a.legend(loc="best", fontsize=8)
    a.set_title("engine, disc and wheel speeds")
    a = ax[0, 1]
    if f"T_{clutch}" in result.signals:
        # the plant reports the torque with Modelica's sign (on the driven flange); drawn
        # here as the torque the engine side transmits to the disc, against the capacity
        a.plot(t, -result[f"T_{clutch}"], label="clutch torque, engine → disc")
        a.plot(t, result[f"capacity_{clutch}"], "--", label="capacity (static)")
    if "T_engine" in result.signals:
        a.plot(t, result["T_engine"], ":", label="engine torque")
    a.set_ylabel("torque [N·m]")
    a.legend(loc="best", fontsize=8)
    a.set_title("clutch torque and capacity")
    a = ax[1, 0]
    if f"w_slip_{clutch}" in result.signals:
        a.plot(t, result[f"w_slip_{clutch}"] * _RPM)
    a.set_ylabel("slip speed [rpm]")
    a.set_title("clutch slip (disc − engine)")
    a = ax[1, 1]
    for name in result.signals:
        if name.startswith("theta_"):
            a.plot(t, result[name], label=name[6:])
    a.set_ylabel("temperature [°C]")
    if a.get_legend_handles_labels()[0]:       # a network without thermal nodes has none
        a.legend(loc="best", fontsize=8)
    a.set_title("lining (pressure plate) and flywheel temperature")
    for a, sig, lab in ((ax[2, 0], "v_vehicle", "vehicle speed [km/h]"),
                        (ax[2, 1], "a_vehicle", "acceleration [m/s²]")):
        if sig in result.signals:
            a.plot(t, result[sig] * (3.6 if sig == "v_vehicle" else 1.0))
        a.set_ylabel(lab)
        a.set_xlabel("time [s]")
    for a in ax.ravel():
        a.grid(True, alpha=0.3)
    fig.suptitle(title or f"{result.system}: {result.metadata.get('models', {}).get(clutch, '')}"
                 f" ({result.status})")
    return fig, ax


def plot_comparison(runs: dict, *, clutch: str = "clutch", **kw):
    """Engine and disc speeds and clutch torque of several models (seed Figs 9-10)."""
    if kw:
        raise TypeError(f"plot_comparison: unknown keyword(s) {', '.join(kw)}")
    fig, ax = new_figure(len(runs), 2, figsize=(11.0, 3.2 * len(runs)), sharex=True)
    for i, (model, res) in enumerate(runs.items()):
        t = res.t
        a = ax[i, 0]
        for name in ("omega_engine", "omega_disc"):
            if name in res.signals:
                a.plot(t, res[name] * _RPM, _LINE.get(name, "-"), label=name[6:])
        a.set_ylabel("speed [rpm]")
        end = "" if res.status == "completed" else f" — {res.status} at t = {t[-1]:.3f} s"
        a.set_title(f"{model}: speeds{end}", fontsize=10)
        a.legend(loc="best", fontsize=8)
        a = ax[i, 1]
        if f"T_{clutch}" in res.signals:
            a.plot(t, -res[f"T_{clutch}"], label="clutch torque, engine → disc")
            a.plot(t, res[f"capacity_{clutch}"], "--", label="capacity")
        a.set_ylabel("torque [N·m]")
        a.set_title(f"{model}: clutch torque", fontsize=10)
        a.legend(loc="best", fontsize=8)
        if res.status != "completed":
            for a in ax[i]:
                a.axvline(t[-1], color="red", lw=0.8, ls="--")
    for a in ax.ravel():
        a.grid(True, alpha=0.3)
    for a in ax[-1]:
        a.set_xlabel("time [s]")
    return fig, ax
