"""judder_analysis on scenarios, the CLI, the time-domain metric, bad input."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from clutchsim.analysis import OperatingPointError, judder_amplitude
from clutchsim.core import Result, Stats
from clutchsim.studies.judder import judder_analysis

REPO = Path(__file__).resolve().parents[2]


def _cli(*args):
    return subprocess.run([sys.executable, "-m", "clutchsim", "judder", *args], cwd=REPO, check=False,
                          capture_output=True, text=True, timeout=600)


def test_cli_json_shape_and_out(tmp_path):
    p = _cli("--at", "3", "--model", "coulomb-robust", "--json", "--out",
             str(tmp_path / "j"))
    assert p.returncode == 0, p.stderr
    doc = json.loads(p.stdout)
    assert set(doc) == {"kind", "model", "operating_point", "modes", "stable", "parameters"}
    assert doc["kind"] == "judder" and doc["model"] == "coulomb-robust"
    # the linearised network's values with units (the report's Parameters section)
    assert doc["parameters"]["clutch"]["friction.model"]["value"] == "coulomb-robust"
    assert doc["parameters"]["driveshaft"]["c"]["unit"] == "N·m/rad"
    assert doc["operating_point"]["t_s"] == 3.0
    assert doc["operating_point"]["elements"]["clutch"] == {
        "slip_rad_s": pytest.approx(0.0, abs=1e-9), "friction_slope_Nms": None,
        "state": "locked"}
    freqs = [m["frequency_hz"] for m in doc["modes"]]
    assert freqs == sorted(freqs) and freqs[0] == 0.0
    for m in doc["modes"]:
        assert set(m) == {"frequency_hz", "damping_ratio", "growth_rate_1_s", "stable",
                          "dominant_states"}
    assert doc["stable"] == all(m["stable"] for m in doc["modes"])
    # the shuffle mode of the locked launch: driveshaft twist, a few Hz
    shuffle = [m for m in doc["modes"] if 1.0 < m["frequency_hz"] < 10.0]
    assert shuffle and "phi_driveshaft" in shuffle[0]["dominant_states"]
    assert json.loads((tmp_path / "j" / "judder.json").read_text()) == doc
    assert (tmp_path / "j" / "judder.png").stat().st_size > 1000


@pytest.mark.parametrize(("args", "code", "text"), [
    (("--at", "9"), 2, "past the scenario's end t_end = 4"),
    (("--at", "-1"), 2, "must be >= 0"),
    (("--element", "clutc"), 2, "did you mean 'clutch'"),
    (("--at", "1", "--set", "solver.max_steps=5"), 1, "simulation did not complete"),
])
def test_cli_bad_input(args, code, text):
    p = _cli(*args)
    assert p.returncode == code, p.stderr
    assert text in p.stderr and "Traceback" not in p.stderr
    assert p.stdout == ""


def test_failed_run_before_the_operating_time_is_an_operating_point_error():
    with pytest.raises(OperatingPointError, match="ended at") as info:
        judder_analysis(None, "coulomb-robust", at=1.0, overrides=["solver.max_steps=5"])
    assert info.value.outcome == "budget"


def test_model6_contact_mode_and_its_pre_sliding_damping():
    """The locked model-(6) contact: ~650 Hz, lightly damped; c_ps damps it."""
    seed = judder_analysis(None, "mykhailevych2020", at=3.0)
    damped = judder_analysis(None, "mykhailevych2020", at=3.0,
                             overrides=["coupling[0].friction.overrides.c_ps=20"])
    top0, top1 = seed.modes[-1], damped.modes[-1]
    assert 550 < top0.frequency_hz < 750 and "clutch.phi" in top0.dominant_states
    assert 0 < top0.damping_ratio < 0.02
    assert top1.damping_ratio > 10 * top0.damping_ratio
    assert top1.frequency_hz == pytest.approx(top0.frequency_hz, rel=0.05)


def _result(t, torque, slip, cap):
    cols = [("T_clutch", "N·m", torque), ("w_slip_clutch", "rad/s", slip),
            ("capacity_clutch", "N·m", cap)]
    return Result.build(t, cols, outcome="completed", message="",
                        stats=Stats(0, 0, 0, 0, 0, 0, 0.0, 0.0))


def test_judder_amplitude_measures_a_band_oscillation_during_slip():
    t = np.linspace(0.0, 3.0, 6001)
    slip = np.where(t < 2.0, 50.0 * (1 - t / 2.0) + 2.0, 0.0)
    ramp = 100.0 * t
    cap = np.full_like(t, 200.0)
    quiet = judder_amplitude(_result(t, ramp, slip, cap))
    assert quiet == pytest.approx(0.0, abs=1e-6)
    shaken = judder_amplitude(_result(t, ramp + 7.0 * np.sin(2 * np.pi * 10.0 * t), slip, cap))
    assert shaken == pytest.approx(7.0, rel=0.03)
    fast = judder_amplitude(_result(t, ramp + 7.0 * np.sin(2 * np.pi * 200.0 * t), slip, cap))
    assert fast < 0.5                                  # outside the first-mode band
    assert judder_amplitude(_result(t, ramp, np.zeros_like(t), cap)) is None
    with pytest.raises(ValueError, match="band"):
        judder_amplitude(_result(t, ramp, slip, cap), band=(5.0, 1.0))


def test_judder_map_grid_table_and_figure(tmp_path):
    from clutchsim.plot.judder import plot_map
    from clutchsim.studies.judder import judder_map
    jm = judder_map(None, "coulomb-robust", x=("coupling[1].d", [0.05, 3.0]),
                    y=("vehicle.grade", [0.0, 10.0]), classic="x")
    assert jm.damping_ratio.shape == (2, 2) and jm.stable.all()
    # more damper damping: a larger margin (the damper mode is the least damped at 0.05)
    assert np.all(jm.damping_ratio[:, 1] > jm.damping_ratio[:, 0])
    doc = jm.as_dict()
    assert doc["kind"] == "judder_map" and len(doc["points"]) == 4
    assert set(doc["points"][0]) == {"coupling[1].d", "vehicle.grade", "damping_ratio",
                                     "growth_rate_1_s", "frequency_hz",
                                     "friction_slope_Nms", "stable"}
    json.dumps(doc, allow_nan=False)
    plot_map(jm, tmp_path / "map.png")
    assert (tmp_path / "map.png").stat().st_size > 1000
    with pytest.raises(ValueError, match="must be"):
        judder_map(None, x=("coupling[1].d", []), y=("vehicle.grade", [0.0]))


def test_cli_map_needs_two_axes():
    p = _cli("--map", "coupling[1].d=0.1:1:2")
    assert p.returncode == 2 and "exactly twice" in p.stderr
    p = _cli("--map", "coupling[1].d=0.1:1", "--map", "vehicle.grade=0:1:2")
    assert p.returncode == 2 and "KEY=LO:HI:N" in p.stderr
