"""Friction curves: the seed's Figs. 1-2 and the steady-state (static) curve of each model.

Seed paper (Mykhailevych 2020), model (6): Fig. 1 shows the force against the integrated
slip ``∫v dt`` while ``|v| < omega0`` (the elastic tanh term), Fig. 2 the force against the
slip velocity for ``v >= omega0`` (the Stribeck drop to ``T_din``).  Both are reproduced on
the translational rig under an imposed velocity:

* ``presliding``: ``v = A·2πf·cos(2πft)`` with ``f = 0.1`` Hz and ``∫v dt`` amplitude
  ``A = 2·phi0`` (within the clamp of the reset), 0-10 s;
* ``sliding``: ``v`` ramped from ``omega0`` to ``10·omega0`` over 10 s after 1 s at
  ``omega0``.

Every model also gets its steady-state curve ``F_ss(v)`` on a logarithmic velocity grid,
from which the metrics are taken:

* ``f_static``: ``F_ss`` as ``v -> 0+`` (at 1e-9 m/s) [N];
* ``f_kinetic``: intercept of the high-speed asymptote ``F_ss(v) - v·dF_ss/dv`` at 1 m/s
  [N] (the Coulomb level once Stribeck and viscous terms are separated);
* ``stribeck_min``: ``{"value": F [N], "speed": v [m/s]}`` of an interior minimum of
  ``F_ss``, or None when the curve has none.

For hybrid stick/slip models the static level is held only in stick and is not on the
sliding curve (see the ``breakaway`` benchmark).
"""

from __future__ import annotations

import math

import numpy as np

from ..core import Ramp, Sine
from ..rig import run_rig
from ._base import STIFF_OPTIONS, BenchmarkResult, failure, models_where, resolve_models

__all__ = ["DEFAULT_MODELS", "REFERENCES", "VELOCITY_GRID", "curve_metrics", "run_curves"]

#: slip velocities of the static curves [m/s]
VELOCITY_GRID = np.logspace(-7, 0, 701)
SEED_MODEL = "mykhailevych2020"

DEFAULT_MODELS = ("coulomb-robust", "karnopp", "tanh", "stribeck", "dahl", "lugre",
                  "elastoplastic", "gms", "mykhailevych2020")
APPLICABLE = models_where(lambda cls: True)
#: friction-models.md T1 (exact algebra on LuGre Table I)
REFERENCES = {"lugre": {"f_static": 1.5, "f_kinetic": 1.0,
                        "stribeck_min": {"value": 1.001261, "speed": 2.986e-3}}}


def curve_metrics(model) -> dict:
    """``f_static``, ``f_kinetic`` and ``stribeck_min`` of a model's steady-state curve."""
    v = VELOCITY_GRID
    f = model.steady_state_force(v)
    hi, dv = 1.0, 1e-6
    slope = (model.steady_state_force(hi + dv) - model.steady_state_force(hi - dv)) / (2 * dv)
    f_kin = float(model.steady_state_force(hi) - hi * slope)
    i = int(np.argmin(f))
    minimum = None
    if 0 < i < v.size - 1 and f[i] < min(f[0], f[-1]) - 1e-9 * abs(f[0]):
        # here, not at the top: every command that imports the benchmarks (the demo's drift
        # test) would import scipy.optimize (~300 modules) for this one call
        from scipy.optimize import minimize_scalar
        lo, up = math.log(v[i - 1]), math.log(v[i + 1])
        opt = minimize_scalar(lambda s: float(model.steady_state_force(math.exp(s))),
                              bounds=(lo, up), method="bounded",
                              options={"xatol": 1e-10})
        minimum = {"value": float(opt.fun), "speed": float(math.exp(opt.x))}
    return {"f_static": float(model.steady_state_force(1e-9)), "f_kinetic": f_kin,
            "stribeck_min": minimum}


def run_curves(models=None, *, solver: str = "rodas4", options=STIFF_OPTIONS
               ) -> BenchmarkResult:
    """Static curves of each model and the seed's Figs. 1-2 on model (6).

    Parameters
    ----------
    models : sequence, optional
        Model specs or instances (default :data:`DEFAULT_MODELS`).  The seed's two
        regimes are simulated for every ``mykhailevych2020`` entry.
    solver, options
        Integrator and tolerances of the imposed-velocity runs.

    Returns
    -------
    BenchmarkResult
        metrics ``{model: {f_static, f_kinetic, stribeck_min}}``; runs
        ``{model (6): {"presliding", "sliding"}}``; extra ``{"velocity": grid,
        "static": {model: F_ss}}``.
    """
    entries = resolve_models(models, DEFAULT_MODELS, APPLICABLE)
    metrics, runs, static = {}, {}, {}
    for e in entries:
        static[e.label] = e.model.steady_state_force(VELOCITY_GRID)
        metrics[e.label] = curve_metrics(e.model)
        if e.model.name == SEED_MODEL:
            m = e.model
            f = 0.1
            amp = 2.0 * m.phi0 * (1.0 - 1e-9)
            r1 = run_rig(m, 10.0, velocity=Sine(amp * 2 * math.pi * f, f, phase=math.pi / 2),
                         solver=solver, options=options)
            r2 = run_rig(m, 11.0, velocity=Ramp(1.0, 10.0, 9.0 * m.omega0, m.omega0),
                         solver=solver, options=options)
            runs[e.label] = {"presliding": r1, "sliding": r2}
            if failure(r1, r2):
                metrics[e.label] = {**metrics[e.label], **failure(r1, r2)}
    protocol = ("steady-state curve F_ss(v) of each model on 1e-7..1 m/s; model (6): imposed "
                "velocity, presliding v = 2·phi0·2πf·cos(2πft), f = 0.1 Hz, 0-10 s; sliding "
                "v ramped from omega0 to 10·omega0 over 1-11 s")
    return BenchmarkResult("curves", protocol, {e.label: e.description for e in entries},
                           metrics, runs, extra={"velocity": VELOCITY_GRID, "static": static},
                           references=REFERENCES)
