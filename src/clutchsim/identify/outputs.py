"""Write a fit's outputs: fit.json, traces.csv, report.md and its figures."""

from __future__ import annotations

import json
from pathlib import Path

__all__ = ["report_markdown", "write_outputs"]


def write_outputs(result, out: Path, *, plots: bool = True, unit: str = "") -> dict[str, Path]:
    """fit.json, traces.csv, report.md and (optionally) the two figures in ``out``.

    ``unit`` (the output's, from the data file) labels the output axis of the figures and
    is recorded in fit.json as ``output_unit`` (the interactive report's axes read it).
    """
    import numpy as np

    from .._util import atomic_write
    out.mkdir(parents=True, exist_ok=True)
    files = {}
    doc = {**result.as_dict(), "output_unit": unit}
    files["fit.json"] = atomic_write(out / "fit.json", lambda p: p.write_text(
        json.dumps(doc, indent=2, allow_nan=False)))
    tr = result.fit_trace
    table = np.column_stack([tr.t, tr.measured, tr.simulated, tr.residual])
    files["traces.csv"] = atomic_write(out / "traces.csv", lambda p: np.savetxt(
        p, table, delimiter=",", header="t,measured,simulated,residual", comments=""))
    files["report.md"] = atomic_write(out / "report.md", lambda p: p.write_text(
        report_markdown(result)))
    if plots:
        from ..plot._style import save_png
        from ..plot.fit import plot_fit, plot_residuals
        fig, _, _ = plot_fit(result, unit=unit)
        files["fit.png"] = save_png(fig, out / "fit.png")
        fig, _, _ = plot_residuals(result, unit=unit)
        files["residuals.png"] = save_png(fig, out / "residuals.png")
    return files


def report_markdown(result) -> str:
    """A short Markdown report of a fit."""
    lines = [f"# Fit of {result.model_name} ({result.plant} plant)", "",
             (f"Data: `{result.fit_trace.source}`; input `{result.input}`, output "
              f"`{result.output}` (simulated `{result.signal}`)."), "",
             "| parameter | value | std. error | bounds |", "|---|---|---|---|"]
    for name, value in result.parameters.items():
        lo, hi = result.bounds[name]
        se = result.stderr.get(name)
        flag = " (at bound)" if name in result.at_bound else ""
        shown = "undetermined" if se is None else f"{se:.2g}"
        lines.append(f"| {name} | {value:.6g}{flag} | {shown} | {lo:g} … {hi:g} |")
    lines += ["", "| record | NRMSE | R² | other |", "|---|---|---|---|"]
    fits = list(result.records) or [result.fit_trace]
    rows = [("fit" if len(fits) == 1 else f"fit {k + 1}", tr) for k, tr in enumerate(fits)]
    for what, tr in rows + [(f"validation {k + 1}", v) for k, v in
                            enumerate(result.validation)]:
        other = ", ".join(f"{k} = {v:.4g}" for k, v in tr.metrics.items())
        lines.append(f"| {what}: `{Path(tr.source).name}` | {tr.nrmse:.4g} | {tr.r2:.4g} | "
                     f"{other} |")
    if len(fits) > 1:
        lines.append(f"| pooled (RMS of the fit records' NRMSE) | {result.nrmse_pooled:.4g} | "
                     "| |")
    if result.notes:
        lines += [""] + [f"- {note}" for note in result.notes]
    lines += ["", (f"{result.evaluations} simulations ({result.failed_evaluations} failed), "
                   f"{len(result.starts)} start(s), wall time {result.wall_time:.1f} s; "
                   f"optimiser: {result.message}"), ""]
    return "\n".join(lines)
