"""Ranges a physical system has (issue 35 §3-4) on real runs: the engine's rev limiter and
overspeed warning, a launch without a vehicle, and a chatter window that does not grow
with the run."""

from __future__ import annotations

import dataclasses
import math

import pytest
from _dl_paths import EXAMPLES

from clutchsim import run_scenario
from clutchsim.core import SolverOptions
from clutchsim.core.options import CHATTER_WINDOW_MAX_S
from clutchsim.core.simulate import _failure_message
from clutchsim.core.status import Code
from clutchsim.scenario import default_scenario_text, load_scenario

LAUNCH = EXAMPLES / "launch.toml"


def test_the_engine_stops_at_its_rev_limiter_and_the_run_says_it_overspeeds():
    """Throttle 1 with the clutch open: the full-load torque used to be held past the
    table's end (628 rad/s = 6,000 rpm), and the engine ran on to any speed silently."""
    lr = run_scenario(LAUNCH, "coulomb-robust",
                      overrides=['inputs.throttle="1.0"', 'inputs.clutch_command="0.0"',
                                 "scenario.t_end=3.0"])
    m = lr.metrics
    top_rpm = 628.3 * 30 / math.pi
    assert top_rpm < m["engine_speed_max_rpm"] <= 1.05 * top_rpm, m["engine_speed_max_rpm"]
    assert any("the engine overspeeds" in w and "rev limiter" in w for w in m["warnings"])


def test_a_launch_without_a_vehicle_says_which_metrics_are_null(tmp_path):
    text = default_scenario_text()
    start, end = text.index("[vehicle]"), text.index("[[thermal]]")
    path = tmp_path / "no_vehicle.toml"
    path.write_text(text[:start] + text[end:], encoding="utf-8")
    m = run_scenario(path, "coulomb-robust", overrides=["scenario.t_end=2.0"]).metrics
    assert m["vdv_mps175"] is None
    assert any("this launch has no vehicle ([vehicle]: a_vehicle)" in w for w in m["warnings"])


def test_the_chatter_window_does_not_grow_with_the_run():
    opts = SolverOptions()
    assert opts.chatter_window_for(1.0) == 1e-4            # short runs as before
    assert opts.chatter_window_for(4.0) == CHATTER_WINDOW_MAX_S
    assert opts.chatter_window_for(2e4) == CHATTER_WINDOW_MAX_S   # was 2 s
    assert SolverOptions(chatter_window=0.5).chatter_window_for(2e4) == 0.5


def test_a_long_default_launch_is_not_called_chatter():
    """t_end = 2e4 s: the window was 2 s, and model (6)'s zero crossings of the slip
    after lock-up (~50/s) ended the run as chatter, advising the model already in use."""
    sc = load_scenario(LAUNCH, overrides=["scenario.t_end=20000", "solver.dt_out=0.01"])
    opts = dataclasses.replace(sc.options, max_output=1000)   # the metrics are not the point
    lr = run_scenario(sc, "mykhailevych2020", options=opts)
    assert lr.metrics["outcome"] != "chatter", lr.metrics["message"]


def test_the_chatter_message_names_no_model():
    from clutchsim.scenario import load_scenario as load
    system = load(LAUNCH).system("mykhailevych2020")
    _, msg, _ = _failure_message(Code.CHATTER, 2.2, 0, 0, system, SolverOptions(), "rodas5p",
                                 4e-4)
    assert "chatter detected" in msg
    for name in ("mykhailevych2020", "coulomb-robust", "coulomb-naive"):
        assert name not in msg, msg


def test_the_engine_dip_of_a_dct_upshift_is_measured_from_engagement_start():
    """It was measured from the speed at t = 0 (idle), and read −1,578 rpm on this shift;
    from the speed when the oncoming clutch starts to carry torque it is the shift's drop
    of engine speed towards the second gear's."""
    import numpy as np
    lr = run_scenario(EXAMPLES / "dct_upshift.toml")
    m, res = lr.metrics, lr.result
    t0, t1 = m["engagement_start_s"], m["lockup_time_s"]
    assert 2.9 < t0 < t1 < 4.0
    rpm = res["omega_engine"] * 30 / math.pi
    inside = (res.t >= t0) & (res.t <= t1)
    want = float(np.interp(t0, res.t, rpm)) - float(rpm[inside].min())
    assert m["engine_dip_rpm"] == pytest.approx(want, rel=1e-3)
    assert 500.0 < m["engine_dip_rpm"] < 1500.0
