"""Friction that never creates energy: the sliding direction comes from the slip, and the
plant's physics checks (:mod:`clutchsim.network.invariants`) run on every result.

The first cases are the ones of issue 34, found as a new user would: a clutch that slid
against its slip and created 3.72 J while the run said "completed"; a clutch switched to
forward sliding at zero slip that then slid backwards; an engagement from command 0 at
zero slip that never locked.
"""

import numpy as np
import pytest

from clutchsim.core import Outcome, SolverOptions, simulate
from clutchsim.core.signals import Ramp, Sine
from clutchsim.friction import CoulombRobust
from clutchsim.network import Network
from clutchsim.network.components import Brake, Clutch, Inertia, SpringDamper, TorqueSource
from clutchsim.network.invariants import FrictionCheck, Invariants

TIGHT = SolverOptions(rtol=1e-9, atol=1e-10, dt_out=5e-4)


def _no_physics_warnings(res):
    assert res.outcome == Outcome.COMPLETED, res.message
    assert not [w for w in res.warnings if "physics check" in w], res.warnings


def _dissipates(res, *elements):
    wf = res["W_friction"]
    assert np.all(np.diff(wf) >= -1e-9 * (1.0 + abs(wf).max())), "W_friction decreased"
    for e in elements:
        assert res[f"P_{e}"].min() >= -1e-6, f"{e} delivered power"


def test_issue34_clutch_slides_with_its_slip_and_dissipates():
    """Torque s1 and a brake on P (J 4, at rest) -> spring-damper -> A (J 1, 10 rad/s) ->
    clutch -> B (J 1, 10 rad/s); clutch and brake commanded by s1 = sin(2π t), which starts
    at 0.  Before the fix only the first of the two break-aways due at t0 fired: the
    clutch stayed in its stuck mode with a growing slip, then slid in the direction of its
    stick torque, against its slip (W_friction -3.72 J, B sped up to 10.49 rad/s)."""
    net = Network(
        [TorqueSource("src", input="s1"),
         Brake("brake", CoulombRobust(F_c=0.5, F_s=0.5), command="s1"),
         Inertia("P", J=4.0), SpringDamper("sd", c=1e4, d=10.0),
         Inertia("A", J=1.0, omega0=10.0),
         Clutch("clutch", CoulombRobust(F_c=1.56, F_s=1.716), command="s1"),
         Inertia("B", J=1.0, omega0=10.0)],
        [["src.flange", "brake.flange", "P.a"], ["P.b", "sd.a"], ["sd.b", "A.a"],
         ["A.b", "clutch.a"], ["clutch.b", "B.a"]])
    s1 = Sine(1.0, 1.0)
    res = simulate(net.build({"s1": 0.0}), (0.0, 0.5), {"s1": s1}, solver="rodas4",
                   options=TIGHT)
    _no_physics_warnings(res)
    _dissipates(res, "clutch", "brake")
    # each element's own friction work: never falling, together the total
    wc, wbk = res["W_friction_clutch"], res["W_friction_brake"]
    assert np.all(np.diff(wc) >= -1e-12) and np.all(np.diff(wbk) >= -1e-12)
    assert wc[-1] + wbk[-1] == pytest.approx(res["W_friction"][-1], rel=1e-9)
    assert wc[-1] > 1.0 and wbk[-1] > 0.01
    # B is driven by nothing but the clutch, whose other side is slower: B slows down
    wb = res["omega_B"]
    assert wb[-1] < 10.0 and np.all(np.diff(wb) <= 1e-9)
    sliding = (res["clutch.locked"] < 0.5) & (res["clutch.mode"] != 0.0)
    assert np.all(res["clutch.mode"][sliding] * res["w_slip_clutch"][sliding] >= -1e-9)
    # both elements leave their stuck mode at t0 (the brake's break-away event, the clutch
    # in the plant's settling after it), each the way its stick torque drives its slip:
    # the damper slows A, so the clutch's slip b - a grows positive
    after = res.t > 0.0
    assert res["clutch.mode"][after][0] == 1.0 and res["clutch.locked"][after][0] == 0.0
    assert res["brake.mode"][after][0] == 1.0


def _pair(command, tau, omega0=5.0, J_a=1.0):
    net = Network([TorqueSource("drive", input="tau"), Inertia("a", J=J_a, omega0=omega0),
                   Clutch("clutch", CoulombRobust(F_c=10.0, F_s=11.0), command="f"),
                   Inertia("b", J=1.0, omega0=omega0)],
                  [["drive.flange", "a.a"], ["a.b", "clutch.a"], ["clutch.b", "b.a"]])
    return simulate(net.build({"f": 0.0}), (0.0, 0.5), {"tau": tau, "f": command},
                    options=TIGHT)


@pytest.mark.parametrize("tau", [5.0, -5.0])
def test_engagement_from_zero_command_with_load_slides_then_sticks(tau):
    """Both sides at the same speed, the command rising from 0: the free clutch slides the
    way the torque drives it (Modelica: free, then forward/backward by the slip's sign),
    the rising capacity brings the slip back to zero, where the stop event locks it."""
    res = _pair(Ramp(0.0, 0.1, 1.0), tau)
    _no_physics_warnings(res)
    _dissipates(res, "clutch")
    w = res["w_slip_clutch"]
    # the torque on a accelerates a: the slip b - a goes the other way
    assert np.sign(w[np.argmax(abs(w))]) == -np.sign(tau)
    stops = [e for e in res.events if e.name == "clutch: stop"]
    assert len(stops) == 1 and 0.0 < stops[0].t < 0.1
    assert res["clutch.locked"][-1] == 1.0 and abs(w[-1]) < 1e-12


def test_engagement_from_zero_command_without_load_is_locked_throughout():
    """Nothing loads the clutch and its slip is exactly zero: it sticks from t0 (locked,
    mode 0), not a free element that never locks (before: locked = 0 and no lock-up)."""
    res = _pair(Ramp(0.0, 0.1, 1.0), 0.0)
    _no_physics_warnings(res)
    assert np.all(res["clutch.locked"] == 1.0) and np.all(res["w_slip_clutch"] == 0.0)
    assert not res.events


# ---------------------------------------------------------------- the checks themselves
def _check():
    return Invariants((FrictionCheck("c", True, True, mode=1, locked=2, torque=0, slip=1,
                                     capacity=2),), speeds=(0,), w_friction=3, all_passive=True,
                      speed_unit="rad/s", effort_unit="N·m")


def _rows(mode, locked, slip, torque, cap, wf=None):
    n = len(mode)
    ts = np.arange(n, dtype=float)
    ys = np.zeros((n, 4))
    ys[:, 0] = 10.0
    ys[:, 1] = mode
    ys[:, 2] = locked
    ys[:, 3] = np.arange(n, dtype=float) if wf is None else wf
    outs = np.column_stack([torque, slip, cap])
    return ts, ys, outs


@pytest.mark.parametrize("rows, invariant, fatal", [
    (_rows([1, 1, -1], [0, 0, 0], [1.0, 0.5, 0.5], [1, 1, -1], [2, 2, 2]),
     "mode_against_slip", True),
    (_rows([0, 0, 0], [0, 0, 0], [0.0, 0.2, 0.4], [1, 1, 1], [2, 2, 2]),
     "slipping_while_stuck", True),
    (_rows([0, 0, 0], [1, 1, 1], [0.0, 0.0, 0.0], [1, 2.5, 1], [2, 2, 2]),
     "stick_over_capacity", True),
    (_rows([1, 1, 1], [0, 0, 0], [1e-3, 0.5, 0.5], [1, 1, 1], [2, 2, 2], wf=[0, 1, 0.5]),
     "friction_work_decreases", True),
    (_rows([1, 1, 1], [0, 0, 0], [1.0, -2e-5, 1.0], [1, 1, 1], [2, 2, 2]),
     "mode_against_slip", False),
])
def test_each_invariant_names_element_time_and_values(rows, invariant, fatal):
    found = _check()(*rows, rtol=1e-8, atol=1e-9)
    hit = [v for v in found if v.invariant == invariant]
    assert hit, found
    v = hit[0]
    assert v.fatal == fatal and v.element in ("c", "friction")
    assert f"t = {v.t:.9g} s" in v.text and v.unit in v.text


def test_a_mode_without_capacity_is_not_physics_and_with_capacity_it_is():
    """An element at zero capacity has no force in either mode: sliding in mode -1 with a
    positive slip creates nothing (a brake at zero command beside a naive clutch in its
    sliding mode, fuzzed networks).  The same rows with capacity are a violation."""
    rows = _rows([-1, -1, -1], [0, 0, 0], [1e-5, 3e-5, 0.5], [0, 0, 0], [0, 0, 0])
    assert [v for v in _check()(*rows, rtol=1e-8, atol=1e-9)
            if v.invariant == "mode_against_slip"] == []
    rows = _rows([-1, -1, -1], [0, 0, 0], [1e-5, 3e-5, 0.5], [0, 0, 0], [0, 0, 2])
    hit = [v for v in _check()(*rows, rtol=1e-8, atol=1e-9)
           if v.invariant == "mode_against_slip"]
    assert hit and hit[0].t == 2.0


def test_consistent_rows_and_reset_left_limits_pass():
    """Sliding with the slip, stuck at zero slip within capacity, and a row over capacity
    that is the left limit of a reset at the same instant (the break-away's own row)."""
    ts, ys, outs = _rows([1, 0, 0, -1], [0, 1, 1, 0], [1.0, 0.0, 0.0, -0.1],
                         [1, 1, 3, -1], [2, 2, 2, 2])
    ts[3] = ts[2]
    assert _check()(ts, ys, outs, rtol=1e-8, atol=1e-9) == []


# ------------------------------------------------ freewheels (FrictionModel.forward_only)
def _freewheel():
    return Invariants((FrictionCheck("f", False, True, mode=-1, locked=2, torque=0, slip=1,
                                     capacity=2, forward_only=True),), speeds=(0,),
                      w_friction=3, all_passive=True, speed_unit="rad/s", effort_unit="N·m")


def test_a_free_freewheel_sliding_backwards_is_fatal():
    """Fuzzed networks found a one-way clutch that was released and then slid backwards
    (-0.5 rad/s) while the run said "completed": nothing checked a freewheel's direction."""
    ts, ys, outs = _rows([0, 0, 0, 0], [1, 0, 0, 0], [0.0, 0.5, 0.1, -0.3],
                         [1, 1, 1, -1], [2, 2, 2, 2])
    found = _freewheel()(ts, ys, outs, rtol=1e-8, atol=1e-9)
    assert [(v.invariant, v.fatal, v.t) for v in found] == [("mode_against_slip", True, 3.0)]
    assert "freewheel sliding backwards" in found[0].text


def test_a_locked_freewheel_and_a_forward_slide_pass():
    ts, ys, outs = _rows([0, 0, 0], [1, 1, 0], [-1e-13, 0.0, 0.4], [-3, -3, 1], [2, 2, 2])
    assert _freewheel()(ts, ys, outs, rtol=1e-8, atol=1e-9) == []


def test_the_msl_one_way_clutch_example_is_checked_and_clean():
    """Modelica's OneWayClutch example (freewheel + clutch in parallel): the plant declares
    the freewheel's check, and the run (it frees and locks the freewheel) passes it."""
    from pathlib import Path

    from clutchsim.scenario import load_scenario, run_scenario

    path = Path(__file__).resolve().parents[2] / "examples" / "one_way_clutch.toml"
    scenario = load_scenario(path)
    checks = {c.name: c for c in scenario.system(None).invariants.elements}
    assert checks["oneWayClutch"].forward_only and checks["oneWayClutch"].locked >= 0
    _no_physics_warnings(run_scenario(scenario).result)


# ------------------------------------------- lossy gears (their loss element's modes)
def _lossy():
    return Invariants((FrictionCheck("g", True, True, mode=1, locked=2, torque=0, slip=1,
                                     capacity=-1),), speeds=(0,), w_friction=3,
                      all_passive=True, speed_unit="rad/s", effort_unit="N·m")


def test_a_lossy_gear_rolling_against_its_mode_is_fatal_and_any_stuck_torque_passes():
    ts, ys, outs = _rows([0, 0, 1, 1], [1, 1, 0, 0], [0.0, 0.0, 0.3, -0.2],
                         [50.0, -80.0, 0.5, 0.5], [0, 0, 0, 0])
    found = _lossy()(ts, ys, outs[:, :2], rtol=1e-8, atol=1e-9)
    assert {v.invariant for v in found} == {"mode_against_slip", "negative_power"}
    assert all(v.t == 3.0 and v.fatal for v in found)


def test_the_lossy_gears_of_a_network_are_checked():
    from clutchsim.network.components import LossyGear

    net = Network(
        [TorqueSource("src", input="tau"), Inertia("A", J=1.0, omega0=0.2),
         LossyGear("g", ratio=2.0, loss_table=((0.0, 0.9, 0.8, 0.1, 0.1),)),
         Inertia("B", J=2.0, omega0=0.1)],
        [["src.flange", "A.a"], ["A.b", "g.a"], ["g.b", "B.a"]])
    system = net.build({"tau": 0.0})
    (check,) = system.invariants.elements
    assert check.name == "g" and check.hybrid and check.passive and check.capacity == -1
    res = simulate(system, (0.0, 3.0), {"tau": Sine(amplitude=3.0, freq=1.0, offset=-0.5)},
                   solver="rodas4", options=TIGHT)
    _no_physics_warnings(res)
    # it rolls forward and backward, through zero speed, and its loss dissipates
    assert res["g.mode"].min() == -1.0 and res["g.mode"].max() == 1.0
    assert np.all(res["P_g"] >= -1e-9) and res["W_friction_g"][-1] > 0.0
