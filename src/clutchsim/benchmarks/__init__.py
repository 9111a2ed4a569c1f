"""Friction benchmarks: a protocol (input signals applied to a test rig) plus metrics.

Each benchmark is a public function ``run_<name>(models=None, **protocol_options)``
returning an immutable :class:`BenchmarkResult`; :data:`BENCHMARKS` lists them by their
command-line name and :func:`run_benchmark` runs one by name.  Figures are drawn
separately by :mod:`clutchsim.plot.benchmarks`.

============== ================================================================
name           protocol (friction-models.md §3)
============== ================================================================
curves         steady-state curves; seed Figs. 1-2 on model (6)
drift          D1 and D2: biased sine below break-away (seed Figs. 3-5, T6)
hysteresis     imposed displacement cycles, pre-sliding and sliding (seed Figs. 6-7)
presliding     slow force cycle to 95 % of F_s (T2)
lag            oscillating imposed velocity at 1, 10, 25 rad/s (T3)
breakaway      force ramps at 1-50 N/s (T4)
stick-slip     spring pulled at constant speed (T5)
coulomb-analytic two-mass Coulomb problem with an analytic stick time (T9)
============== ================================================================

:mod:`clutchsim.benchmarks.phenomena` runs several of them on a model and classifies the
metrics into the classic friction phenomena (stiction, Stribeck effect, ...).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from ..core.system import closest
from . import (
    breakaway,
    coulomb_analytic,
    curves,
    drift,
    hysteresis,
    lag,
    phenomena,
    presliding,
    stick_slip,
)
from ._base import BenchmarkResult, ModelEntry, entry_from_spec, resolve_models
from .breakaway import run_breakaway
from .coulomb_analytic import run_coulomb_analytic
from .curves import run_curves
from .drift import run_drift
from .hysteresis import run_hysteresis
from .lag import run_lag
from .outputs import traces_frame, write_outputs
from .presliding import run_presliding
from .stick_slip import run_stick_slip

__all__ = [
    "BENCHMARKS",
    "Benchmark",
    "BenchmarkResult",
    "ModelEntry",
    "entry_from_spec",
    "get_benchmark",
    "phenomena",
    "resolve_models",
    "run_benchmark",
    "run_breakaway",
    "run_coulomb_analytic",
    "run_curves",
    "run_drift",
    "run_hysteresis",
    "run_lag",
    "run_presliding",
    "run_stick_slip",
    "traces_frame",
    "write_outputs",
]


@dataclass(frozen=True)
class Benchmark:
    """A registered benchmark: its function, default and applicable models, summary."""

    name: str
    run: Callable[..., BenchmarkResult]
    default_models: tuple[str, ...]
    applicable: tuple[str, ...]
    summary: str


def _b(name, module, fn, summary):
    return Benchmark(name, fn, tuple(module.DEFAULT_MODELS), tuple(module.APPLICABLE), summary)


#: benchmark name -> :class:`Benchmark`
BENCHMARKS: dict[str, Benchmark] = {b.name: b for b in (
    _b("curves", curves, run_curves, "steady-state curves; seed Figs. 1-2 (model (6))"),
    _b("drift", drift, run_drift, "drift tests D1 and D2 (biased sine below break-away)"),
    _b("hysteresis", hysteresis, run_hysteresis,
       "force-displacement/velocity loops, pre-sliding and sliding"),
    _b("presliding", presliding, run_presliding, "slow force cycle to 95 % of F_s (T2)"),
    _b("lag", lag, run_lag, "frictional lag at 1, 10, 25 rad/s (T3)"),
    _b("breakaway", breakaway, run_breakaway, "break-away force vs force rate (T4)"),
    _b("stick-slip", stick_slip, run_stick_slip, "spring pulled at constant speed (T5)"),
    _b("coulomb-analytic", coulomb_analytic, run_coulomb_analytic,
       "two-mass Coulomb problem, analytic stick time (T9)"),
)}


def get_benchmark(name: str) -> Benchmark:
    """The benchmark registered as ``name``; ValueError lists the valid names."""
    if name not in BENCHMARKS:
        raise ValueError(f"unknown benchmark {name!r}{closest(name, BENCHMARKS)}; valid "
                         f"benchmarks: {', '.join(BENCHMARKS)}")
    return BENCHMARKS[name]


def run_benchmark(name: str, models=None, **protocol_options) -> BenchmarkResult:
    """Run the benchmark ``name`` (see :data:`BENCHMARKS`) on ``models``.

    Parameters
    ----------
    name : str
        Benchmark name, e.g. ``"drift"``.
    models : sequence, optional
        Model specs (``NAME[:PARAMETER_SET][,key=value...]``) or instances; default the
        benchmark's default models.
    **protocol_options
        Passed to the benchmark function (e.g. ``solver=``, ``options=``).
    """
    return get_benchmark(name).run(models, **protocol_options)
