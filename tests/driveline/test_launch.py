"""The example scenarios: model (6) and the robust switching model complete with a closed
energy balance; the naive switching model is stopped by chatter at lock-up."""

import numpy as np
import pytest

from clutchsim.driveline.run import run_scenario
from clutchsim.scenario import load_scenario

from _dl_paths import EXAMPLES


@pytest.fixture(scope="module")
def launch():
    return load_scenario(None)


@pytest.mark.slow
def test_default_launch_model6_completes_with_energy_balance(launch):
    r = run_scenario(launch, "mykhailevych2020")
    m = r.metrics
    assert m["completed"], m["message"]
    assert m["energy_balance_rel"] <= 1e-5
    assert not m["engine_stalled"] and m["engine_speed_min_rpm"] > 500
    assert m["slip_energy_J"] > 1000


def test_default_launch_robust_completes_and_naive_chatters_at_lockup(launch):
    robust = run_scenario(launch, "coulomb-robust").metrics
    assert robust["completed"], robust["message"]
    assert robust["energy_balance_rel"] <= 1e-8
    naive = run_scenario(launch, "coulomb-naive").metrics
    assert not naive["completed"]
    assert "chatter" in naive["message"] and "lock-up" in naive["message"]
    # it stops where the robust model locks
    t_stop = float(naive["message"].split("at t = ")[-1].split(" s")[0])
    assert t_stop == pytest.approx(robust["lockup_time_s"], abs=0.01)


@pytest.mark.parametrize("name,model", [("hill_start", "coulomb-robust"),
                                        ("tip_out", "coulomb-robust"),
                                        ("shift_1_2", "coulomb-robust"),
                                        ("coupled_clutches", "coulomb-robust")])
def test_examples_energy_balance(name, model):
    r = run_scenario(EXAMPLES / f"{name}.toml", model)
    assert r.metrics["completed"], r.metrics["message"]
    assert r.metrics["energy_balance_rel"] <= 1e-6


def test_tip_out_reverses_torque_without_slip_burst():
    r = run_scenario(EXAMPLES / "tip_out.toml", "coulomb-robust")
    res = r.result
    after = res.t > 1.2
    # Modelica sign: negative while the engine drives, positive once the drag reverses it
    assert np.max(res["T_clutch"][after]) > 0 > np.min(res["T_clutch"][res.t < 1.0])
    assert np.max(np.abs(res["w_slip_clutch"])) < 1e-6
    assert r.metrics["events"] == 0


def test_hill_start_moves_uphill():
    r = run_scenario(EXAMPLES / "hill_start.toml", "coulomb-robust")
    assert r.metrics["completed"]
    assert r.result["v_vehicle"][-1] > 1.0
