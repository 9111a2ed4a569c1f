"""Hysteresis loops under a cyclic imposed displacement (seed Figs. 6-7).

The rig's position follows ``x = A·sin(2πft)`` (imposed velocity ``v = A·2πf·cos(2πft)``,
f = 1 Hz, 3 cycles) in two regimes:

* ``presliding``: ``A = 2 µm``, inside the elastic (pre-sliding) range of the bristle
  models (LuGre ``F_c/sigma0 = 10 µm``);
* ``sliding``: ``A = 1 mm``, gross sliding with slip speeds up to 6.3 mm/s.

The figure shows the force against displacement and against velocity, one panel per
regime.  Metrics per regime, taken over the last cycle:

* ``loop_energy_J``: dissipated energy ``∮F dx = ∫F·v dt`` [J/cycle];
* ``loop_closes``: the force returns to its value one period earlier within 1e-3 of the
  force range (a periodic loop, no drift of the force).
"""

from __future__ import annotations

import math

import numpy as np

from ..core import Sine, SolverOptions
from ..rig import run_rig
from ._base import BenchmarkResult, failure, models_where, resolve_models, velocity_driven

__all__ = ["DEFAULT_MODELS", "REGIMES", "loop_metrics", "run_hysteresis"]

FREQ = 1.0          # Hz
CYCLES = 3
#: regime -> displacement amplitude [m]
REGIMES = {"presliding": 2e-6, "sliding": 1e-3}
OPTIONS = SolverOptions(rtol=1e-8, atol=1e-12, h_max=2e-3, dt_out=1e-3, max_steps=400_000,
                        wall_time=30.0)

DEFAULT_MODELS = ("tanh", "dahl", "lugre", "elastoplastic", "mykhailevych2020")
#: velocity-driven rig: the switching models (stuck = zero force) do not apply
APPLICABLE = models_where(velocity_driven)


def loop_metrics(res, period: float = 1.0 / FREQ) -> dict:
    """Energy of the last cycle and whether the loop closes (see module doc)."""
    t, f, v = res.t, res["F"], res["v"]
    t_end = t[-1]
    last = t >= t_end - period - 1e-12
    energy = float(np.trapezoid(f[last] * v[last], t[last]))
    f_prev = float(np.interp(t_end - period, t, f))
    span = float(np.ptp(f[last])) or 1.0
    return {"loop_energy_J": energy,
            "loop_closes": bool(abs(f[-1] - f_prev) <= 1e-3 * span)}


def run_hysteresis(models=None, *, freq: float = FREQ, cycles: int = CYCLES,
                   regimes=None, solver: str = "rodas4", options=OPTIONS) -> BenchmarkResult:
    """Force-displacement and force-velocity loops in the pre-sliding and sliding regimes.

    Parameters
    ----------
    models : sequence, optional
        Model specs or instances (default :data:`DEFAULT_MODELS`).
    freq : float
        Excitation frequency [Hz].
    cycles : int
        Number of cycles (the metrics use the last).
    regimes : mapping of str to float, optional
        Regime name -> displacement amplitude [m] (default :data:`REGIMES`).
    solver, options
        Integrator and tolerances.

    Returns
    -------
    BenchmarkResult
        metrics ``{model: {regime: {loop_energy_J, loop_closes}}}``; runs
        ``{model: {regime: Result}}``.
    """
    entries = resolve_models(models, DEFAULT_MODELS, APPLICABLE)
    regimes = dict(REGIMES if regimes is None else regimes)
    metrics, runs = {}, {}
    for e in entries:
        runs[e.label], metrics[e.label] = {}, {}
        for regime, amp in regimes.items():
            vel = Sine(amp * 2 * math.pi * freq, freq, phase=math.pi / 2)
            res = run_rig(e.model, cycles / freq, velocity=vel, solver=solver,
                          options=options)
            runs[e.label][regime] = res
            metrics[e.label][regime] = failure(res) or loop_metrics(res, 1.0 / freq)
    protocol = (f"imposed displacement x = A·sin(2πft), f = {freq:g} Hz, {cycles} cycles; "
                + ", ".join(f"{k}: A = {v:g} m" for k, v in regimes.items())
                + "; metrics over the last cycle")
    return BenchmarkResult("hysteresis", protocol, {e.label: e.description for e in entries},
                           metrics, runs, extra={"amplitudes": regimes, "period": 1.0 / freq})
