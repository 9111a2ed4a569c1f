"""Figure of a calibration from vehicle logs: measured against simulated speeds per launch."""

from __future__ import annotations

import math

from ._style import new_figure

__all__ = ["plot_calibration"]

RPM = 30.0 / math.pi
#: signal -> (panel, label, factor to the plotted unit, colour)
_SHOWN = {"engine_speed": (0, "engine", RPM, "C0"), "input_speed": (0, "gearbox input", RPM, "C1"),
          "wheel_speed": (1, "wheel [rad/s]", 1.0, "C2"),
          "vehicle_speed": (1, "vehicle [km/h]", 3.6, "C2")}


def plot_calibration(result, *, figsize=None):
    """One row per launch (fitted, then validation): engine and gearbox input speed [rpm]
    on the left, vehicle speed on the right; measured as dots at their own stamps,
    simulated as lines through the same stamps.

    Returns
    -------
    (Figure, ndarray of Axes)
    """
    traces = list(result.launches) + list(result.validation)
    fig, axes = new_figure(len(traces), 2, figsize=figsize or (10.0, 2.6 * len(traces) + 0.6))
    for row, tr in zip(axes, traces):
        for signal, (t, measured, simulated) in tr.signals.items():
            panel, label, factor, colour = _SHOWN[signal]
            ax = row[panel]
            ax.plot(t, measured * factor, ".", ms=2.5, color=colour, alpha=0.6,
                    label=f"{label} measured")
            ax.plot(t, simulated * factor, "-", lw=0.9, color=colour, label=f"{label} model")
        rms = tr.metrics.get("engine_rms_rpm")
        row[0].set_title(f"{tr.role}: {tr.name}  (engine RMS {rms:.3g} rpm)", fontsize=9)
        row[0].set_ylabel("speed [rpm]")
        row[1].set_ylabel("vehicle speed [km/h]")
        for ax in row:
            ax.legend(loc="lower right", fontsize=7)
    for ax in axes[-1]:
        ax.set_xlabel("time [s]")
    return fig, axes
