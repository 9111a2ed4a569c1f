"""Calibration from vehicle logs against a known truth: recovery within the issue's targets
and inside the reported intervals, through CSV, MDF4 and CAN files; validation errors; the
parameters the logs cannot identify; spec errors with file and line.

The coverage over 50 seeded logs is measured by benchmarks/calibration_coverage.py (too slow
for the suite); here one seed per case.
"""

from __future__ import annotations

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


@pytest.fixture(scope="module")
def cmap():
    return load_channel_map(EXAMPLES / "channels.toml")


@pytest.fixture(scope="module")
def spec():
    return load_calibration(SPEC)


def _check_recovery(res, truth):
    p, iv = res.parameters, res.intervals
    assert abs(p["capacity"] / truth["capacity"] - 1) < 0.05
    assert abs(p["touch_point"] - truth["touch_point"]) < 0.0003      # 0.3 mm
    assert abs(p["stiffness"] / truth["stiffness"] - 1) < 0.10
    for name in ("capacity", "touch_point", "stiffness", "torque_scale"):
        assert iv[name][0] <= truth[name] <= iv[name][1], (name, p[name], iv[name])
    assert not res.unidentified and not res.at_bound


@pytest.mark.parametrize("suffix", [".csv", ".mf4", ".blf"])
def test_round_trip_simulate_write_read_calibrate(tmp_path, spec, suffix):
    log, truth = synthetic_log(launches=2, seed=11)
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


def test_model_error_friction_rising_with_slip(spec, cmap):
    """Truth with a friction coefficient 20 % higher at large slip, fitted with Coulomb
    friction: the capacity absorbs the mean friction level; the targets still hold."""
    log, truth = synthetic_log(launches=3, seed=5, truth={"mu_rise": 0.2})
    res = calibrate(spec, [map_log(log, cmap)])
    p = res.parameters
    assert abs(p["touch_point"] - truth["parameters"]["touch_point"]) < 0.0003
    assert abs(p["stiffness"] / truth["parameters"]["stiffness"] - 1) < 0.10
    # the fitted capacity lies between the static and the full-slip capacity
    assert 0.95 * 240.0 < p["capacity"] < 1.25 * 240.0


def test_a_parameter_the_logs_do_not_excite_is_flagged(tmp_path, cmap):
    text = SPEC.read_text().replace(
        "[fixed]\n", "slip_ref = { start = 20.0, bounds = [1.0, 100.0] }\n\n[fixed]\n"
    ).replace("confidence = 0.95", "confidence = 0.95\nmax_nfev = 10")
    (tmp_path / "channels.toml").write_text((EXAMPLES / "channels.toml").read_text())
    path = tmp_path / "spec.toml"
    path.write_text(text)
    log, _ = synthetic_log(launches=1, seed=3)
    res = calibrate(load_calibration(path), [map_log(log, cmap)])
    # mu_rise = 0: the slip speed of the rise has no effect at all
    assert "slip_ref" in res.unidentified
    assert any(w.startswith("slip_ref cannot be identified") for w in res.warnings)
    assert "capacity" not in res.unidentified


@pytest.mark.parametrize("edit, message", [
    (("capacity = {", "capasity = {"),
     (r"spec.toml:\d+: \[parameters\] capasity: 'capasity' is not a launch-model parameter "
      r"\(did you mean 'capacity'\?\)")),
    (("start = 0.005, bounds = [0.002", "start = 0.009, bounds = [0.002"),
     r"spec.toml:\d+: \[parameters\] touch_point start = 0.009 lies outside bounds"),
    (("[fixed]\n", "[fixed]\ncapacity = 200.0\n"), r"capacity is both fitted and fixed"),
    (("ratio = 14.76", "ratio = -1.0"), r"spec.toml:\d+: \[vehicle\] ratio: -1.0 must be > 0"),
    # an unknown top-level key or table still names its line (it is not under any header)
    (("[calibration]\n", "stepp = 0.001\n\n[calibration]\n"),
     r"spec.toml:5: \[stepp\]: unknown table"),
    (("[fixed]\n", "[fixd]\n"), r"spec.toml:\d+: \[fixd\]: unknown table \(did you mean 'fixed'"),
])
def test_spec_errors_name_file_line_and_key(tmp_path, edit, message):
    (tmp_path / "channels.toml").write_text((EXAMPLES / "channels.toml").read_text())
    path = tmp_path / "spec.toml"
    path.write_text(SPEC.read_text().replace(*edit))
    with pytest.raises(CalibrationError, match=message):
        load_calibration(path)


def test_prior_and_per_launch_start_speed(tmp_path, cmap):
    """A tight Gaussian prior holds its parameter; the engine speed at the start of each
    launch is fitted per launch (``engine_speed0@k``) near the measured one."""
    text = SPEC.read_text().replace(
        "stiffness = { start = 8000.0, bounds = [1000.0, 60000.0] }",
        "stiffness = { start = 8000.0, bounds = [1000.0, 60000.0], prior = [15000.0, 10.0] }"
    ).replace("step = 0.001", 'step = 0.001\nper_launch = ["engine_speed0"]')
    (tmp_path / "channels.toml").write_text((EXAMPLES / "channels.toml").read_text())
    path = tmp_path / "spec.toml"
    path.write_text(text)
    log, _ = synthetic_log(launches=1, seed=8)
    res = calibrate(load_calibration(path), [map_log(log, cmap)])
    assert res.names[-1] == "engine_speed0@1"
    assert abs(res.parameters["stiffness"] - 15000.0) < 100.0       # the prior wins
    assert abs(res.parameters["engine_speed0@1"] - 79.8) < 5.0     # the idle speed held
    assert "engine_speed0" not in res.fixed


def test_a_stiffness_bound_the_step_cannot_follow_is_refused(tmp_path):
    (tmp_path / "channels.toml").write_text((EXAMPLES / "channels.toml").read_text())
    path = tmp_path / "spec.toml"
    path.write_text(SPEC.read_text().replace("bounds = [1000.0, 60000.0]",
                                             "bounds = [1000.0, 6.0e8]"))
    with pytest.raises(CalibrationError, match=r"spec.toml:\d+: \[parameters\] stiffness: "
                                               r"up to 6e\+08 is beyond what a step"):
        calibrate(load_calibration(path), [])


def test_explicit_start_points_are_checked(spec, cmap):
    from clutchsim.identify import FitOptions
    log, _ = synthetic_log(launches=1, seed=2)
    with pytest.raises(ValueError, match=r"starts\[0\]: mass not fitted; fitted: capacity"):
        calibrate(spec, [map_log(log, cmap)], options=FitOptions(starts=[{"mass": 1.0}]))
