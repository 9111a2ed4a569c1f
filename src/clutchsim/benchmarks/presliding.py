"""Pre-sliding displacement under a slow force cycle below break-away (LuGre paper Fig. 2).

Protocol (friction-models.md T2, after Canudas de Wit et al. 1995): unit mass; the force
ramps at 0.1425 N/s to 1.425 N (95 % of F_s = 1.5 N) over 0-10 s, holds to 15 s, ramps down
to -1.425 N over 15-35 s, holds to 40 s, ramps up to 1.425 N over 40-60 s, holds to 65 s.

Metrics:

* ``x_first_ramp_m``: displacement at the end of the first up-ramp (10 s) [m];
* ``x_end_m``: displacement at 65 s [m];
* ``loop_width_m``: ``x(60 s) - x(35 s)``, the extent of the loop [m];
* ``closure_m``: ``x(60 s) - x(10 s)``, displacement between the two ends of up-ramps at
  the same force [m];
* ``loop_closes``: ``|closure_m| <= 5 %`` of ``loop_width_m`` (creep during the holds is
  the only difference).
"""

from __future__ import annotations

import numpy as np

from ..core import Table
from ..rig import run_rig
from ._base import STIFF_OPTIONS, BenchmarkResult, failure, models_where, resolve_models, sample

__all__ = ["DEFAULT_MODELS", "FORCE", "run_presliding"]

F_MAX = 1.425   # N, 95 % of F_s
#: the force cycle of T2 [s, N]
FORCE = Table(np.array([0.0, 10.0, 15.0, 35.0, 40.0, 60.0, 65.0]),
              np.array([0.0, F_MAX, F_MAX, -F_MAX, -F_MAX, F_MAX, F_MAX]))
T_END = 65.0

DEFAULT_MODELS = ("lugre", "elastoplastic", "mykhailevych2020")
#: models that show pre-sliding displacement by the literature (their declared phenomena)
APPLICABLE = models_where(lambda cls: cls.phenomena["presliding"].expected != "no")


def presliding_metrics(res) -> dict:
    """Displacements at the corners of the force cycle (see module doc)."""
    x10, x35, x60 = sample(res, "x", [10.0, 35.0, 60.0])
    width = float(x60 - x35)
    closure = float(x60 - x10)
    return {"x_first_ramp_m": float(x10), "x_end_m": res.final("x"), "loop_width_m": width,
            "closure_m": closure, "loop_closes": bool(abs(closure) <= 0.05 * abs(width))}


def run_presliding(models=None, *, mass: float = 1.0, solver: str = "rodas4",
                   options=STIFF_OPTIONS) -> BenchmarkResult:
    """Run the pre-sliding force cycle on each model.

    Parameters
    ----------
    models : sequence, optional
        Model specs or instances (default :data:`DEFAULT_MODELS`).
    mass : float
        Mass [kg].
    solver, options
        Integrator and tolerances.

    Returns
    -------
    BenchmarkResult
        metrics ``{model: {x_first_ramp_m, x_end_m, loop_width_m, closure_m,
        loop_closes}}``; runs ``{model: {"presliding": Result}}``.
    """
    entries = resolve_models(models, DEFAULT_MODELS, APPLICABLE)
    metrics, runs = {}, {}
    for e in entries:
        res = run_rig(e.model, T_END, force=FORCE, mass=mass, solver=solver, options=options)
        runs[e.label] = {"presliding": res}
        metrics[e.label] = failure(res) or presliding_metrics(res)
    protocol = (f"mass {mass:g} kg; force 0 -> {F_MAX} N (0-10 s), hold to 15 s, -> -{F_MAX} N "
                f"(15-35 s), hold to 40 s, -> {F_MAX} N (40-60 s), hold to 65 s")
    return BenchmarkResult("presliding", protocol, {e.label: e.description for e in entries},
                           metrics, runs)
