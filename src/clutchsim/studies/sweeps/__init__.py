"""Batch sweeps: grids and seeded random samples of a scenario, in-process or on Dask.

>>> from clutchsim import SweepOptions, SweepSpec, sweep
>>> res = sweep(None, {"vehicle.mass": "1100:1500:3"}, out="mass_sweep/")  # doctest: +SKIP
>>> spec = SweepSpec({"vehicle.grade": "uniform(0, 10)"}, samples=50, seed=1)
>>> res = sweep(None, spec, SweepOptions(workers=2))                     # doctest: +SKIP
>>> res.table[["vehicle.mass", "status", "lockup_time_s"]]                   # doctest: +SKIP
"""

from .api import SweepOptions, SweepResult, SweepSpec, sweep
from .design import (
    Grid,
    LogUniform,
    Normal,
    SweepError,
    Uniform,
    Values,
    make_design,
    parse_spec,
    parse_vary,
)
from .runner import DEFAULT_METRICS, METRICS
from .store import read_results

__all__ = [
    "DEFAULT_METRICS",
    "METRICS",
    "Grid",
    "LogUniform",
    "Normal",
    "SweepError",
    "SweepOptions",
    "SweepResult",
    "SweepSpec",
    "Uniform",
    "Values",
    "make_design",
    "parse_spec",
    "parse_vary",
    "read_results",
    "sweep",
]

