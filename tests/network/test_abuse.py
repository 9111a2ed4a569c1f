"""Abuse load cases of clutch sizing (issue 39; docs/components.md, abuse load cases).

The clutch dump (``examples/clutch_dump.toml``): the pedal released in 50 ms at 4000 rpm.
The slipping clutch's torque ramps to its sliding capacity in 50 ms and drives the
driveline, two inertias on the driveshaft.  The peak driveshaft torque is checked against
the closed form of that two-inertia impact: the damped oscillator's response to a ramp,
``J_r·φ'' + d·φ' + k·φ = J2/(J1 + J2)·T_in(t)``, ``T_shaft = k·φ + d·φ'``."""

import math

import numpy as np
import pytest
from _dl_paths import EXAMPLES

from clutchsim.analysis.launch_metrics import energy_balance
from clutchsim.scenario import run_scenario

RATIO = 3.6 * 4.1
J1 = (0.015 + 0.01) * RATIO ** 2 + 0.05          # disc, gearbox input, carrier at the wheels
J2 = 1.6 + 1300.0 * 0.3 ** 2                     # wheels and the car
K, D, T_RAMP, F_C, F_S = 12000.0, 60.0, 0.05, 192.0, 240.0


def ramp_response(t):
    """``(φ, φ')·k/F`` of the damped oscillator under a unit-slope ramp of the force, from
    rest at t = 0 (Duhamel's integral of the impulse response, in closed form); 0 before."""
    jr = J1 * J2 / (J1 + J2)
    w, z = math.sqrt(K / jr), D / (2 * math.sqrt(K * jr))
    wd = w * math.sqrt(1 - z * z)
    t = np.maximum(t, 0.0)
    e = np.exp(-z * w * t)
    x = t - 2 * z / w + e * ((2 * z / w) * np.cos(wd * t) + ((2 * z * z - 1) / wd)
                             * np.sin(wd * t))
    xd = 1.0 - e * (np.cos(wd * t) + z / math.sqrt(1 - z * z) * np.sin(wd * t))
    return np.where(t > 0, x, 0.0), np.where(t > 0, xd, 0.0)


def two_inertia_impact_peak():
    """Peak shaft torque for the clutch torque ramping to F_C in T_RAMP (seen at the
    wheels: F_C·RATIO, J2/(J1 + J2) of it twisting the shaft): the ramp minus the same
    ramp delayed by T_RAMP, divided by T_RAMP."""
    f = F_C * RATIO * J2 / (J1 + J2)
    t = np.linspace(0.0, 0.5, 500001)
    x0, xd0 = ramp_response(t)
    x1, xd1 = ramp_response(t - T_RAMP)
    torque = f * ((x0 - x1) + D / K * (xd0 - xd1)) / T_RAMP
    k = int(np.argmax(torque))
    return torque[k], t[k]


def test_clutch_dump_peak_torque_against_the_two_inertia_impact():
    """The driveshaft peaks at 1.55 times the quasi-static share of the clutch's sliding
    torque, 1.19 times the nominal (static) capacity at the wheels: the closed form within
    0.5 % in size and 1 ms in time.  The clutch slips throughout (the impact is its sliding
    torque, not a lock-up), and the energy balance closes."""
    run = run_scenario(EXAMPLES / "clutch_dump.toml")
    res = run.result
    assert res.status == "completed", res.message
    assert energy_balance(res)["energy_balance_rel"] < 1e-8
    shaft = -res["T_driveshaft"]                      # drive torque: negative on side a
    k = int(np.argmax(shaft))
    peak, t_peak = two_inertia_impact_peak()
    assert shaft[k] == pytest.approx(peak, rel=5e-3)
    assert res.t[k] == pytest.approx(t_peak, abs=1e-3)
    assert np.all(res["w_slip_clutch"][res.t <= 2 * t_peak] < -100.0)
    nominal = F_S * RATIO
    assert shaft[k] / nominal == pytest.approx(1.185, abs=0.01)
    quasi_static = F_C * RATIO * J2 / (J1 + J2)
    assert shaft[k] / quasi_static == pytest.approx(1.55, abs=0.01)
    # what `clutchsim run` reports ([scenario] shaft = "driveshaft"): the same peak, and
    # the nominal capacity through the gears, 240 N·m × 3.6 × 4.1
    m = run.metrics
    assert m["peak_shaft_torque_Nm"] == pytest.approx(peak, rel=5e-3)
    assert m["shaft_capacity_Nm"] == pytest.approx(nominal, rel=1e-12)
    assert m["peak_shaft_torque_over_capacity"] == pytest.approx(1.185, abs=0.01)
    # an undamped shaft would overshoot to 1 + sin(ωT/2)/(ωT/2) = 1.78 of it
    w = math.sqrt(K * (1 / J1 + 1 / J2))
    assert shaft[k] < quasi_static * (1 + math.sin(w * T_RAMP / 2) / (w * T_RAMP / 2))


def test_dump_metrics_do_not_depend_on_the_output_grid():
    """The peak is refined between the samples (the vertex of the parabola through the
    largest and its neighbours): on the coarsest grid the metrics allow (10 ms) it is within
    0.1 % of the 0.2 ms grid's (the largest sample alone: 0.25 % low)."""
    fine, coarse = (run_scenario(EXAMPLES / "clutch_dump.toml",
                                 overrides=[f"solver.dt_out={dt}"]).metrics
                    for dt in (2e-4, 1e-2))
    for key in ("peak_shaft_torque_Nm", "peak_shaft_torque_over_capacity"):
        assert coarse[key] == pytest.approx(fine[key], rel=1e-3), key


@pytest.mark.parametrize("value, words", [
    ('"wheels"', ["scenario.shaft", "'wheels' is not a compliant coupling",
                  "driveshaft"]),
    ('"driveshat"', ["scenario.shaft", "did you mean 'driveshaft'"]),
])
def test_bad_shaft_is_refused_with_key_file_and_line(tmp_path, capsys, value, words):
    from clutchsim.cli import main
    text = (EXAMPLES / "clutch_dump.toml").read_text(encoding="utf-8")
    path = tmp_path / "bad.toml"
    path.write_text(text.replace('shaft = "driveshaft"', f"shaft = {value}", 1),
                    encoding="utf-8")
    assert main(["run", str(path), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "bad.toml:" in err and "Traceback" not in err
    for w in words:
        assert w in err, (w, err)


def test_hill_restarts_temperature_history_and_first_start_in_closed_form(tmp_path, capsys):
    """examples/durability/hill_restarts.toml: 90 starts on 12 %, 10 s apart.  The
    temperature history (durability.csv, the peak of each start) climbs start after start
    and the lining wears out before the 90th; the first start's pressure-plate temperature
    follows the lumped node's closed form ``θ(t) = θ_a + (θ0 − θ_a)·e^(−t/τ) + (s/C)·∫P(u)·
    e^(−(t−u)/τ) du`` (τ = C/G, s its heat share, P the clutch's friction power)."""
    import json

    import pandas as pd

    from clutchsim.cli import main
    from clutchsim.scenario import load_scenario
    duty = EXAMPLES / "durability" / "hill_restarts.toml"
    out = tmp_path / "hill"
    assert main(["durability", str(duty), "--full", "--out", str(out), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["outcome"] == "end_of_life" and summary["life_cycles"] < 90
    assert summary["max_energy_balance_rel"] < 1e-6
    hist = pd.read_csv(out / "durability.csv", skiprows=[1])
    peaks = hist["peak_theta_C"].to_numpy()
    assert len(peaks) == summary["life_cycles"] == 73
    assert np.all(np.diff(peaks) > 0.0)                 # each start adds heat
    assert peaks[10] == pytest.approx(131.8, abs=0.5)
    assert summary["peak_theta_C"] > 450.0
    # the first start alone, from 40 °C: pressure plate C = 1600 J/K, G = 5 W/K, share 0.5
    sc = load_scenario(EXAMPLES / "launch_wear.toml", overrides=[
        "vehicle.grade=12", 'inputs.throttle="0.1 + ramp(0.3, 0.5, 0.6)"'])
    res = run_scenario(sc, "coulomb-robust").result
    assert res.status == "completed", res.message
    C, G, share, th0, tha = 1600.0, 5.0, 0.5, 40.0, 20.0
    tau = C / G
    t, P = res.t, np.abs(res["P_clutch"])
    g = share * P * np.exp(t / tau)
    integral = np.concatenate([[0.0], np.cumsum(0.5 * (g[1:] + g[:-1]) * np.diff(t))])
    closed = tha + (th0 - tha) * np.exp(-t / tau) + np.exp(-t / tau) * integral / C
    theta = res["theta_pressure_plate"]
    assert np.max(np.abs(theta - closed)) < 0.05
    # adiabatic estimate share·W/C: 11 K, less what the plate loses to the air meanwhile
    work = float(res["W_friction"][-1])
    assert np.max(theta) - th0 == pytest.approx(share * work / C, abs=0.3)
    assert peaks[0] == pytest.approx(np.max(theta), abs=0.05)
