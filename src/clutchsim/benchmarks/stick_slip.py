"""Stick-slip: a mass pulled through a spring whose free end moves at constant speed.

The classic Rabinowicz set-up (Rabinowicz, "Stick and slip", Sci. Am. 194:109, 1956) as
used in the LuGre paper (Canudas de Wit et al., IEEE TAC 40(3):419-425, 1995): unit mass,
spring k = 2 N/m, free end at ``y = 0.1·t`` m, 0-30 s (friction-models.md T5).

Metrics (from the velocity and spring-force traces):

* ``first_slip_s``: first time the velocity exceeds half the pull speed [s];
* ``period_s``: mean interval between successive slip onsets (velocity rising through
  half the pull speed) [s];
* ``force_min_N``, ``force_max_N``: extremes of the spring force over the cycles after
  the first slip [N];
* ``peak_velocity_m_s``: largest velocity [m/s].

A model that never slips reports NaN (``null`` in JSON) for the timing metrics.
"""

from __future__ import annotations

import numpy as np

from ..core import SolverOptions
from ..rig import run_rig
from ._base import (
    BenchmarkResult,
    crossing_times,
    failure,
    force_driven,
    models_where,
    resolve_models,
)

__all__ = [
    "APPLICABLE",
    "DEFAULT_MODELS",
    "REFERENCES",
    "run_stick_slip",
    "stick_slip_metrics",
]

SPRING = 2.0        # N/m
PULL_SPEED = 0.1    # m/s
T_END = 30.0        # s
OPTIONS = SolverOptions(rtol=1e-8, atol=1e-10, h_max=1e-2, max_steps=400_000, wall_time=30.0)

DEFAULT_MODELS = ("coulomb-robust", "lugre", "elastoplastic",
                  "mykhailevych2020")
#: force-driven rig (a spring pulled at a few newtons)
APPLICABLE = models_where(force_driven)
#: [C] friction-models.md T5 (LuGre Table I, independent re-implementation)
REFERENCES = {"lugre": {"period_s": 6.3627, "first_slip_s": 7.540, "force_min_N": 0.7412,
                        "force_max_N": 1.5080, "peak_velocity_m_s": 0.3698}}


def stick_slip_metrics(res, pull_speed: float = PULL_SPEED) -> dict:
    """Slip timing and spring-force extremes of one stick-slip run (see module doc)."""
    t, v, fs = res.t, res["v"], res["F_spring"]
    onsets = crossing_times(t, v, 0.5 * pull_speed, rising=True)
    nan = float("nan")
    if onsets.size == 0:
        return {"first_slip_s": nan, "period_s": nan, "force_min_N": nan,
                "force_max_N": nan, "peak_velocity_m_s": float(v.max())}
    after = t > onsets[0]
    return {
        "first_slip_s": float(onsets[0]),
        "period_s": float(np.mean(np.diff(onsets))) if onsets.size > 1 else nan,
        "force_min_N": float(fs[after].min()) if after.any() else nan,
        "force_max_N": float(fs[after].max()) if after.any() else nan,
        "peak_velocity_m_s": float(v.max()),
    }


def run_stick_slip(models=None, *, spring: float = SPRING, pull_speed: float = PULL_SPEED,
                   t_end: float = T_END, mass: float = 1.0, solver: str = "rodas4",
                   options=OPTIONS) -> BenchmarkResult:
    """Run the stick-slip test on each model.

    Parameters
    ----------
    models : sequence, optional
        Model specs or instances (default :data:`DEFAULT_MODELS`).
    spring : float
        Spring stiffness [N/m].
    pull_speed : float
        Speed of the spring's free end [m/s].
    t_end : float
        Duration [s].
    mass : float
        Mass [kg].
    solver, options
        Integrator and tolerances.

    Returns
    -------
    BenchmarkResult
        metrics ``{model: {first_slip_s, period_s, force_min_N, force_max_N,
        peak_velocity_m_s}}``; runs ``{model: {"stick-slip": Result}}``.
    """
    entries = resolve_models(models, DEFAULT_MODELS, APPLICABLE)
    metrics, runs = {}, {}
    for e in entries:
        res = run_rig(e.model, t_end, force=0.0, spring=spring, pull_speed=pull_speed,
                      mass=mass, solver=solver, options=options)
        metrics[e.label] = failure(res) or stick_slip_metrics(res, pull_speed)
        runs[e.label] = {"stick-slip": res}
    protocol = (f"mass {mass:g} kg pulled through a spring k = {spring:g} N/m whose free end "
                f"moves at {pull_speed:g} m/s, 0-{t_end:g} s; slip onset: velocity rising "
                "through half the pull speed")
    return BenchmarkResult("stick-slip", protocol, {e.label: e.description for e in entries},
                           metrics, runs, references=REFERENCES)
