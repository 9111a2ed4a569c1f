"""The launch metrics do not depend on the output grid (issue 35 §3), and a grid too coarse
for them is refused before anything runs.

Before: ``dt_out = 10`` on the 4 s launch exited 0 with a slip energy of 6e-11 J (true
2.5 kJ), a jerk peak of 3.4 m/s³ (true 17.8) and no flare."""

from __future__ import annotations

import math

import pytest
from _dl_paths import EXAMPLES

from clutchsim import run_scenario
from clutchsim.analysis.launch_metrics import DT_OUT_MAX_S
from clutchsim.core import SolverOptions
from clutchsim.scenario import ScenarioError, load_scenario

LAUNCH = EXAMPLES / "launch.toml"
#: metrics compared; the times to 1 % of the engagement's duration (they are located or
#: interpolated, not relative quantities)
RELATIVE = ("vdv_mps175", "aw_rms_mps2", "jerk_peak_mps3", "jerk_rms_mps3",
            "lockup_shock_mps2", "friction_energy_density_J_mm2",
            "friction_power_density_peak_W_mm2", "engine_dip_rpm", "engine_flare_rpm",
            "slip_energy_J", "peak_heat_node_temp_C", "engine_speed_min_rpm",
            "engine_speed_max_rpm")
TIMES = ("engagement_start_s", "lockup_time_s")


@pytest.mark.parametrize("model", ["mykhailevych2020", "coulomb-robust"])
def test_metrics_on_a_1_ms_and_a_10_ms_grid_agree_within_1_percent(model):
    fine = run_scenario(LAUNCH, model, overrides=["solver.dt_out=0.001"]).metrics
    coarse = run_scenario(LAUNCH, model, overrides=[f"solver.dt_out={DT_OUT_MAX_S}"]).metrics
    span = fine["lockup_time_s"] - fine["engagement_start_s"]
    for key in TIMES:
        assert coarse[key] == pytest.approx(fine[key], abs=0.01 * span), key
    for key in RELATIVE:
        assert coarse[key] == pytest.approx(fine[key], rel=0.01), (key, fine[key], coarse[key])


@pytest.mark.parametrize("dt_out", [0.02, 0.5, 10.0])
def test_a_grid_coarser_than_the_metrics_need_is_refused_with_key_value_and_rule(
        tmp_path, dt_out):
    text = LAUNCH.read_text(encoding="utf-8").replace("dt_out = 0.002", f"dt_out = {dt_out}")
    path = tmp_path / "coarse.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(ScenarioError) as info:
        load_scenario(path)
    msg = str(info.value)
    assert info.value.key == "solver.dt_out" and f"{dt_out:g} s" in msg
    assert f"<= {DT_OUT_MAX_S:g} s" in msg and str(path) in msg
    assert info.value.line == next(i for i, ln in enumerate(text.splitlines(), 1)
                                   if ln.startswith("dt_out ="))
    # the library call with its own options is refused too, before it simulates
    with pytest.raises(ValueError, match="solver.dt_out"):
        run_scenario(LAUNCH, "coulomb-robust", options=SolverOptions(dt_out=dt_out))


def test_the_filters_stay_designable_however_long_the_run():
    """A 1e6 s run used to ask scipy for a 10 Hz low-pass on a 2 Hz grid: its raw
    "Digital filter critical frequencies" error."""
    import numpy as np

    from clutchsim.analysis import launch_quality as lq
    t = np.linspace(0.0, 1e6, 200_001)
    a = np.sin(2 * math.pi * t / 1e5)
    step = lq.filter_step_s(t)
    assert step == pytest.approx(lq.FILTER_DT_MAX_S)
    lq._lowpass_sos(lq.JERK_CUTOFF_HZ, step)       # was 0.5 s: a 10 Hz corner above Nyquist
    lq._wd_sos(step)
    with pytest.raises(ValueError, match="filter step dt_s = 0.1 s"):
        lq.weighted_acceleration_mps2(t, a, dt_s=0.1)
