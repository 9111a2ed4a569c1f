"""Varying break-away force: a force ramp ``u = r·t`` at several rates (LuGre Fig. 4).

Protocol (friction-models.md T4): unit mass from rest, ``u = r·t`` N for rates r = 1, 2, 5,
10, 20, 50 N/s, until ``u`` reaches 3 N.  The break-away force is the first local maximum
of the friction force ``F`` (the first drop of ``F``).

Metric ``breakaway``: ``[[rate N/s, break-away force N], ...]``; the force is NaN (JSON
null) when ``F`` has no local maximum (e.g. Dahl, which rises monotonically to ``F_c``).
"""

from __future__ import annotations

import numpy as np

from ..core import Ramp
from ..rig import run_rig
from ._base import (
    STIFF_OPTIONS,
    BenchmarkResult,
    failure,
    force_driven,
    models_where,
    resolve_models,
)

__all__ = ["DEFAULT_MODELS", "RATES", "breakaway_force", "run_breakaway"]

RATES = (1.0, 2.0, 5.0, 10.0, 20.0, 50.0)   # N/s
U_END = 3.0   # N

DEFAULT_MODELS = ("coulomb-robust", "lugre", "elastoplastic", "mykhailevych2020")
#: force-driven rig (a ramp to a few newtons)
APPLICABLE = models_where(force_driven)


def breakaway_force(res) -> float:
    """The first local maximum of ``F`` [N] (NaN if there is none)."""
    f = res["F"]
    drops = np.flatnonzero((f[1:-1] >= f[:-2]) & (f[1:-1] > f[2:]))
    return float(f[drops[0] + 1]) if drops.size else float("nan")


def run_breakaway(models=None, *, rates=RATES, mass: float = 1.0, solver: str = "rodas4",
                  options=STIFF_OPTIONS) -> BenchmarkResult:
    """Break-away force of each model at each force rate.

    Parameters
    ----------
    models : sequence, optional
        Model specs or instances (default :data:`DEFAULT_MODELS`).
    rates : sequence of float
        Force rates r [N/s].
    mass : float
        Mass [kg].
    solver, options
        Integrator and tolerances.

    Returns
    -------
    BenchmarkResult
        metrics ``{model: {"breakaway": [[rate, force], ...]}}``; runs
        ``{model: {"r=1": Result, ...}}``.
    """
    entries = resolve_models(models, DEFAULT_MODELS, APPLICABLE)
    metrics, runs = {}, {}
    for e in entries:
        runs[e.label], pairs, failed = {}, [], None
        for rate in rates:
            t_end = U_END / rate
            res = run_rig(e.model, t_end, force=Ramp(0.0, t_end, U_END), mass=mass,
                          solver=solver, options=options)
            runs[e.label][f"r={rate:g}"] = res
            failed = failed or failure(res)
            if not failure(res):
                pairs.append([rate, breakaway_force(res)])
        metrics[e.label] = failed or {"breakaway": pairs}
    protocol = (f"mass {mass:g} kg from rest; force u = r·t up to {U_END:g} N, r = "
                + ", ".join(f"{r:g}" for r in rates)
                + " N/s; break-away force = first local maximum of F")
    return BenchmarkResult("breakaway", protocol, {e.label: e.description for e in entries},
                           metrics, runs, extra={"rates": tuple(rates)})
