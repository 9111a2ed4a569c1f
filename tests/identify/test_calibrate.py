"""Calibration from vehicle logs against a known truth: recovery within the issue's targets
and inside the reported intervals, through CSV, MDF4 and CAN files; validation errors; the
parameters the logs cannot identify; spec errors with file and line.

The coverage over 50 seeded logs is measured by benchmarks/calibration_coverage.py (too slow
for the suite); here one seed per case.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from clutchsim.data.channels import load_channel_map, map_log
from clutchsim.data.logs import write_log
from clutchsim.identify.calibrate import CalibrationError, calibrate, load_calibration
from clutchsim.identify.synthetic import synthetic_log

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples" / "calibration"
SPEC = EXAMPLES / "launch_calibration.toml"
#: the example's truth of the scenario keys it fits (the default launch's driveshaft)
KEYS = {"stiffness": "coupling[3].c", "damping": "coupling[3].d"}


def spec_text() -> str:
    """The example spec, its scenario path made absolute (for a copy in tmp_path)."""
    return SPEC.read_text().replace('scenario = "../launch.toml"',
                                    f'scenario = "{ROOT / "examples" / "launch.toml"}"')


def _write_spec(tmp_path, text: str) -> Path:
    (tmp_path / "channels.toml").write_text((EXAMPLES / "channels.toml").read_text())
    path = tmp_path / "spec.toml"
    path.write_text(text)
    return path


@pytest.fixture(scope="module")
def cmap():
    return load_channel_map(EXAMPLES / "channels.toml")


@pytest.fixture(scope="module")
def spec():
    return load_calibration(SPEC)


def _check_recovery(res, truth):
    p, iv = res.parameters, res.intervals
    truth = {**truth, "stiffness": truth.get(KEYS["stiffness"], 12000.0)}
    assert abs(p["capacity"] / truth["capacity"] - 1) < 0.05
    assert abs(p["touch_point"] - truth["touch_point"]) < 0.0003      # 0.3 mm
    assert abs(p["stiffness"] / truth["stiffness"] - 1) < 0.10
    for name in ("capacity", "touch_point", "stiffness", "torque_scale"):
        assert iv[name][0] <= truth[name] <= iv[name][1], (name, p[name], iv[name])
    assert not res.unidentified and not res.at_bound
    assert res.keys == KEYS


@pytest.mark.parametrize("suffix", [".csv", ".mf4", ".blf"])
def test_round_trip_simulate_write_read_calibrate(tmp_path, spec, suffix):
    log, truth = synthetic_log(launches=2, seed=11, truth={KEYS["stiffness"]: 10000.0})
    path = write_log(log, tmp_path / f"log{suffix}", dbc=EXAMPLES / "j1939_launch.dbc")
    res = calibrate(spec, [path])
    assert len(res.launches) == 2
    _check_recovery(res, truth["parameters"])


def test_three_launches_six_parameters_within_a_minute(spec, cmap):
    log, truth = synthetic_log(launches=3, seed=5)
    res = calibrate(spec, [map_log(log, cmap)])
    _check_recovery(res, truth["parameters"])
    assert res.wall_time < 60.0
    # the correlation matrix is one, symmetric, with a unit diagonal
    c = res.correlation
    assert c.shape == (6, 6) and np.allclose(c, c.T) and np.allclose(np.diag(c), 1.0)


def test_validation_launches_are_predicted(spec, cmap):
    fit_log, _ = synthetic_log(launches=2, seed=21)
    val_log, _ = synthetic_log(launches=1, seed=22)
    res = calibrate(spec, [map_log(fit_log, cmap)], [map_log(val_log, cmap)])
    (v,) = res.validation
    assert v.role == "validate"
    assert v.metrics["engine_rms_rpm"] < 40.0
    assert abs(v.metrics["slip_end_error_ms"]) < 60.0
    assert abs(v.metrics["peak_jerk_error"]) < 0.3 * v.metrics["peak_jerk_measured"]
    # measured and simulated at the measured stamps, each signal its own rate
    t_e, _, _ = v.signals["engine_speed"]
    t_i, _, _ = v.signals["input_speed"]
    assert t_i.size > 1.5 * t_e.size


def test_model_error_truth_of_another_friction_model(spec, cmap):
    """Truth made with coulomb-robust on the clutch (sliding torque 192 N·m, static
    240 N·m), fitted with model (6) (sliding/static 0.955): a launch measures the sliding
    torque, so the fitted static capacity is 192/0.955 and the sliding capacity is
    recovered; touch point and stiffness hold their targets."""
    log, truth = synthetic_log(launches=3, seed=5, model="coulomb-robust")
    res = calibrate(spec, [map_log(log, cmap)])
    p = res.parameters
    assert abs(p["touch_point"] - truth["parameters"]["touch_point"]) < 0.0003
    assert abs(p["stiffness"] / 12000.0 - 1) < 0.10
    sliding = res.sliding_capacity
    assert sliding["speed"] == 20.0
    assert abs(sliding["value"] / 192.0 - 1) < 0.05
    assert p["capacity"] < 0.9 * 240.0              # not the truth's static capacity


def test_a_parameter_the_logs_do_not_excite_is_flagged(tmp_path, cmap):
    """The pressure plate's heat capacity: the plate stays below 200 °C, where the friction
    coefficient's temperature factor is 1, so no speed depends on it."""
    text = spec_text().replace(
        "[fixed]\n", 'plate = { key = "thermal[0].capacity", start = 1600.0, bounds = '
        "[100.0, 10000.0] }\n\n[fixed]\n").replace("confidence = 0.95",
                                                    "confidence = 0.95\nmax_nfev = 10")
    log, _ = synthetic_log(launches=1, seed=3)
    res = calibrate(load_calibration(_write_spec(tmp_path, text)), [map_log(log, cmap)])
    assert "plate" in res.unidentified
    assert any(w.startswith("plate cannot be identified") for w in res.warnings)
    assert "capacity" not in res.unidentified
    assert res.units["plate"] == "J/K" and res.keys["plate"] == "thermal[0].capacity"


@pytest.mark.parametrize("edit, message", [
    (("capacity = {", "capasity = {"),
     (r"spec.toml:\d+: \[parameters\] capasity: 'capasity' is neither a parameter of the "
      r"measured inputs \(did you mean 'capacity'\?\)")),
    (('key = "coupling[3].c"', 'key = "coupling[3].cc"'),
     (r"spec.toml:\d+: \[parameters\] stiffness: key = 'coupling\[3\].cc': the scenario "
      r"has no number there \(did you mean 'c'\?\)")),
    (("start = 0.005, bounds = [0.002", "start = 0.009, bounds = [0.002"),
     r"spec.toml:\d+: \[parameters\] touch_point start = 0.009 lies outside bounds"),
    (("[fixed]\n", "[fixed]\ncapacity = 200.0\n"), r"capacity is both fitted and fixed"),
    (("launch.toml", "nolaunch.toml"), (r"spec.toml:\d+: \[calibration\] scenario: no such "
                                        r"scenario .*nolaunch.toml")),
    (("[calibration]\n", "[vehicle]\nmass = 1300.0\n\n[calibration]\n"),
     r"spec.toml:\d+: \[vehicle\]: unknown table"),
    (('model = "mykhailevych2020"', 'model = "lugree"'),
     (r"spec.toml:\d+: \[calibration\] model: 'lugree' is not a friction model \(did you "
     r"mean 'lugre'\?\)")),
    # an unknown top-level key or table still names its line (it is not under any header)
    (("[calibration]\n", "stepp = 0.001\n\n[calibration]\n"),
     r"spec.toml:7: \[stepp\]: unknown table"),
    (("[fixed]\n", "[fixd]\n"), r"spec.toml:\d+: \[fixd\]: unknown table \(did you mean 'fixed'"),
])
def test_spec_errors_name_file_line_and_key(tmp_path, edit, message):
    path = _write_spec(tmp_path, spec_text().replace(*edit))
    with pytest.raises(CalibrationError, match=message):
        load_calibration(path)


def test_prior_and_per_launch_start_speed(tmp_path, cmap):
    """A tight Gaussian prior holds its parameter; the engine speed at the start of each
    launch is fitted per launch (``engine_speed0@k``) near the measured one."""
    text = spec_text().replace(
        "start = 8000.0, bounds = [1000.0, 60000.0] }",
        "start = 8000.0, bounds = [1000.0, 60000.0], prior = [15000.0, 10.0] }"
    ).replace("step = 0.001", 'step = 0.001\nper_launch = ["engine_speed0"]')
    log, _ = synthetic_log(launches=1, seed=8)
    res = calibrate(load_calibration(_write_spec(tmp_path, text)), [map_log(log, cmap)])
    assert res.names[-1] == "engine_speed0@1"
    assert abs(res.parameters["stiffness"] - 15000.0) < 100.0       # the prior wins
    assert abs(res.parameters["engine_speed0@1"] - 83.78) < 5.0    # the idle speed held
    assert "engine_speed0" not in res.fixed


def test_a_scenario_without_an_engine_is_refused(tmp_path):
    """The measured torque drives the scenario's engine: a scenario without one (here its
    torque a load on the engine's inertia) cannot be calibrated."""
    scenario = tmp_path / "no_engine.toml"
    data = (ROOT / "examples" / "launch.toml").read_text()
    start = data.index("[engine]")
    end = data.index("[[inertia]]")
    scenario.write_text(data[:start] + data[end:].replace(
        'name = "engine"      # crankshaft + flywheel',
        'name = "engine"      # crankshaft + flywheel\nload = "throttle"'))
    text = spec_text().replace(str(ROOT / "examples" / "launch.toml"), str(scenario))
    with pytest.raises(CalibrationError, match=r"spec.toml:\d+: \[calibration\] scenario: "
                       r".*no_engine.toml: the scenario has no engine component; a "
                       r"calibration needs a launch scenario"):
        load_calibration(_write_spec(tmp_path, text))


def test_signals_and_a_fixed_scenario_key(tmp_path, cmap):
    """``[calibration] signals`` names the run's signal a measured speed is; a scenario key
    in ``[fixed]`` holds that value in every run; a signal the run does not have is refused
    at its line."""
    text = spec_text().replace(
        "step = 0.001", 'step = 0.001\nsignals = { input_speed = "omega_gearbox_input" }'
    ).replace('damping = { key = "coupling[3].d", start = 40.0, bounds = [1.0, 500.0] }',
              "").replace("[fixed]\n", '[fixed]\n"coupling[3].d" = 60.0\n')
    spec = load_calibration(_write_spec(tmp_path, text))
    assert spec.plant.layout.signals["input_speed"] == "omega_gearbox_input"
    assert spec.keys == {"stiffness": "coupling[3].c", "coupling[3].d": "coupling[3].d"}
    log, _ = synthetic_log(launches=1, seed=3, signals={"input_speed":
                                                        "omega_gearbox_input"})
    res = calibrate(spec, [map_log(log, cmap)])
    assert res.fixed["coupling[3].d"] == 60.0 and "damping" not in res.parameters
    assert abs(res.parameters["stiffness"] / 12000.0 - 1) < 0.10
    bad = _write_spec(tmp_path, text.replace("omega_gearbox_input", "omega_gearbox"))
    with pytest.raises(CalibrationError, match=r"spec.toml:\d+: \[calibration\] signals: "
                       r"input_speed = 'omega_gearbox' is not a signal of the run \(did you "
                       r"mean 'omega_gearbox_input'\?\); its speeds: .*omega_engine"):
        load_calibration(bad)


def test_engine_driven_by_the_measured_throttle(tmp_path, cmap):
    """``engine = "throttle"``: the scenario's own engine (full-load map, drag, idle
    governor) runs on the logged accelerator pedal (EEC2, 20 Hz, 0.4 % steps); no engine
    torque is needed, and the targets hold."""
    text = spec_text().replace("step = 0.001", 'step = 0.001\nengine = "throttle"')
    text = "\n".join(line for line in text.splitlines() if not line.startswith("torque_"))
    log, truth = synthetic_log(launches=2, seed=9)
    mapped = map_log(log, cmap)
    mapped = replace(mapped, signals={k: v for k, v in mapped.signals.items()
                                      if k != "engine_torque"})
    res = calibrate(load_calibration(_write_spec(tmp_path, text)), [mapped])
    p, iv = res.parameters, res.intervals
    assert abs(p["capacity"] / 240.0 - 1) < 0.05
    assert abs(p["touch_point"] - truth["parameters"]["touch_point"]) < 0.0003
    assert abs(p["stiffness"] / 12000.0 - 1) < 0.10
    assert iv["capacity"][1] > iv["capacity"][0]
    assert any(w.startswith("the intervals of a calibration driven by the logged throttle "
                            "are too narrow") for w in res.warnings)
    assert "torque_scale" not in res.fixed and "measured throttle" in res.notes[0]
    bad = _write_spec(tmp_path, text.replace("[fixed]\n", "[fixed]\ntorque_scale = 1.0\n"))
    with pytest.raises(CalibrationError, match=r"spec.toml:\d+: \[fixed\] torque_scale: "
                       r"torque_scale scales the measured engine torque; with engine = "
                       r"'throttle'"):
        load_calibration(bad)
    bad = _write_spec(tmp_path, text.replace('engine = "throttle"', 'engine = "pedal"'))
    with pytest.raises(CalibrationError, match=r"\[calibration\] engine: engine = 'pedal'"):
        load_calibration(bad)


def test_explicit_start_points_are_checked(spec, cmap):
    from clutchsim.identify import FitOptions
    log, _ = synthetic_log(launches=1, seed=2)
    with pytest.raises(ValueError, match=r"starts\[0\]: mass not fitted; fitted: capacity"):
        calibrate(spec, [map_log(log, cmap)], options=FitOptions(starts=[{"mass": 1.0}]))
