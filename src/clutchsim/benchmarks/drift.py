"""Drift test: a biased oscillating force below break-away (tests D1 and D2).

Single-state bristle models (Dahl, LuGre) ratchet forward a little in every cycle of
a sub-break-away force with non-zero mean; elasto-plastic models with a true elastic
zone do not (Dupont, Hayward, Armstrong, Altpeter, IEEE TAC 47(5):787-792, 2002).  The
seed paper's Figs. 3-5 (Mykhailevych 2020) show the same test on its model (6), which
is drift-free only with a clamp-type reset of its integrator.

Protocols (unit mass, friction-models.md T6):

* **D1**: ``u = 0.5 + 0.4·sin(2πt)`` N from rest, 0-20 s.
* **D2** (seed-like): 1.6 N for 0-0.5 s (above break-away: the body slides), then
  ``0.5 + 0.4·sin(2π(t - 0.5))`` N to 20 s, then 0 N to 30 s.

Metrics: ``drift_per_cycle_m``, the slope of a least-squares line through ``x`` sampled
once per period over the sinusoidal phase after its first cycle [m/cycle]; for D2 also
``residual_m``, the displacement left at 30 s, 10 s after the force was removed [m].
"""

from __future__ import annotations

import numpy as np

from ..core import Result, Signal, Sine, Step
from ..rig import run_rig
from ._base import STIFF_OPTIONS, BenchmarkResult, failure, models_where, resolve_models, sample

__all__ = [
    "APPLICABLE",
    "D1_FORCE",
    "D2_FORCE",
    "DEFAULT_MODELS",
    "REFERENCES",
    "drift_per_cycle",
    "run_drift",
]

#: D1: u = 0.5 + 0.4·sin(2πt) N, 0-20 s
D1_FORCE: Signal = Sine(0.4, 1.0, offset=0.5)
D1_T_END = 20.0
#: D2: 1.6 N for 0.5 s, biased sine to 20 s, zero to 30 s
D2_FORCE: Signal = (Step(0.0, 1.6) + Step(0.5, -1.1) + Sine(0.4, 1.0, start=0.5)
                    + Step(20.0, -0.5) + Sine(0.4, 1.0, start=20.0))
D2_T_END = 30.0
D2_SINE = (0.5, 20.0)

DEFAULT_MODELS = ("coulomb-robust", "dahl", "lugre", "elastoplastic",
                  "mykhailevych2020", "mykhailevych2020,reset=zero")
APPLICABLE = models_where(lambda cls: True)
#: [C] values of friction-models.md §3 T6 and T11 (independent re-implementation)
REFERENCES = {
    "lugre": {"D1_drift_per_cycle_m": 6.637e-6, "D1_x10_m": 73.439e-6, "D1_x20_m": 139.809e-6},
    "dahl": {"D1_drift_per_cycle_m": 16.661e-6},
    "elastoplastic": {"D1_drift_per_cycle_m": 0.0, "D1_x_m": 4.920e-6},
    "mykhailevych2020": {"D1_drift_per_cycle_m": 0.0},
    "mykhailevych2020,reset=zero": {"D1_drift_per_cycle_m": 490.99e-6},
}


def drift_per_cycle(res: Result, t_start: float, t_stop: float, period: float = 1.0) -> float:
    """Least-squares slope of ``x`` sampled once per period in [t_start, t_stop] [m/cycle].

    The first period after ``t_start`` is skipped (the transient of the first cycle).
    """
    times = np.arange(t_start + period, t_stop + 0.5 * period, period)
    times = times[times <= t_stop + 1e-9]
    if times.size < 3:
        raise ValueError(f"drift: need at least 3 periods in [{t_start}, {t_stop}] s")
    x = sample(res, "x", times)
    return float(np.polyfit(np.arange(times.size), x, 1)[0])


def run_drift(models=None, *, mass: float = 1.0, solver: str = "rodas4",
              options=STIFF_OPTIONS) -> BenchmarkResult:
    """Run the drift tests D1 and D2 on each model.

    Parameters
    ----------
    models : sequence, optional
        Model specs or instances (default :data:`DEFAULT_MODELS`).
    mass : float
        Mass of the rig [kg] (1 kg in the reference protocol).
    solver : str
        Integrator (see :func:`clutchsim.core.simulate`).
    options : SolverOptions
        Tolerances; the default is tight (rtol 1e-8, atol 1e-12 m) because the drift of
        interest is micrometres per cycle.

    Returns
    -------
    BenchmarkResult
        metrics ``{model: {"D1": {"drift_per_cycle_m", "x_end_m"}, "D2":
        {"drift_per_cycle_m", "residual_m"}}}``; runs ``{model: {"D1", "D2"}}``.
    """
    entries = resolve_models(models, DEFAULT_MODELS, APPLICABLE)
    metrics, runs = {}, {}
    for e in entries:
        r1 = run_rig(e.model, D1_T_END, force=D1_FORCE, mass=mass, solver=solver,
                     options=options)
        r2 = run_rig(e.model, D2_T_END, force=D2_FORCE, mass=mass, solver=solver,
                     options=options)
        runs[e.label] = {"D1": r1, "D2": r2}
        metrics[e.label] = failure(r1, r2) or {
            "D1": {"drift_per_cycle_m": drift_per_cycle(r1, 0.0, D1_T_END),
                   "x_end_m": r1.final("x")},
            "D2": {"drift_per_cycle_m": drift_per_cycle(r2, *D2_SINE),
                   "x_sine_end_m": float(sample(r2, "x", [D2_SINE[1]])[0]),
                   "residual_m": r2.final("x")},
        }
    protocol = ("unit-mass rig from rest. D1: u = 0.5 + 0.4·sin(2πt) N for 0-20 s. "
                "D2: 1.6 N for 0-0.5 s, 0.5 + 0.4·sin(2π(t-0.5)) N to 20 s, 0 N to 30 s. "
                "drift_per_cycle_m: slope of x sampled once per period after the first "
                "cycle of the sine; residual_m: x at 30 s")
    return BenchmarkResult("drift", protocol, {e.label: e.description for e in entries},
                           metrics, runs, references=REFERENCES)
