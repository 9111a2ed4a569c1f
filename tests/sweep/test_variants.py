"""Variants as parameter values on the built network (scenario.variants.VariantPlan)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from clutchsim.scenario import ScenarioError, load_scenario
from clutchsim.scenario.run import run_system
from clutchsim.scenario.variants import VariantPlan
from clutchsim.studies.sweeps import SweepOptions, SweepSpec, sweep

BASE = ["scenario.t_end=1.3", "solver.dt_out=0.005"]
MODEL = "mykhailevych2020"
EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


@pytest.fixture(scope="module")
def plan():
    return VariantPlan(load_scenario(None, overrides=BASE), MODEL)


@pytest.mark.parametrize("changes", [
    (("vehicle.mass", 1450.0), ("vehicle.grade", 4.0)),    # an inertia: derived block again
    (("inertia[1].J", 0.02),),
    (("coupling[1].c", 720.0), ("engine.kp", 0.03)),
    (("coupling[0].friction.overrides.phi0", 1.1e-3), ("vehicle.mass", 1350.0)),
    (("coupling[2].final_drive", 4.3),),                  # a gearbox value: a new ratio
    (("engine.stall_speed", 50.0),),                      # named in an event: its name again
    (("inertia[0].omega0", 90.0), ("vehicle.mass", 1250.0)),  # initial speeds: state anew
])
def test_a_direct_variant_is_the_rebuilt_one_bit_for_bit(plan, changes):
    fast = plan.system(changes)
    assert fast is not None and all(plan.direct(k, v) is not None for k, v in changes)
    sc, slow = plan.rebuilt(changes)
    if changes[0][0] == "engine.stall_speed":
        assert any("50 rad/s = 477 rpm" in n for n in fast.event_names)
    np.testing.assert_array_equal(fast.params, slow.params)
    np.testing.assert_array_equal(fast.y0, slow.y0)
    assert fast.event_names == slow.event_names and fast.metadata == slow.metadata
    a, b = run_system(plan.scenario, fast, MODEL), run_system(sc, slow, MODEL)
    assert {k: v for k, v in a.metrics.items() if k != "wall_s"} == \
        {k: v for k, v in b.metrics.items() if k != "wall_s"}


@pytest.mark.parametrize("key, value", [
    ("coupling[0].r_outer", 0.12),                      # read by the metrics, not the plant
    ("solver.rtol", 1e-7),
])
def test_other_keys_rebuild_the_variant(plan, key, value):
    assert plan.direct(key, value) is None
    assert plan.system(((key, value),)) is None
    sc, system = plan.rebuilt(((key, value),))
    assert sc.data != plan.scenario.data and system.n_states == plan.system(()).n_states


def test_solver_options_of_the_sweep_keep_keys_direct():
    from clutchsim.scenario.loader import with_solver_options
    sc = with_solver_options(load_scenario(None, overrides=BASE), {"rtol": 1e-7})
    plan = VariantPlan(sc, MODEL)
    assert plan.direct("vehicle.mass", 1400.0) is not None
    assert plan.scenario.options.rtol == 1e-7


def test_the_base_value_changes_nothing(plan):
    base = plan.system((("vehicle.mass", 1300.0),))
    np.testing.assert_array_equal(base.params, plan.params)


def test_a_friction_parameter_builds_the_model_again(plan):
    d = plan.direct("coupling[0].friction.overrides.phi0", 1.2e-3)
    assert d is not None and d.path == ("overrides", "phi0")
    fast = plan.system((("coupling[0].friction.overrides.phi0", 1.3e-3),))
    clutch = fast.metadata["models"]["clutch"]
    assert clutch == MODEL
    _sc, slow = plan.rebuilt((("coupling[0].friction.overrides.phi0", 1.3e-3),))
    np.testing.assert_array_equal(fast.params, slow.params)
    assert not np.array_equal(fast.params, plan.params)


@pytest.mark.parametrize("key, valid, bad, words", [
    ("vehicle.mass", 1400.0, -5.0, "vehicle.mass: = -5.0 kg is out of range: must be > 0 kg"),
    ("engine.stall_speed", 40.0, 90.0, "must be below idle_speed"),
    ("coupling[0].friction.overrides.phi0", 1.2e-3, -1.0, "phi0"),
])
def test_a_bad_value_of_a_direct_key_goes_to_the_loader(plan, key, valid, bad, words):
    assert plan.direct(key, valid) is not None
    assert plan.system(((key, bad),)) is None         # refused: the rebuild says why
    with pytest.raises(ScenarioError, match=words):
        plan.rebuilt(((key, bad),))


def test_sweep_rows_of_bad_values_are_errors_naming_key_and_rule(tmp_path):
    # normal(900, 900) with seed 1 draws 1211, 1639, 1197 and -273 kg
    res = sweep(None, SweepSpec(vary={"vehicle.mass": "normal(900, 900)"}, samples=4, seed=1,
                overrides=BASE, metrics=["lockup_time_s"]), SweepOptions(workers=1),
                out=tmp_path / "s")
    t = res.table
    bad = t["vehicle.mass"] <= 0
    assert bad.sum() == 1 and (t["status"][~bad] == "completed").all()
    row = t[bad].iloc[0]
    assert row["status"] == "error" and row["outcome"] == "error"
    assert "vehicle.mass: = " in row["message"] and "kg is out of range: must be > 0 kg" \
        in row["message"]


def test_a_stall_is_read_from_the_engine_component(plan):
    system = plan.system((("vehicle.grade", 40.0),))
    lr = run_system(plan.scenario, system, MODEL)
    assert lr.result.outcome == "event_failed"
    assert lr.result.event_source == "engine_torque"
    assert lr.result.metadata["kinds"]["engine_torque"] == "engine"
    assert lr.metrics["engine_stalled"] and lr.metrics["outcome"] == "stalled"


def test_a_network_scenario_maps_its_component_keys():
    sc = load_scenario(EXAMPLES / "simple_gear_shift.toml")
    plan = VariantPlan(sc, None)
    key = next(f"component[{i}].J" for i, c in enumerate(sc.data["component"])
               if c["name"] == "load")
    fast = plan.system(((key, 12.0),))
    assert plan.direct(key, 12.0) is not None
    np.testing.assert_array_equal(fast.params, plan.rebuilt(((key, 12.0),))[1].params)


def test_a_shifting_lossy_gearbox_variant_equals_its_rebuild():
    """A gearbox with losses and a shift carries banks of values (one per shift): a direct
    variant re-derives all of them and equals the rebuilt scenario's vector bit for bit."""
    plan = VariantPlan(load_scenario(EXAMPLES / "shift_1_2.toml"), "mykhailevych2020")
    key = "inertia[4].J"
    fast = plan.system(((key, 1.9),))
    assert plan.direct(key, 1.9) is not None
    np.testing.assert_array_equal(fast.params, plan.rebuilt(((key, 1.9),))[1].params)


def test_a_variant_system_checks_what_it_replaces(plan):
    """System.with_values (a variant: the base system with its own values) refuses
    vectors of another layout, naming the sizes, and keeps the base's metadata apart."""
    base = plan.system((("vehicle.mass", 1300.0),))
    with pytest.raises(ValueError, match=r"needs \d+ parameters and \d+ initial states"):
        base.with_values(base.params[:-1], base.y0)
    with pytest.raises(ValueError, match="event names for"):
        base.with_values(base.params, base.y0, event_names=("x",))
    other = base.with_values(base.params * 1.0, base.y0)
    other.metadata["extra"] = 1
    assert "extra" not in base.metadata
