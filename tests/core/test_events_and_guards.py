"""Events located on the dense output, reset maps, breakpoints, and the guards that stop
runs which would otherwise hang."""

import numpy as np
import pytest

from clutchsim.core import Constant, Ramp, SolverOptions, Step, simulate
from clutchsim.core.reference_problems import (
    ball,
    ball_bounce_times,
    oscillator,
    poison,
    sign_switch,
)


@pytest.mark.parametrize("solver", ["dopri5", "rodas4", "ros34pw2", "scipy-radau"])
def test_bouncing_ball_impact_times_are_analytic(solver):
    g, e, h0 = 9.81, 0.8, 1.0
    res = simulate(ball(g, e, h0), (0.0, 3.0), solver=solver,
                   options=SolverOptions(rtol=1e-10, atol=1e-12))
    assert res.status == "completed"
    times = np.array([ev.t for ev in res.events])
    exact = ball_bounce_times(g, e, h0, 20)
    exact = exact[exact < 3.0]
    assert len(times) == len(exact)
    assert np.abs(times - exact).max() < 1e-8
    # the reset map was applied: the ball leaves every impact upwards with e times the speed
    assert all(ev.action == "reset" for ev in res.events)
    assert res["h"].min() > -1e-9


def test_events_are_located_not_stepped_over_with_loose_tolerance():
    # A polynomial trajectory has zero local error: steps grow without bound unless event
    # functions are sampled inside each step.  Every bounce must still be found.
    res = simulate(ball(), (0.0, 3.0), solver="dopri5", options=SolverOptions(rtol=1e-3,
                                                                              atol=1e-3))
    exact = ball_bounce_times(9.81, 0.8, 1.0, 20)
    assert len(res.events) == np.sum(exact < 3.0)


@pytest.mark.parametrize("solver", ["dopri5", "rodas4", "ros34pw2"])
def test_breakpoints_are_hit_exactly(solver):
    # x' = u with u a step at an awkward time: x must be exactly piecewise linear.
    t_step = 1.2345678901
    sysm = oscillator(omega=0.0)            # x'' = F: integrate the step twice
    res = simulate(sysm, (0.0, 3.0), {"F": Step(t_step, height=2.0)}, solver=solver,
                   options=SolverOptions(rtol=1e-10, atol=1e-12))
    assert t_step in set(res.t.tolist())
    later = res.t >= t_step
    exact_v = np.where(later, 2.0 * (res.t - t_step), 0.0)
    assert np.abs(res["v"] - exact_v).max() < 1e-9
    # a ramp's two kinks are hit too
    res = simulate(sysm, (0.0, 3.0), {"F": Ramp(0.3333, 1.1111, 1.0)}, solver=solver)
    assert {0.3333, 0.3333 + 1.1111} <= set(res.t.tolist())


def test_a_reset_that_stops_the_run_is_reported_as_stopped():
    from clutchsim.core import STOP
    assert STOP == 2   # documented action code used by plants for terminal events


def test_chatter_detection_stops_a_naive_switching_law():
    # x' = 0.3 - sign(x): x reaches 0 at t = 1/0.7 and then must stay there, which the
    # switching law cannot do: its sign-change event fires ever faster.
    res = simulate(sign_switch(c=1.0, x0=1.0), (0.0, 5.0), {"u": Constant(0.3)},
                   solver="dopri5")
    assert res.status == "failed"
    assert "chatter" in res.message
    assert "sign change of x" in res.message
    t_fail = float(res.message.split("at t = ")[1].split()[0])
    assert t_fail == pytest.approx(1.0 / 0.7, abs=1e-3)
    assert res.t[-1] < 5.0
    assert res.stats.wall_s < 5.0


def test_without_events_the_step_collapse_guard_stops_the_run():
    res = simulate(sign_switch(c=1.0, x0=1.0, monitored=False), (0.0, 5.0),
                   {"u": Constant(0.3)}, solver="rodas4",
                   options=SolverOptions(h_min=1e-9))
    assert res.status == "failed"
    assert "step size collapsed" in res.message
    assert res.t[-1] == pytest.approx(1.0 / 0.7, abs=1e-3)


def test_step_budget_stops_a_long_run():
    res = simulate(oscillator(omega=50.0), (0.0, 1000.0), {"F": 0.0}, solver="dopri5",
                   options=SolverOptions(max_steps=500))
    assert res.status == "failed"
    assert "500 steps" in res.message and "max_steps" in res.message


def test_wall_time_budget_stops_a_long_run():
    res = simulate(oscillator(omega=50.0), (0.0, 1e7), {"F": 0.0}, solver="dopri5",
                   options=SolverOptions(wall_time=0.2, max_steps=10**9, max_output=10))
    assert res.status == "failed"
    assert "wall-time budget" in res.message
    assert res.stats.wall_s < 2.0


@pytest.mark.parametrize("solver", ["dopri5", "rodas4", "ros34pw2"])
def test_nan_from_the_right_hand_side_is_a_failed_result_naming_state_and_time(solver):
    res = simulate(poison(0.5), (0.0, 1.0), solver=solver)
    assert res.status == "failed"
    assert "non-finite" in res.message and "'b [-]'" in res.message
    t_fail = float(res.message.split("at t = ")[1].split()[0])
    assert 0.45 < t_fail <= 0.5


def test_truncated_output_is_said_in_the_message():
    res = simulate(oscillator(omega=50.0), (0.0, 10.0), {"F": 0.0}, solver="dopri5",
                   options=SolverOptions(max_output=50))
    assert res.status == "completed"
    assert res.t.size == 50 and res.t[-1] < 10.0
    assert "output stopped after 50 rows" in res.message and "max_output" in res.message
    assert res.outcome == "completed" and len(res.warnings) == 1
    assert "output stopped after 50 rows" in res.warnings[0]
    assert res.summary()["warnings"] == list(res.warnings)


@pytest.mark.parametrize("solver", ["dopri5", "rodas4", "ros34pw2", "scipy-radau"])
def test_parameters_and_event_index_reach_the_plant(solver):
    from clutchsim.core.reference_problems import probe
    res = simulate(probe(7.0), (0.0, 1.0), solver=solver,
                   options=SolverOptions(rtol=1e-10, atol=1e-12))
    # y' = 7: events at t = 1/7 (k = 0) and 2/7 (k = 1); log = (0*100 + 7)*1000 + 107
    assert [round(e.t, 9) for e in res.events] == [round(1 / 7, 9), round(2 / 7, 9)]
    assert res.final("log") == pytest.approx(7 * 1000 + 107)
    assert np.all(res["c"] == 7.0)


@pytest.mark.parametrize("solver", ["rodas5p", "dopri5"])
def test_passing_events_are_located_without_restarting_the_step(solver):
    # Monitoring events whose reset changes nothing: with Action.PASS the step goes on
    # through the crossing, with CONTINUE it restarts there.  Both locate every crossing
    # at its analytic time; PASS takes fewer steps and gives the same solution.
    from clutchsim.core import CONTINUE, PASS
    from clutchsim.core.reference_problems import monitored_oscillator
    omega, Omega, t_end = 3.0, 2.0 * np.pi, 6.0
    opts = SolverOptions(rtol=1e-9, atol=1e-12)
    runs = {a: simulate(monitored_oscillator(omega, Omega, int(a)), (0.0, t_end),
                        solver=solver, options=opts) for a in (CONTINUE, PASS)}
    for res in runs.values():
        assert res.status == "completed"
        assert {ev.action for ev in res.events} == {"recorded"}
        tx = np.array([ev.t for ev in res.events if ev.name == "x = 0"])
        ts = np.array([ev.t for ev in res.events if ev.name == "sin(Ωt) = 0"])
        kx = np.arange(tx.size)
        assert tx.size == np.sum((kx + 0.5) * np.pi / omega < t_end) == 6
        assert np.abs(tx - (kx + 0.5) * np.pi / omega).max() < 1e-9
        ks = np.arange(1, ts.size + 1)
        assert ts.size == 11                               # k·π/Ω inside (0, 6)
        assert np.abs(ts - ks * np.pi / Omega).max() < 1e-9
        assert np.abs(res["x"] - np.cos(omega * res.t)).max() < 1e-6
        assert np.all(np.diff([ev.t for ev in res.events]) > 0)   # in time order
    assert runs[PASS].stats.steps < runs[CONTINUE].stats.steps


def test_two_passing_crossings_in_one_step_are_both_located():
    # x stays 1 (omega = 0): the steps grow to h_max = 0.7 periods of sin(Ωt), so a step
    # holds up to two of its crossings, found by the samples inside the step.
    from clutchsim.core import PASS
    from clutchsim.core.reference_problems import monitored_oscillator
    res = simulate(monitored_oscillator(0.0, 2.0 * np.pi, int(PASS)), (0.0, 20.0),
                   solver="rodas5p", options=SolverOptions(h_max=0.7))
    t = np.array([ev.t for ev in res.events])
    assert t.size == 39                                    # k/2 inside (0, 20)
    assert np.abs(t - 0.5 * np.arange(1, 40)).max() < 1e-9
    assert res.stats.steps < t.size                        # some steps hold two


@pytest.mark.parametrize("solver", ["rodas4", "rodas5p", "ros34pw2"])   # a stiff problem
def test_the_earliest_of_three_crossings_in_one_step_is_found(solver):
    # The clock sin(2t) of the stiff tracker has nothing to do with the step size, which
    # grows to several seconds on its smooth solution: a step whose ends differ in sign
    # can hold three crossings, and the root of its two ends alone was the last of them
    # (π/2 and π were lost, 3π/2 came first).  Such a step is sampled like one whose ends
    # come near zero, so that the earliest crossing is the one located.
    from clutchsim.core.reference_problems import stiff_tracker
    res = simulate(stiff_tracker(lam=1e6, Omega=2.0), (0.0, 10.0), solver=solver,
                   options=SolverOptions(rtol=1e-4, atol=1e-6))
    assert res.status == "completed"
    exact = np.arange(1, 7) * np.pi / 2.0
    times = np.array([ev.t for ev in res.events])
    assert len(times) == len(exact), times
    assert np.abs(times - exact).max() < 1e-9
