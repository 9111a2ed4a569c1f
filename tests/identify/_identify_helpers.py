"""Helpers of the identification tests: synthetic records and the shared data sets."""

from __future__ import annotations

import numpy as np
import pytest

from clutchsim.core import SolverOptions, Table, simulate
from clutchsim.data import Measurement, shared_dir
from clutchsim.rig import make_rig

SHARED = shared_dir()


def shared_file(*parts: str):
    """Path of a shared data file, or skip the test with the reason."""
    path = SHARED.joinpath(*parts)
    if not path.is_file():
        pytest.skip(f"shared data not available: {path} (set CLUTCHSIM_SHARED to the shared "
                    "directory)")
    return path


def synthetic_velocity_record(model, t, v, *, noise=0.0, seed=0, scale=1.0) -> Measurement:
    """Friction force of ``model`` under the imposed velocity ``v(t)``, plus white noise."""
    system = make_rig(model, drive="velocity")
    res = simulate(system, (t[0], t[-1]), {"v": Table(t, v, hit_knots=False), "scale": scale},
                   options=SolverOptions(rtol=1e-10, atol=1e-13, dt_out=float(t[1] - t[0])))
    assert res.status == "completed", res.message
    F = np.interp(t, res.t, res["F"])
    F = F + np.random.default_rng(seed).normal(0.0, noise, t.size) if noise else F
    return Measurement.from_arrays(t, source="synthetic", v=v, F=F)


def synthetic_force_record(model, t, f, *, mass=1.0, noise=0.0, seed=0) -> Measurement:
    """Position of a mass on ``model`` pushed by the force ``f(t)``, plus white noise."""
    system = make_rig(model, drive="force", mass=mass)
    res = simulate(system, (t[0], t[-1]), {"force": Table(t, f, hit_knots=False),
                                           "scale": 1.0},
                   options=SolverOptions(rtol=1e-10, atol=1e-13, dt_out=float(t[1] - t[0])))
    assert res.status == "completed", res.message
    x = np.interp(t, res.t, res["x"])
    x = x + np.random.default_rng(seed).normal(0.0, noise, t.size) if noise else x
    return Measurement.from_arrays(t, source="synthetic", f=f, x=x)
