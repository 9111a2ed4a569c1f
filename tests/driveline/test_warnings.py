"""Warnings of driveline runs that complete but should not be trusted (real runs)."""

from __future__ import annotations

import numpy as np
import pytest
from _dl_paths import EXAMPLES

from clutchsim import run_scenario
from clutchsim.analysis.launch_metrics import LOCK_SLIP, STEP_RATE_LIMIT

LAUNCH = EXAMPLES / "launch.toml"
F = "coupling[0].friction.overrides."
#: a model-(6) clutch that judders at lock-up: capacity 360 N·m, k_v 0.05, friction falling
#: by 20 % within ~1 rad/s of slip (the user's report: ±400 N·m, ~600 Hz, 70,000 steps)
JUDDER = [F + "T_stat=360", F + "k_din=0.8", F + "omega0=1.0"]


def _kinds(warnings) -> set:
    words = {"never locked": "no_lockup", "rings after lock-up": "ringing",
             "per simulated second": "steps"}
    return {k for w in warnings for needle, k in words.items() if needle in w}


@pytest.mark.parametrize("model", ["mykhailevych2020", "coulomb-robust"])
def test_default_launch_has_no_warnings(model):
    lr = run_scenario(LAUNCH, model)
    assert lr.metrics["outcome"] == "completed" and lr.metrics["lockup_time_s"] is not None
    assert lr.result.warnings == () and lr.metrics["warnings"] == []


def test_a_ringing_contact_is_warned_about_three_ways():
    lr = run_scenario(LAUNCH, "mykhailevych2020", overrides=JUDDER)
    r = lr.result
    assert lr.metrics["outcome"] == "completed"          # it completes ...
    # ... but after the first touch of zero slip the torque swings ±A, A above the capacity
    cap, torque, w = r["capacity_clutch"], r["T_friction_clutch"], np.abs(r["w_slip_clutch"])
    engaged = cap > 0.5 * cap.max()
    after = engaged & (np.arange(r.t.size) >= np.flatnonzero(engaged & (w < LOCK_SLIP))[0])
    amplitude = 0.5 * (torque[after].max() - torque[after].min())
    assert amplitude > 1.05 * cap[after].max() and cap[after].max() == pytest.approx(360.0)
    assert w[r.t > 2.0].max() > 5.0                      # it never holds
    assert r.stats.steps / r.t[-1] > STEP_RATE_LIMIT     # and it costs 100x the steps
    assert lr.metrics["lockup_time_s"] is None
    assert _kinds(r.warnings) == {"no_lockup", "ringing", "steps"}
    assert lr.metrics["warnings"] == list(r.warnings)
    ring = next(x for x in r.warnings if "rings" in x)
    assert f"±{amplitude:.0f} N·m" in ring and "capacity 360 N·m" in ring and "k_v" in ring


def test_many_steps_alone():
    # the seed's literal "zeroing" reset: the clutch locks, but the contact chatters through
    # thousands of resets (17,000 steps per simulated second)
    # (on the solver the warning was calibrated with: RODAS5P takes ~4,700 steps/s here)
    lr = run_scenario(LAUNCH, "mykhailevych2020",
                      overrides=[F + "reset='zero'", 'solver.method="ros34pw2"',
                                 "solver.rtol=1e-6"])
    assert lr.result.stats.steps / 4.0 > STEP_RATE_LIMIT
    assert _kinds(lr.result.warnings) == {"steps"}


def test_a_clutch_that_never_locks_and_expect_lockup():
    # engaged to 15 % only: 36 N·m of capacity cannot carry the engine's torque
    weak = ['inputs.clutch_command="ramp(0.5, 1.2, 0.15)"']
    lr = run_scenario(LAUNCH, "coulomb-robust", overrides=weak)
    r = lr.result
    assert lr.metrics["outcome"] == "completed" and "clutch.locked" in r.signals
    assert not np.any(r["clutch.locked"] > 0.5)
    assert np.abs(r["w_slip_clutch"][r.t > 1.5]).min() > LOCK_SLIP
    assert _kinds(r.warnings) == {"no_lockup"}
    assert "expect_lockup = false" in r.warnings[0]
    # a scenario that means its clutch to slip says so
    lr = run_scenario(LAUNCH, "coulomb-robust", overrides=[*weak, "scenario.expect_lockup=false"])
    assert lr.result.warnings == ()


def test_sweep_rows_carry_outcome_and_warnings(tmp_path):
    from clutchsim.studies.sweeps import SweepSpec, read_results, sweep
    # a sliding level of 30 N·m cannot carry the engine (never locks: a warning); 192 N·m
    res = sweep(LAUNCH, SweepSpec(vary={"coupling[0].friction.alternatives.coulomb-robust.F_c":
                "30,192"}, model="coulomb-robust", overrides=["scenario.t_end=1.5",
                "solver.dt_out=0.005"]), out=tmp_path / "s", plots=False)
    t = read_results(tmp_path / "s")
    assert list(t["outcome"]) == ["completed", "completed"]
    weak, strong = list(t["warnings"][0]), list(t["warnings"][1])
    assert _kinds(weak) == {"no_lockup"} and strong == []
    assert t.attrs["units"]["outcome"] == "-" and res.table is not None
