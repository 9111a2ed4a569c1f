"""Frictional lag: force-velocity loops under an oscillating imposed velocity (LuGre Fig. 3).

Protocol (friction-models.md T3): ``v(t) = 1e-3·(cos(ωt) + 1.5)`` m/s for ω = 1, 10 and
25 rad/s; the loop is taken over the last full period after 5 s of transient.  Dynamic
models give less friction on the decreasing than on the increasing branch, and the loop
widens with frequency (Canudas de Wit et al., IEEE TAC 40(3), 1995).

Metric ``loop_width_N``: ``{ω: F_increasing - F_decreasing}`` at ``v = 1.5 mm/s`` [N]
(ω in rad/s as the key).
"""

from __future__ import annotations

import math

import numpy as np

from ..core import Sine, SolverOptions
from ..rig import run_rig
from ._base import BenchmarkResult, failure, models_where, resolve_models, velocity_driven

__all__ = ["DEFAULT_MODELS", "OMEGAS", "loop_width", "run_lag"]

OMEGAS = (1.0, 10.0, 25.0)   # rad/s
V_MEAN, V_AMP = 1.5e-3, 1.0e-3
T_SETTLE = 5.0
OPTIONS = SolverOptions(rtol=1e-8, atol=1e-12, h_max=1e-3, max_steps=400_000,
                        wall_time=30.0)

DEFAULT_MODELS = ("stribeck", "dahl", "lugre", "elastoplastic", "mykhailevych2020")
#: velocity-driven rig
APPLICABLE = models_where(velocity_driven)


def velocity_signal(omega: float):
    """``1e-3·(cos(ωt) + 1.5)`` m/s."""
    return Sine(V_AMP, omega / (2 * math.pi), phase=math.pi / 2, offset=V_MEAN)


def t_end(omega: float) -> float:
    """End of the run: the settling time plus at least one full period [s]."""
    period = 2 * math.pi / omega
    return period * (math.floor(T_SETTLE / period) + 2)


def loop_width(res, omega: float, v_at: float = V_MEAN) -> float:
    """``F`` on the accelerating minus ``F`` on the decelerating branch at ``v_at`` [N],
    over the last period."""
    period = 2 * math.pi / omega
    t, v, f = res.t, res["v"], res["F"]
    last = t >= t[-1] - period - 1e-12
    t, v, f = t[last], v[last], f[last]
    acc = np.gradient(v, t)
    out = {}
    for name, sel in (("inc", acc > 0), ("dec", acc < 0)):
        order = np.argsort(v[sel])
        out[name] = float(np.interp(v_at, v[sel][order], f[sel][order]))
    return out["inc"] - out["dec"]


def run_lag(models=None, *, omegas=OMEGAS, solver: str = "rodas4", options=OPTIONS
            ) -> BenchmarkResult:
    """Force-velocity loops at each excitation frequency.

    Parameters
    ----------
    models : sequence, optional
        Model specs or instances (default :data:`DEFAULT_MODELS`).
    omegas : sequence of float
        Angular frequencies of the velocity oscillation [rad/s].
    solver, options
        Integrator and tolerances.

    Returns
    -------
    BenchmarkResult
        metrics ``{model: {"loop_width_N": {"1": w, "10": w, "25": w}}}``; runs
        ``{model: {"omega=1": Result, ...}}``.
    """
    entries = resolve_models(models, DEFAULT_MODELS, APPLICABLE)
    metrics, runs = {}, {}
    for e in entries:
        runs[e.label], widths, failed = {}, {}, None
        for omega in omegas:
            res = run_rig(e.model, t_end(omega), velocity=velocity_signal(omega),
                          solver=solver, options=options)
            runs[e.label][f"omega={omega:g}"] = res
            failed = failed or failure(res)
            if not failure(res):
                widths[f"{omega:g}"] = loop_width(res, omega)
        metrics[e.label] = failed or {"loop_width_N": widths}
    protocol = ("imposed velocity v = 1e-3·(cos(ωt) + 1.5) m/s, ω = "
                + ", ".join(f"{w:g}" for w in omegas)
                + " rad/s; loop over the last period after 5 s; width at v = 1.5 mm/s")
    return BenchmarkResult("lag", protocol, {e.label: e.description for e in entries},
                           metrics, runs, extra={"omegas": tuple(omegas)})
