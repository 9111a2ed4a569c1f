"""Coulomb stick/slip against an analytic solution (Code_Aster V5.01.106).

Two masses ``m1 = m2 = 5`` kg joined by ``k = 1e4`` N/m; ``m1`` rubs with normal force
``F_N = 1e4`` N, ``mu_S = 0.3``, ``mu_D = 0.2``.  A force of 3e3 N pushes ``m2`` from
t = 0 and is removed at 0.2 s.  ``m1`` sticks until the spring force reaches
``mu_S·F_N``::

    t1 = arccos(1 - mu_S·F_N/F) / omega0,   omega0 = sqrt(k/m2)   (= 0.035124 s)

then slides and sticks again when its velocity returns to zero (t3 = 0.31492 s,
x1(t3) = 3.9556 m; friction-models.md T9, [C] values).

Metrics: ``stick_time_s`` (break-away event), ``stick_time_error_s`` (against t1),
``restick_time_s`` and ``x1_restick_m``.
"""

from __future__ import annotations

import math

from ..core import SolverOptions, Step, simulate
from ._base import BenchmarkResult, failure, models_where, resolve_models, sample
from .two_mass import make_two_mass

__all__ = ["FORCE", "REFERENCES", "analytic_stick_time", "run_coulomb_analytic"]

M1 = M2 = 5.0            # kg
K = 1.0e4                # N/m
F_N, MU_S, MU_D = 1.0e4, 0.3, 0.2
F_PUSH, T2 = 3.0e3, 0.2  # N, s
T_END = 0.5
#: 3 kN on m2 from t = 0, removed at t2 = 0.2 s
FORCE = Step(T2, -F_PUSH, offset=F_PUSH)
OPTIONS = SolverOptions(rtol=1e-10, atol=1e-12, event_tol=1e-12)

DEFAULT_MODELS = ("coulomb-robust",)
#: the analytic stick and re-stick need a model that truly sticks: a lockable one
APPLICABLE = models_where(lambda cls: cls.lockable)
REFERENCES = {"coulomb-robust": {"stick_time_s": 0.035124, "restick_time_s": 0.31492,
                                 "x1_restick_m": 3.9556}}


def analytic_stick_time(m2: float = M2, k: float = K, force: float = F_PUSH,
                        static: float = MU_S * F_N) -> float:
    """``t1 = arccos(1 - mu_S·F_N/F)/sqrt(k/m2)`` [s]: end of the first adhesion phase."""
    return math.acos(1.0 - static / force) / math.sqrt(k / m2)


def run_coulomb_analytic(models=None, *, solver: str = "rodas4",
                         options=OPTIONS) -> BenchmarkResult:
    """Run the two-mass Coulomb problem and compare the stick time with the analytic t1.

    Parameters
    ----------
    models : sequence, optional
        Only ``"coulomb-robust"`` applies; its levels are set to ``F_c = mu_D·F_N`` and
        ``F_s = mu_S·F_N`` whatever parameter set is named.
    solver, options
        Integrator and tolerances (events located to 1e-12 s by default).

    Returns
    -------
    BenchmarkResult
        metrics ``{model: {stick_time_s, stick_time_analytic_s, stick_time_error_s,
        restick_time_s, x1_restick_m}}``.
    """
    entries = resolve_models(models, DEFAULT_MODELS, APPLICABLE)
    t1 = analytic_stick_time()
    metrics, runs = {}, {}
    for e in entries:
        model = e.model.with_(F_c=MU_D * F_N, F_s=MU_S * F_N)
        system = make_two_mass(model, m1=M1, m2=M2, k=K)
        res = simulate(system, (0.0, T_END), {"force": FORCE}, solver=solver, options=options)
        runs[e.label] = {"two-mass": res}
        if failure(res):
            metrics[e.label] = failure(res)
            continue
        brk = [ev.t for ev in res.events if ev.name.endswith("breakaway")]
        stops = [ev.t for ev in res.events if ev.name.endswith("stop") and ev.t > T2]
        t_stick = brk[0] if brk else float("nan")
        t3 = stops[0] if stops else float("nan")
        metrics[e.label] = {
            "stick_time_s": t_stick, "stick_time_analytic_s": t1,
            "stick_time_error_s": t_stick - t1, "restick_time_s": t3,
            "x1_restick_m": float(sample(res, "x1", [t3])[0]) if stops else float("nan"),
        }
    protocol = (f"two masses {M1:g} kg + {M2:g} kg joined by k = {K:g} N/m; mass 1 on a "
                f"Coulomb contact F_N = {F_N:g} N, mu_S = {MU_S}, mu_D = {MU_D}; "
                f"{F_PUSH:g} N on mass 2 from 0 to {T2} s; from rest, 0-{T_END} s")
    return BenchmarkResult("coulomb-analytic", protocol,
                           {e.label: e.description + f", F_c = {MU_D * F_N:g} N, "
                            f"F_s = {MU_S * F_N:g} N" for e in entries},
                           metrics, runs, references=REFERENCES)
