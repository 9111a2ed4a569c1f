"""Write a calibration's outputs: calibration.json, parameters.toml, traces.csv, report.md
and the figure."""

from __future__ import annotations

import csv
import io
import json
import math
from pathlib import Path

__all__ = ["calibration_report", "write_calibration_outputs"]

RPM = 30.0 / math.pi


def write_calibration_outputs(result, out: Path, *, plots: bool = True) -> dict[str, Path]:
    """The files of ``clutchsim calibrate`` in ``out`` (each written atomically)."""
    from .._util import atomic_write
    out.mkdir(parents=True, exist_ok=True)
    files = {}
    doc = result.as_dict()
    files["calibration.json"] = atomic_write(out / "calibration.json", lambda p: p.write_text(
        json.dumps(doc, indent=2, allow_nan=False)))
    files["parameters.toml"] = atomic_write(out / "parameters.toml", lambda p: p.write_text(
        result.parameters_toml()))
    files["traces.csv"] = atomic_write(out / "traces.csv", lambda p: p.write_text(
        traces_csv(result)))
    files["report.md"] = atomic_write(out / "report.md", lambda p: p.write_text(
        calibration_report(result)))
    if plots:
        from ..plot._style import save_png
        from ..plot.calibration import plot_calibration
        fig, _ = plot_calibration(result)
        files["calibration.png"] = save_png(fig, out / "calibration.png")
    return files


def traces_csv(result) -> str:
    """Long format: launch, role, signal, t [s], measured, simulated (SI units)."""
    buf = io.StringIO()
    w = csv.writer(buf)
    w.writerow(["launch", "role", "signal", "t [s]", "measured", "simulated"])
    for tr in list(result.launches) + list(result.validation):
        for signal, (t, meas, sim) in tr.signals.items():
            for row in zip(t, meas, sim):
                w.writerow([tr.name, tr.role, signal, *(repr(float(v)) for v in row)])
    return buf.getvalue()


def _fmt(v, spec=".4g"):
    return "–" if v is None or (isinstance(v, float) and not math.isfinite(v)) else format(v, spec)


def calibration_report(result) -> str:
    """A Markdown report: parameters with intervals, correlations, the launches' errors."""
    pct = f"{100 * result.confidence:g} %"
    lines = ["# Launch calibration from vehicle logs", "",
             f"| parameter | value | unit | std. error | {pct} interval | bounds | flag |",
             "|---|---|---|---|---|---|---|"]
    for n in result.names:
        iv = result.intervals[n]
        lo, hi = result.bounds[n]
        flag = ", ".join(f for f, on in (("at bound", n in result.at_bound),
                                          ("not identified", n in result.unidentified)) if on)
        shown = "–" if iv is None else f"[{iv[0]:.6g}, {iv[1]:.6g}]"
        lines.append(f"| {n} | {result.parameters[n]:.6g} | "
                     f"{result.units.get(n, '')} | {_fmt(result.stderr[n], '.3g')} "
                     f"| {shown} | {lo:g} … {hi:g} | {flag} |")
    sc = result.sliding_capacity
    if sc is not None:
        iv = sc["interval"]
        lines += ["", (f"Sliding capacity (the clutch's torque at full clamp load at "
                       f"{sc['speed']:g} rad/s of slip, what a launch measures of its "
                       f"capacity): {sc['value']:.6g} N·m"
                       + ("" if iv is None else f", {pct} [{iv[0]:.6g}, {iv[1]:.6g}] N·m")
                       + ".")]
    if result.keys:
        lines += ["", "Scenario keys: " + ", ".join(f"{n} = `{k}`"
                                                    for n, k in result.keys.items()) + "."]
    lines += ["", "Correlation of the estimates:", "",
              "| | " + " | ".join(result.names) + " |",
              "|---|" + "---|" * len(result.names)]
    for i, n in enumerate(result.names):
        lines.append(f"| {n} | " + " | ".join(f"{c:+.2f}" for c in result.correlation[i]) + " |")
    lines += ["", ("| launch | role | engine RMS [rpm] | slip end error [ms] | peak jerk "
                   "measured / simulated [m/s³] |"), "|---|---|---|---|---|"]
    for tr in list(result.launches) + list(result.validation):
        m = tr.metrics
        lines.append(f"| `{tr.name}` | {tr.role} | {_fmt(m.get('engine_rms_rpm'))} | "
                     f"{_fmt(m.get('slip_end_error_ms'), '.3g')} | "
                     f"{_fmt(m.get('peak_jerk_measured'))} / {_fmt(m.get('peak_jerk_simulated'))} |")
    lines += ["", "Noise level per signal (RMS residual, SI): " + ", ".join(
        f"{k} {v:.3g}" for k, v in result.sigma.items()), ""]
    lines += [f"- {w}" for w in result.warnings] + [f"- {n}" for n in result.notes]
    lines += ["", (f"{result.evaluations} launch simulations, wall time "
                   f"{result.wall_time:.1f} s; optimiser: {result.message}"), ""]
    return "\n".join(lines)
