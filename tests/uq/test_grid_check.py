"""Sobol' indices of a real two-input clutch study against a dense-grid variance
decomposition of the same launches (midpoint grid over the two uniform inputs): the grid's
first-order and total indices lie inside the Sobol' study's 95 % intervals."""

from __future__ import annotations

import numpy as np

from clutchsim.studies.sweeps import SweepSpec, sweep
from clutchsim.studies.uq import uq

MASS, GRADE = (1100.0, 1500.0), (0.0, 1.5)      # kg, %: every launch locks up


def test_sobol_agrees_with_a_dense_grid_variance_decomposition():
    n = 14
    mid = (np.arange(n) + 0.5) / n
    grid = sweep(None, SweepSpec({"vehicle.mass": list(MASS[0] + mid * (MASS[1] - MASS[0])),
                                  "vehicle.grade": list(GRADE[0] + mid * (GRADE[1] - GRADE[0]))},
                                 metrics=["lockup_time_s"]))
    y = grid.table.pivot(index="vehicle.mass", columns="vehicle.grade",
                         values="lockup_time_s").to_numpy()
    assert np.isfinite(y).all()
    v = y.var()
    s1 = {"vehicle.mass": y.mean(axis=1).var() / v, "vehicle.grade": y.mean(axis=0).var() / v}
    st = {"vehicle.mass": 1 - s1["vehicle.grade"], "vehicle.grade": 1 - s1["vehicle.mass"]}
    r = uq(None, {"vehicle.mass": f"uniform({MASS[0]},{MASS[1]})",
                  "vehicle.grade": f"uniform({GRADE[0]},{GRADE[1]})"},
           method="sobol", samples=256, seed=3, metrics=["lockup_time_s"])
    for key, first in s1.items():
        got = r.sobol["lockup_time_s"][key]
        lo, hi = got["S1_ci95"]
        assert lo - 0.01 <= first <= hi + 0.01, (key, first, got)
        lo, hi = got["ST_ci95"]
        assert lo - 0.01 <= st[key] <= hi + 0.01, (key, st[key], got)
    # the mass dominates the lock-up time of this launch, the grade adds a little
    assert s1["vehicle.mass"] > 0.85 and 0.02 < s1["vehicle.grade"] < 0.15
