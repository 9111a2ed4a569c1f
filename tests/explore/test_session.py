"""The explorer session: parameter changes re-run the launch and move its metrics the way
the physics says; refused values name the key, the value and the rule."""

from __future__ import annotations

import math

import pytest

from clutchsim.explore import ENGAGEMENT, TORQUE_FACTOR, Session
from clutchsim.scenario import ScenarioError

T_STAT = "coupling[0].friction.overrides.T_stat"


@pytest.fixture(scope="module")
def base():
    s = Session()
    return s, s.run()


def _after(key, value):
    s = Session()
    s.set(key, value)
    return s, s.run()


def test_parameters_of_the_default_launch(base):
    s, out = base
    keys = [p.key for p in s.parameters]
    assert keys[0] == T_STAT        # the capacity first
    for k in (ENGAGEMENT, TORQUE_FACTOR, "vehicle.mass", "vehicle.grade", "coupling[1].c"):
        assert k in keys
    for p in s.parameters:
        assert p.low <= p.value <= p.high and p.step > 0
    assert out.completed and out.status == "completed"
    assert 0.9 < out.metrics["lockup_time_s"] < 1.5
    assert {"t", "omega_engine", "omega_disc", "T_clutch"} <= set(out.traces)
    assert out.units["omega_engine"] == "rad/s"
    assert len(out.traces["t"]) == len(out.traces["omega_engine"])


@pytest.mark.parametrize("key,factor,later", [
    ("vehicle.mass", 1.3, True),        # more inertia to accelerate: longer slip
    (T_STAT, 1.3, False),               # more clutch capacity: the disc catches up sooner
    (ENGAGEMENT, 1.5, True),            # a slower clutch ramp: lock-up later
])
def test_lockup_moves_the_right_way(base, key, factor, later):
    s0, out0 = base
    _, out = _after(key, s0.parameter(key).value * factor)
    assert out.completed, out.message
    t0, t1 = out0.metrics["lockup_time_s"], out.metrics["lockup_time_s"]
    assert (t1 > t0 + 1e-3) if later else (t1 < t0 - 1e-3)
    e0, e1 = out0.metrics["slip_energy_J"], out.metrics["slip_energy_J"]
    assert (e1 > e0) if later else (e1 < e0)


def test_uphill_and_more_torque_cost_slip_energy(base):
    _, out0 = base
    _, up = _after("vehicle.grade", 3.0)
    assert up.metrics["slip_energy_J"] > out0.metrics["slip_energy_J"]
    _, strong = _after(TORQUE_FACTOR, 1.2)
    # more engine torque during the slip: the engine flares, the clutch dissipates more
    assert strong.metrics["slip_energy_J"] > out0.metrics["slip_energy_J"]


def test_component_values_reuse_the_compiled_plant():
    s = Session()
    s.set("vehicle.mass", 1500.0)
    sc, _ = s._built
    assert sc is s.scenario                  # no rebuild: parameter values on the plant
    s.set(ENGAGEMENT, 1.0)                   # an input formula: the scenario rebuilt
    assert s._built[0] is not s.scenario
    assert s.changes()[1] == ("inputs.clutch_command", "ramp(0.5, 1.0, 1.0)")
    assert s.overrides() == ["vehicle.mass=1500.0",
                             'inputs.clutch_command="ramp(0.5, 1.0, 1.0)"']


@pytest.mark.parametrize("key,value,words", [
    ("vehicle.mass", -5.0, ["vehicle.mass", "-5.0", "must be > 0 kg"]),
    ("vehicle.mass", "heavy", ["vehicle.mass", "'heavy'", "must be a number"]),
    ("vehicle.mass", math.nan, ["vehicle.mass", "nan", "finite"]),
    (ENGAGEMENT, 0.0, [ENGAGEMENT, "0.0", "must be > 0 s"]),
    ("vehicle.wings", 2.0, ["vehicle.wings", "unknown key"]),
    ("scenario.name", 1.0, ["scenario.name", "not a number"]),
])
def test_refused_values_name_key_value_and_rule(base, key, value, words):
    s = Session()
    s.set("vehicle.mass", 1400.0)
    before = dict(s.values)
    with pytest.raises((ValueError, ScenarioError)) as info:
        s.set(key, value)
    msg = str(info.value)
    for w in words:
        assert w in msg, msg
    assert s.values == before                # a refused value changes nothing
    assert s.run().completed


def test_a_run_that_does_not_complete_is_an_outcome():
    _, out = _after("vehicle.grade", 12.0)   # too steep for 35 % throttle: it stalls
    assert not out.completed
    assert out.status != "completed" and out.message
    assert out.metrics["outcome"] != "completed"


def test_other_model():
    s = Session()
    s.set("vehicle.mass", 1500.0)
    s.set_model("coulomb-robust")
    keys = [p.key for p in s.parameters]
    assert keys[0].endswith("alternatives.coulomb-robust.F_s")
    assert s.values == {"vehicle.mass": 1500.0}
    out = s.run()
    assert out.model == "coulomb-robust" and out.completed
    with pytest.raises(ValueError, match="nosuchmodel"):
        s.set_model("nosuchmodel")
