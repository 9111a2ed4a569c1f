"""Run a scenario: resolve it, pick the friction model, build the plant and its inputs,
simulate, and compute the warnings and launch metrics
(:func:`clutchsim.analysis.launch_metrics.analyse_run`: one compiled call per run).

Whether a run is a launch is decided in one place,
:func:`clutchsim.analysis.launch_metrics.is_launch` (re-exported here): the outputs of
``clutchsim run`` (launch metrics and figure, or the summary of any network) and the launch
warnings follow it."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..analysis.actuation import controller_warnings, has_controller
from ..analysis.launch_metrics import (
    LAUNCH_DRIVES,
    analyse_run,
    grid_problem,
    is_launch,
    shaft_torque_metrics,
)
from ..core import Result, SolverOptions, simulate
from .loader import resolve_scenario

__all__ = ["LAUNCH_DRIVES", "LaunchResult", "analyse_system", "batch_reason", "default_model",
           "engine_max_speed", "expects_lockup", "is_launch", "lining_geometry", "model_name",
           "run_batch", "run_scenario", "run_system", "shaft_ratio", "simulate_system", "surface_node"]

@dataclass(frozen=True)
class LaunchResult:
    """One run: the core :class:`~clutchsim.core.Result`, the model and its metrics."""

    model: str
    result: Result
    metrics: dict


def run_scenario(scenario=None, model: str | None = None, *, overrides=None,
                 solver: str | None = None, options: SolverOptions | None = None
                 ) -> LaunchResult:
    """Simulate ``scenario`` (default: the packaged launch) with ``model`` on its clutch.

    Parameters
    ----------
    scenario : Scenario, str, Path or None
        A loaded scenario or a path (``None``: the default launch).
    model : str, optional
        Friction model for the element ``scenario.clutch`` (default: the first of
        ``scenario.models``, else the element's own model).
    overrides : sequence of str, optional
        ``key.path=value`` assignments (only with a path or None).
    solver : str, optional
    options : SolverOptions, optional
        Replace the scenario's solver settings.
    """
    scenario = resolve_scenario(scenario, overrides)
    model = default_model(scenario, model)
    system = scenario.system(model)
    return run_system(scenario, system, model, solver=solver, options=options)


def default_model(scenario, model: str | None) -> str | None:
    """``model``, else the first of ``scenario.models`` (None: the element's own model)."""
    if model is None and scenario.models:
        return scenario.models[0]
    return model


def model_name(scenario, system, model: str | None) -> str:
    """The friction model on ``scenario.clutch`` in ``system`` (``model``, or ``""``
    where the system names none): :class:`LaunchResult`'s ``model``."""
    return system.metadata["models"].get(scenario.clutch, model or "")


def run_system(scenario, system, model: str | None = None, *, solver: str | None = None,
               options: SolverOptions | None = None) -> LaunchResult:
    """Simulate ``system`` (built from ``scenario``, possibly with other parameter values)
    with the scenario's inputs, span and solver, and compute the launch metrics
    (:func:`simulate_system`, then :func:`analyse_system`)."""
    res = simulate_system(scenario, system, solver=solver, options=options)
    return analyse_system(scenario, system, model, res)


def simulate_system(scenario, system, *, solver: str | None = None,
                    options: SolverOptions | None = None) -> Result:
    """The result of ``system`` (built from ``scenario``) over the scenario's span, with
    its inputs and solver (or ``solver``, ``options``), before its analysis."""
    inputs = {n: scenario.inputs[n] for n in system.input_names}
    opts = options if options is not None else scenario.options
    _check_grid(scenario, opts)
    return simulate(system, (0.0, scenario.t_end), inputs, solver=solver or scenario.solver,
                    options=opts)


def analyse_system(scenario, system, model: str | None, res: Result) -> LaunchResult:
    """The run ``res`` of ``system`` (:func:`simulate_system`) with its launch metrics and
    warnings, those of its shaft and of its controllers."""
    name = model_name(scenario, system, model)
    res, metrics = analyse_run(res, scenario.clutch,
                               expect_lockup=expects_lockup(scenario, system.metadata["kinds"]),
                               friction=_is_friction_clutch(scenario),
                               lining=lining_geometry(scenario),
                               engine_max_radps=engine_max_speed(scenario),
                               surface_node=surface_node(scenario))
    shaft = scenario.data["scenario"].get("shaft")
    if shaft:
        metrics.update(shaft_torque_metrics(res, scenario.clutch, shaft,
                                            shaft_ratio(scenario, model)))
    extra = controller_warnings(scenario, system, res)
    if extra:
        res = res.with_warnings(*extra)
        metrics["warnings"] = [*metrics["warnings"], *extra]
    return LaunchResult(name, res, metrics)


def batch_reason(scenario, system) -> str:
    """Why the variants of ``system`` (built from ``scenario``) cannot be run as a batch
    (:func:`run_batch`; "" when they can)."""
    if has_controller(system):
        return "a controller's stability check needs each run's result"
    if surface_node(scenario):
        return "the friction-surface temperature is read from each run's result"
    if scenario.data["scenario"].get("shaft"):
        return "the shaft's peak torque is read from each run's result"
    from ..analysis.launch_batch import batch_supported
    why = batch_supported(system, (0.0, scenario.t_end), scenario.clutch)
    if why:
        return why
    if scenario.solver.startswith("scipy-"):
        return f"solver {scenario.solver!r}: a batch of runs needs a compiled method"
    # the batch calls the C engine: the reason a run cannot take it (no engine here, a
    # plant beyond its bounds), the one launch_batch would raise with
    from ..core.simulate import prepare_runs
    return prepare_runs(system, (0.0, scenario.t_end),
                        {n: scenario.inputs[n] for n in system.input_names},
                        solver=scenario.solver, options=scenario.options).why_not()


def run_batch(scenario, system, variants, *, options: SolverOptions | None = None
              ) -> list[tuple[str, dict]]:
    """Run the variants of ``system`` (built from ``scenario``) in one compiled call:
    ``variants`` = ``[(params, y0, event_names or None), ...]``
    (:meth:`clutchsim.scenario.variants.VariantPlan.values`).  Returns ``(status,
    metrics)`` per variant, the status of its result and the metrics
    :func:`run_system` gives for it (:func:`clutchsim.analysis.launch_batch.launch_batch`).
    Raises ValueError when they cannot be batched (:func:`batch_reason`)."""
    why = batch_reason(scenario, system)
    if why:
        raise ValueError(f"{system.name}: cannot run a batch: {why}")
    from ..analysis.launch_batch import launch_batch
    _check_grid(scenario, options if options is not None else scenario.options)
    inputs = {n: scenario.inputs[n] for n in system.input_names}
    return launch_batch(system, (0.0, scenario.t_end), inputs,
                        np.array([v[0] for v in variants]),
                        np.array([v[1] for v in variants]), clutch=scenario.clutch,
                        solver=scenario.solver,
                        options=options if options is not None else scenario.options,
                        expect_lockup=expects_lockup(scenario, system.metadata["kinds"]),
                        friction=_is_friction_clutch(scenario),
                        lining=lining_geometry(scenario),
                        engine_max_radps=engine_max_speed(scenario),
                        event_names=[v[2] for v in variants])


def _check_grid(scenario, options: SolverOptions) -> None:
    """A ValueError when the launch metrics cannot be computed on the output grid of
    ``options`` (:func:`clutchsim.analysis.launch_metrics.grid_problem`; the scenario loader
    refuses such a ``[solver] dt_out`` with its file and line)."""
    why = grid_problem(options.dt_out)
    if why:
        raise ValueError(f"{scenario.name}: {why}")


def shaft_ratio(scenario, model: str | None = None) -> float:
    """The gears' ratio from the output of the scenario's clutch to its ``[scenario] shaft``
    (:meth:`clutchsim.network.network.Assembly.static_ratio`; the loader checked that one
    exists)."""
    net = scenario.network(model)
    clutch, shaft = net.component(scenario.clutch), net.component(
        scenario.data["scenario"]["shaft"])
    return net.compile().asm.static_ratio((clutch.name, clutch.side_b),
                                       (shaft.name, shaft.twist_flanges[0]))


def surface_node(scenario) -> str | None:
    """The friction-surface layer of the scenario's clutch, or None: the first thermal node
    its friction power heats when that node conducts on to another (``link``: a thin
    layer at the friction face over the bulk of its plate, docs/launch-quality.md)."""
    element = next((t for t in (*scenario.data.get("coupling", []),
                                *scenario.data.get("component", []))
                    if isinstance(t, dict) and t.get("name") == scenario.clutch), None)
    heat = element.get("heat") if element else None
    if not heat or not isinstance(heat[0], dict):
        return None
    first = heat[0].get("node")
    nodes = [*scenario.data.get("thermal", []),
             *(c for c in scenario.data.get("component", [])
               if isinstance(c, dict) and c.get("type") == "thermal_node")]
    node = next((n for n in nodes if isinstance(n, dict) and n.get("name") == first), None)
    return first if node is not None and node.get("link") else None


def engine_max_speed(scenario) -> float | None:
    """The last speed of the full-load table of the scenario's engine [rad/s] (where its
    fuel is cut: the overspeed warning's limit), or None without an engine."""
    tables = [scenario.data["engine"]] if isinstance(scenario.data.get("engine"), dict) else []
    tables += [c for c in scenario.data.get("component", [])
               if isinstance(c, dict) and c.get("type") == "engine"]
    speeds = [float(t["full_load"]["speed"][-1]) for t in tables
              if isinstance(t.get("full_load"), dict) and t["full_load"].get("speed")]
    return max(speeds) if speeds else None


def _is_friction_clutch(scenario) -> bool:
    return any(isinstance(t, dict) and t.get("name") == scenario.clutch
               and t.get("type") == "clutch" for t in scenario.data.get("coupling", []))


def lining_geometry(scenario) -> tuple | None:
    """``(r_inner [m], r_outer [m], faces [-])`` of the scenario's clutch, a coupling or a
    network component (its keys ``r_inner``, ``r_outer``, ``faces``, checked by the
    scenario loader), or None when the element has no lining radii."""
    for t in (*scenario.data.get("coupling", []), *scenario.data.get("component", [])):
        if isinstance(t, dict) and t.get("name") == scenario.clutch and "r_outer" in t:
            return float(t["r_inner"]), float(t["r_outer"]), int(t.get("faces", 2))
    return None


def expects_lockup(scenario, kinds) -> bool:
    """Whether ``scenario`` expects its clutch element to lock up: ``[scenario]
    expect_lockup``, by default true when its network (``kinds``: component name -> kind)
    is a launch (:func:`is_launch`) and false for any other (a one-way clutch, a lossy
    gear, a brake, or a friction clutch with neither a vehicle nor an engine)."""
    value = scenario.data.get("scenario", {}).get("expect_lockup")
    if value is not None:
        return bool(value)
    return is_launch(kinds, scenario.clutch)
