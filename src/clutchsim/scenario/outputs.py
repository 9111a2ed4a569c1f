"""Write the outputs of scenario runs: time series, summary.json, figures (a launch's, or
any network's: docs/outputs.md)."""

from __future__ import annotations

import json
import logging
import re
from pathlib import Path

from .._util import atomic_write
from ..analysis.network_summary import network_summary

__all__ = ["declared_faults", "file_label", "write_runs"]

log = logging.getLogger("clutchsim")


def declared_faults(scenario, model, result) -> list[dict]:
    """The faults ``scenario`` declares (docs/components.md, faults): component, what fails
    and when it struck in ``result`` (its run with ``model``), for summary.json and the
    report.  ``time_s``: the fault's event in the run; None where a triggered fault never
    struck."""
    out = []
    for c in scenario.network(model).components:
        what = c.fault_description() if hasattr(c, "fault_description") else None
        if what:
            struck = [e.t for e in result.events if e.name.startswith(f"{c.name}: fault")]
            out.append({"component": c.name, "kind": c.kind, "fault": what,
                        "time_s": float(struck[0]) if struck else None})
    return out


def run_parameters(scenario, models, labels) -> dict:
    """Every value the runs' equations read, per component: ``{component: {parameter:
    {"value", "unit", "description"}}}``
    (:meth:`clutchsim.network.Network.parameter_values`).  A component whose values differ
    between the runs (the clutch, compared over friction models) is listed once per run,
    as ``"<component> (<label>)"``."""
    per_run = [scenario.network(m).parameter_values() for m in models]
    out: dict = {}
    for name, first in per_run[0].items():
        if all(pv.get(name) == first for pv in per_run[1:]):
            out[name] = first
        else:
            for label, pv in zip(labels, per_run):
                out[f"{name} ({label})"] = pv[name]
    return out


def write_runs(scenario, models, directory: str | Path, *, plots: bool = True,
               progress=None) -> dict:
    """Run ``scenario`` once per friction model and write the results into ``directory``.

    A launch (:func:`clutchsim.analysis.launch_metrics.is_launch`: a friction clutch with a vehicle or
    an engine) gets ``summary.json`` ``{"kind", "scenario", "file", "models": {MODEL:
    launch metrics}, "parameters"}``, one ``launch_MODEL.png`` per model and, for several models,
    ``comparison.png``.  Any other network gets ``summary.json`` ``{"kind", "scenario",
    "file", "runs": {LABEL: summary}, "parameters"}``
    (:func:`clutchsim.analysis.network_summary.network_summary`; ``parameters``:
    :func:`run_parameters`, every value with its unit)
    and one ``network_LABEL.png`` per run (:func:`clutchsim.plot.network.plot_network`):
    LABEL is the scenario's name for one run, the model's name where several models are
    compared.  Both write ``timeseries[_MODEL].csv`` / ``.parquet`` (units in the column
    names), a copy of the scenario text as ``scenario.toml``, and with ``plots`` the
    figures of gear lash, dual-mass flywheels or torque converters
    (``components_LABEL.png``) and of an actuation chain.  The keys: docs/outputs.md.
    Returns the summary.  ``progress``, if given, is called as ``progress(done, total)``
    after each model.  The caller makes the directory atomic (see
    :meth:`clutchsim._util.OutputDir.build`).
    """
    from .run import analyse_system, default_model, is_launch, simulate_system
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    models = list(models) or [None]
    launch = is_launch(scenario.system(models[0]).metadata["kinds"], scenario.clutch)
    if scenario.compare and not launch:
        scenario.fail(f"= {scenario.compare!r} compares the quality of two launches, but "
                      f"this network is not a launch (its element {scenario.clutch!r} is not "
                      "a friction clutch driving a vehicle or driven by an engine); remove "
                      "the key", "scenario.compare")
    key = "models" if launch else "runs"
    summary: dict = {"kind": "run", "scenario": scenario.name, "file": scenario.file, key: {}}
    # every model simulated, then the figures (they need only the results), then the
    # metrics: a first run's metrics kernel compiles, or is waited for, after the figures
    sims = []
    for i, m in enumerate(models):
        if progress is not None:
            progress(i, len(models))
        log.info("running %s with %s ...", scenario.name, m or "its own model")
        m = default_model(scenario, m)
        system = scenario.system(m)
        label = _label(scenario, system, m, len(models), launch)
        sims.append((label, m, system, simulate_system(scenario, system)))
    if plots:
        _run_figures(scenario, {label: res for label, _, _, res in sims}, directory, launch)
    runs = {}
    for label, m, system, res in sims:
        lr = analyse_system(scenario, system, m, res)
        doc = lr.metrics if launch else network_summary(lr.result)
        runs[label] = lr.result
        summary[key][label] = doc
        suffix = "" if len(models) == 1 else f"_{lr.model}"
        lr.result.to_csv(directory / f"timeseries{suffix}.csv")
        lr.result.to_parquet(directory / f"timeseries{suffix}.parquet")
        log.info("  %s: %s", label, doc["message"])
    if progress is not None:
        progress(len(models), len(models))
    summary["parameters"] = run_parameters(scenario, models, list(runs))
    faults = declared_faults(scenario, models[0], next(iter(runs.values())))
    if faults:
        summary["faults"] = faults
    atomic_write(directory / "summary.json",
                 lambda p: Path(p).write_text(json.dumps(summary, indent=2, allow_nan=False,
                                                         default=float)))
    if getattr(scenario, "text", None):
        atomic_write(directory / "scenario.toml", lambda p: Path(p).write_text(scenario.text))
    if scenario.compare:
        _compare_launch(scenario, runs, summary, directory, plots)
    return summary


def _label(scenario, system, model, n_models: int, launch: bool) -> str:
    """The name of a run in the summary and its figures' files: the clutch's model for a
    launch (:class:`~clutchsim.scenario.run.LaunchResult`'s ``model``), else the scenario's
    name for one run and the model's for several."""
    from .run import model_name
    name = model_name(scenario, system, model)
    if launch:
        return name
    return scenario.name if n_models == 1 else (name or str(model))


def file_label(label: str) -> str:
    """``label`` (a model's or a scenario's name) as a part of a file name: ASCII letters,
    digits, ``.``, ``-`` and ``_`` ("run" if nothing is left)."""
    return re.sub(r"[^A-Za-z0-9._-]+", "_", label).strip("._") or "run"


def _run_figures(scenario, runs, directory, launch: bool) -> None:
    """The figure of each run (``launch_MODEL.png`` or ``network_LABEL.png``), of its gear
    lash, dual-mass flywheels or torque converters, of its actuation chain, and for
    several launches their comparison."""
    from ..plot._style import save_png
    from ..plot.components import plot_components
    from ..plot.launch import plot_comparison, plot_launch
    from ..plot.network import plot_network
    for name, res in runs.items():
        if launch:
            fig, _ = plot_launch(res, clutch=scenario.clutch)
            save_png(fig, directory / f"launch_{name}.png")
        else:
            fig, _ = plot_network(res)
            save_png(fig, directory / f"network_{file_label(name)}.png")
        # lash, dual-mass flywheels, torque converters: their own figure
        if any(s.startswith(("contact_", "T_spring_", "speed_ratio_")) for s in res.signals):
            made = plot_components(res)
            if made is not None:
                save_png(made[0], directory / f"components_{file_label(name)}.png")
    if launch and len(runs) > 1:
        fig, _ = plot_comparison(runs, clutch=scenario.clutch)
        save_png(fig, directory / "comparison.png")
    _actuation_figures(scenario, runs, directory)


def _actuation_figures(scenario, runs, directory) -> None:
    """The static characteristics of the actuation chain (``characteristic.png``) and its
    signals in each run (``actuation_MODEL.png``), for a network with one."""
    from ..analysis.actuation import ACTUATION_KINDS, actuation_signals, static_characteristics
    from ..plot._style import save_png
    from ..plot.actuation import plot_actuation, plot_characteristics
    if not any(c.get("type") in ACTUATION_KINDS for c in scenario.data.get("component", [])):
        return
    chars = static_characteristics(scenario.network(None).components)
    if chars:
        save_png(plot_characteristics(chars)[0], directory / "characteristic.png")
    for name, res in runs.items():
        panels = actuation_signals(res)
        if panels:
            save_png(plot_actuation(res, panels)[0],
                     directory / f"actuation_{file_label(name)}.png")


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
