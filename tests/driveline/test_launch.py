"""The example scenarios: model (6) and the robust switching model complete with a closed
energy balance; the naive switching model is stopped by chatter at lock-up; the tip-out
reverses the torque through the locked clutch without a slip burst."""

import numpy as np
import pytest
from _dl_paths import EXAMPLES

from clutchsim.scenario import load_scenario, run_scenario

#: every driveline scenario in examples/ (fit_*.toml are identification specs)
ALL_EXAMPLES = sorted(p.stem for p in EXAMPLES.glob("*.toml") if not p.stem.startswith("fit_"))

#: tip-out slip threshold [rad/s].  With the torque far below the capacity (|T| < 95 N·m
#: against 240 N·m) a locked clutch must not slip: a real slip burst reaches rad/s within
#: milliseconds.  Model (6) holds the torque on its elastic tanh term, so a changing torque
#: moves the linings by Δφ = φ0·Δatanh(T/T_stat) (about 4e-4 rad for the tip-out) at a few
#: 1e-3 rad/s; 0.02 rad/s (0.2 rpm) bounds that creep with a factor of ~3.
TIP_OUT_SLIP_MAX = 0.02


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
    assert robust["energy_balance_rel"] <= 1e-6   # issue: 1e-5; measured 3.7e-8 (ros34pw2)
    run = run_scenario(launch, "coulomb-naive")
    naive = run.metrics
    assert not naive["completed"] and run.result.outcome == "chatter"
    assert "chatter" in naive["message"] and "lock-up" in naive["message"]
    # it chatters from where the robust model locks (the first zero-slip crossing), and
    # chatter detection (100 events within 0.4 ms) stops it soon after.  How soon is
    # chaotic: rtol 2.9999e-6, 3e-6, 3.0001e-6 and 3.01e-6 stop it 35, 6, 34 and 29 ms
    # after the robust lock-up with the LU stage solves, 13, 28, 4 and 10 ms with the
    # explicit inverse (round-off alone), hence 50 ms, not the 20 ms this test had
    t_first = min(e.t for e in run.result.events if e.name.startswith("clutch:"))
    assert t_first == pytest.approx(robust["lockup_time_s"], abs=1e-3)
    t_stop = float(naive["message"].split("at t = ")[-1].split(" s")[0])
    assert robust["lockup_time_s"] < t_stop < robust["lockup_time_s"] + 0.05


def _example_models(name):
    """The robust switching model on a clutch that offers it, else the element's own."""
    sc = load_scenario(EXAMPLES / f"{name}.toml")
    return "coulomb-robust" if "coulomb-robust" in sc.models else None


@pytest.mark.parametrize("name", [n for n in ALL_EXAMPLES
                                  if n not in ("launch", "ten_launches")])
def test_every_example_closes_its_energy_balance(name):
    # the default launch is covered above (robust and model 6), the ten launches in
    # test_ten_launches.py
    r = run_scenario(EXAMPLES / f"{name}.toml", _example_models(name))
    assert r.metrics["completed"], r.metrics["message"]
    assert r.metrics["energy_balance_rel"] <= 1e-6


@pytest.mark.parametrize("name", ["hill_start", "tip_out", "shift_1_2"])
def test_model6_examples_complete_without_chatter(name):
    r = run_scenario(EXAMPLES / f"{name}.toml", "mykhailevych2020")
    m = r.metrics
    assert r.model == "mykhailevych2020"
    assert r.result.metadata["models"]["clutch"] == "mykhailevych2020"
    assert m["completed"], m["message"]
    assert "chatter" not in m["message"]
    assert m["energy_balance_rel"] <= 1e-5
    assert not m["engine_stalled"]
    res = r.result
    if name == "hill_start":
        assert res["v_vehicle"][-1] > 1.0                  # it drives up the 12 % grade
    if name == "shift_1_2":
        assert res["ratio_gearbox"][-1] == pytest.approx(2.1 * 4.1)
        assert abs(res["w_slip_clutch"][-1]) < 0.1        # re-engaged in second gear
    # the gearbox efficiency (all three examples) takes power whichever way it flows
    rolling = res["gearbox.locked"] < 0.5
    assert np.all(res["T_loss_gearbox"][rolling] * res["omega_gearbox_input"][rolling]
                  >= -1e-9)
    assert np.max(res["P_gearbox"]) > 100.0               # W: a real loss, not a rounding


@pytest.mark.parametrize("model", ["mykhailevych2020", "coulomb-robust"])
def test_tip_out_reverses_torque_without_slip_burst(model):
    r = run_scenario(EXAMPLES / "tip_out.toml", model)
    res = r.result
    assert r.metrics["completed"], r.metrics["message"]
    # Modelica sign: negative while the engine drives, positive once the drag reverses it
    driving = (res.t > 0.5) & (res.t < 1.0)
    after = res.t > 1.2
    assert np.max(res["T_clutch"][driving]) < -20.0
    assert np.max(res["T_clutch"][after]) > 20.0
    tip = res.t >= 1.0
    w = res["w_slip_clutch"][tip]
    assert np.max(np.abs(w)) < TIP_OUT_SLIP_MAX
    heat = np.trapezoid(np.abs(res["P_clutch"][tip]), res.t[tip])
    assert heat < 0.1                                     # J: no slip, no heat
    if model == "coulomb-robust":
        assert np.max(np.abs(w)) < 1e-9 and r.metrics["events"] == 0
    else:
        # the linings stay in the elastic range of the tanh term (no macro slip)
        phi = res["clutch.phi"][tip]
        assert np.max(np.abs(phi)) < 2.0e-3                 # reset_c·phi0


def test_hill_start_moves_uphill():
    r = run_scenario(EXAMPLES / "hill_start.toml", "coulomb-robust")
    assert r.metrics["completed"]
    assert r.result["v_vehicle"][-1] > 1.0


def test_scipy_lsoda_reference_backend_completes_the_default_launch():
    # LSODA's atol-sized noise around the stuck clutch's zero slip used to re-fire the
    # slip event every few microseconds until chatter detection stopped the run; the
    # backend's event dead band (width atol) lets it finish and agree with the compiled run
    ref = run_scenario(None, "mykhailevych2020")
    lsoda = run_scenario(None, "mykhailevych2020", solver="scipy-lsoda")
    assert lsoda.metrics["completed"], lsoda.metrics["message"]
    assert lsoda.metrics["lockup_time_s"] == pytest.approx(ref.metrics["lockup_time_s"],
                                                           abs=2e-3)
    grid = np.arange(0.0, 4.0, 0.01)
    for name in ("omega_engine", "omega_disc", "omega_wheels"):
        a = np.interp(grid, lsoda.result.t, lsoda.result[name])
        b = np.interp(grid, ref.result.t, ref.result[name])
        assert np.max(np.abs(a - b)) * 30 / np.pi < 0.2, name      # rpm
    assert lsoda.metrics["energy_balance_rel"] < 1e-5
