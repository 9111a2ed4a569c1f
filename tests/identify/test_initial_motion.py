"""A body that starts moving starts sliding: run_rig, the rig-force fit plant and the EMPS
plant with v0 != 0 (issue 17, item 6's fix: a switching model used to start stuck and then
applied no friction at all)."""

from __future__ import annotations

import numpy as np
import pytest

from clutchsim.core import SolverOptions
from clutchsim.data import Measurement
from clutchsim.friction import MODELS, make_model
from clutchsim.friction.registry import parameter_source
from clutchsim.identify import evaluate, make_emps
from clutchsim.rig import make_rig, run_rig

OPTS = SolverOptions(rtol=1e-10, atol=1e-12, dt_out=1e-3)


@pytest.mark.parametrize("name", sorted(MODELS))
@pytest.mark.parametrize("v0", [0.4, -0.7])
def test_every_model_starts_in_steady_sliding_at_v0(name, v0):
    """A heavy body (1e6 kg, force 0) keeps v ≈ v0: its friction force is the model's
    steady sliding force at v0 from the first sample on, not a stuck or unloaded start."""
    model = make_model(name)
    src = parameter_source(model)
    domain = src.domain if src is not None else "translational"   # the set's own units
    res = run_rig(model, 0.01, force=0.0, v0=v0, mass=1e6, domain=domain, options=OPTS)
    F = res["F" if domain == "translational" else "T"]
    assert res.status == "completed", res.message
    expected = float(model.steady_state_force(v0))
    assert F[0] == pytest.approx(expected, rel=1e-6)
    assert F[-1] == pytest.approx(expected, rel=1e-4)
    assert np.sign(F[0]) == np.sign(v0)


@pytest.mark.parametrize(("v0", "scale"), [(1.0, 1.0), (-1.0, 1.0), (1.5, 0.5)])
def test_coulomb_robust_brakes_from_v0_in_closed_form(v0, scale):
    """Pure Coulomb (F_s = F_c = 1 N, no viscous part), 1 kg, no force: the deceleration is
    scale·F_c/m, so v = v0 − sign(v0)·a·t until t_stop = |v0|/a, where it sticks after
    x = v0·|v0|/(2a).  Before the fix the body kept v0 for the whole run."""
    model = make_model("coulomb-robust", F_s=1.0, sigma2=0.0)
    a = scale * model.F_c
    t_stop = abs(v0) / a
    res = run_rig(model, t_stop + 1.0, force=0.0, v0=v0, scale=scale, options=OPTS)
    assert res.status == "completed", res.message
    assert res["mode"][0] == np.sign(v0)
    t_half = 0.5 * t_stop
    v_half = np.interp(t_half, res.t, res["v"])
    assert v_half == pytest.approx(v0 - np.sign(v0) * a * t_half, rel=1e-8)
    assert res.final("v") == 0.0 and res.final("mode") == 0.0
    assert res.final("x") == pytest.approx(v0 * abs(v0) / (2 * a), rel=1e-8)


def test_rig_force_fit_plant_starts_sliding_at_its_v0():
    """The fit plant rig-force with the option v0 reproduces the closed-form braking record
    (and from rest, the same record is far off)."""
    t = np.linspace(0.0, 2.0, 2001)
    a, v0 = 1.0, 1.0
    x = np.where(t < v0 / a, v0 * t - 0.5 * a * t ** 2, v0 ** 2 / (2 * a))
    data = Measurement.from_arrays(t, source="braking", f=np.zeros(t.size), x=x)
    model = make_model("coulomb-robust", F_s=1.0, sigma2=0.0)
    kw = {"input": "f", "output": "x", "plant": "rig-force",
          "options": {"rtol": 1e-10, "atol": 1e-12}}
    sliding = evaluate(model, data, plant_options={"v0": v0}, **kw)
    assert sliding.nrmse < 1e-6
    rest = evaluate(model, data, **kw)
    assert rest.nrmse > 0.5


def test_emps_plant_initial_mode_follows_dq0():
    model = make_model("coulomb-robust")
    for dq0, mode in ((0.05, 1.0), (-0.05, -1.0), (0.0, 0.0)):
        system = make_emps(model, dq0=dq0)
        assert system.y0[3] == mode
        assert system.y0[1] == system.y0[2] == dq0       # velocity and its filtered copy
    system = make_rig(make_model("lugre"), v0=0.02)
    assert system.y0[2] == pytest.approx(make_model("lugre").sliding_state(0.02)[0])
