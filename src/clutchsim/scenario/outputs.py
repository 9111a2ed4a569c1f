"""Write the outputs of scenario runs: time series, summary.json, figures."""

from __future__ import annotations

import json
import logging
from pathlib import Path

from .._util import atomic_write

__all__ = ["write_runs"]

log = logging.getLogger("clutchsim")


def write_runs(scenario, models, directory: str | Path, *, plots: bool = True,
               progress=None) -> dict:
    """Run ``scenario`` once per friction model and write the results into ``directory``.

    Writes ``timeseries[_MODEL].csv`` / ``.parquet`` (units in the column names),
    ``summary.json`` (``{"scenario", "file", "models": {MODEL: metrics}}``), a copy of the
    scenario text as ``scenario.toml``, and with ``plots`` one ``launch_MODEL.png`` per model
    (``motion_MODEL.png`` for a translational network: positions, velocities, friction)
    and, for several models, ``comparison.png``; a run with gear lash, a dual-mass flywheel
    or a torque converter also gets ``components_MODEL.png``.  Returns the summary.
    ``progress``, if given, is called as ``progress(done, total)`` after each model.  The caller makes
    the directory atomic (see :meth:`clutchsim._util.OutputDir.build`).
    """
    from .run import run_scenario
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    models = list(models) or [None]
    summary: dict = {"kind": "run", "scenario": scenario.name, "file": scenario.file,
                     "models": {}}
    runs = {}
    for i, m in enumerate(models):
        if progress is not None:
            progress(i, len(models))
        log.info("running %s with %s ...", scenario.name, m or "its own model")
        lr = run_scenario(scenario, m)
        runs[lr.model] = lr.result
        summary["models"][lr.model] = lr.metrics
        suffix = "" if len(models) == 1 else f"_{lr.model}"
        lr.result.to_csv(directory / f"timeseries{suffix}.csv")
        lr.result.to_parquet(directory / f"timeseries{suffix}.parquet")
        log.info("  %s: %s", lr.model, lr.metrics["message"])
    if progress is not None:
        progress(len(models), len(models))
    atomic_write(directory / "summary.json",
                 lambda p: Path(p).write_text(json.dumps(summary, indent=2, allow_nan=False,
                                                         default=float)))
    if getattr(scenario, "text", None):
        atomic_write(directory / "scenario.toml", lambda p: Path(p).write_text(scenario.text))
    if plots:
        from ..plot._style import save_png
        from ..plot.components import plot_components
        from ..plot.launch import plot_comparison, plot_launch
        from ..plot.translational import plot_motion
        for name, res in runs.items():
            if res.metadata.get("domain") == "translational":   # masses: their motion
                fig, _ = plot_motion(res)
                save_png(fig, directory / f"motion_{name}.png")
                continue
            fig, _ = plot_launch(res, clutch=scenario.clutch)
            save_png(fig, directory / f"launch_{name}.png")
            # lash, dual-mass flywheels, torque converters: their own figure
            if any(s.startswith(("contact_", "T_spring_", "speed_ratio_")) for s in res.signals):
                made = plot_components(res)
                if made is not None:
                    save_png(made[0], directory / f"components_{name}.png")
        if len(runs) > 1:
            fig, _ = plot_comparison(runs, clutch=scenario.clutch)
            save_png(fig, directory / "comparison.png")
        _actuation_figures(scenario, runs, directory)
    if scenario.compare:
        _compare_launch(scenario, runs, summary, directory, plots)
    return summary


def _actuation_figures(scenario, runs, directory) -> None:
    """The static characteristics of the actuation chain (``characteristic.png``) and its
    signals in each run (``actuation_MODEL.png``), for a network with one."""
    from ..analysis.actuation import ACTUATION_KINDS, actuation_signals, static_characteristics
    from ..plot._style import save_png
    from ..plot.actuation import plot_actuation, plot_characteristics
    if not any(c.get("type") in ACTUATION_KINDS for c in scenario.data.get("component", [])):
        return
    chars = static_characteristics(scenario.chain(None).components)
    if chars:
        save_png(plot_characteristics(chars)[0], directory / "characteristic.png")
    for name, res in runs.items():
        panels = actuation_signals(res)
        if panels:
            save_png(plot_actuation(res, panels)[0], directory / f"actuation_{name}.png")


def _compare_launch(scenario, runs, summary, directory, plots) -> None:
    """Run the launch of ``[scenario] compare`` too (the same friction model where it has
    it) and write the quality metrics of both, one row per launch
    (``quality_comparison.json``), and their speeds and clutch torques
    (``comparison_launch.png``)."""
    from ..analysis.actuation import compare_quality
    from .loader import load_scenario
    from .run import run_scenario
    other = load_scenario(scenario.compare)
    metrics, results = {}, {}
    for model, res in runs.items():
        own = f"{scenario.name} [{model}]"
        metrics[own], results[own] = summary["models"][model], res
    model = next(iter(runs))
    lr = run_scenario(other, model if model in other.models else None)
    base = f"{other.name} [{lr.model}]"
    metrics[base], results[base] = lr.metrics, lr.result
    doc = {"compared_with": other.file, "launches": compare_quality(metrics)}
    atomic_write(directory / "quality_comparison.json",
                 lambda p: Path(p).write_text(json.dumps(doc, indent=2, allow_nan=False,
                                                         default=float)))
    if plots:
        from ..plot._style import save_png
        from ..plot.launch import plot_comparison
        fig, _ = plot_comparison(results, clutch=scenario.clutch)
        save_png(fig, directory / "comparison_launch.png")
