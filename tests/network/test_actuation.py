"""The actuation chain and closed-loop control (issue 20 items 2-4): signals between
components, the actuators' and the release system's closed forms, the PI law's tracking
and anti-windup, the exact Jacobian through signals, and the bad-input rules."""

import math
from pathlib import Path

import numpy as np
import pytest
from test_network import _jac_fd

from clutchsim.core import SolverOptions, simulate
from clutchsim.friction import make_model
from clutchsim.network import Network, NetworkError
from clutchsim.network.components import (
    Brake,
    HydraulicActuator,
    Inertia,
    LaunchController,
    ReleaseSystem,
    ServoActuator,
    TorqueSource,
)
from clutchsim.network.components.release_system import series
from clutchsim.scenario import ScenarioError, load_scenario
from clutchsim.signal_expr import parse_signal

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
OPTS = SolverOptions(rtol=1e-9, atol=1e-9, dt_out=0.002)
CUSHION = ((0.0, 1e-3, 2e-3), (0.0, 1000.0, 3000.0))
SPRING = ((0.0, 1e-3), (0.0, 4000.0))


@pytest.fixture(scope="module")
def bench():
    """One plant (one compilation) for the actuators and the release system."""
    net = Network([
        Inertia("m", J=1.0),
        HydraulicActuator("h1", command="p1", time_constant=0.05, rate_limit=2e6, area=1e-3,
                          threshold_pressure=1e5),
        HydraulicActuator("h2", command="p2", time_constant=0.02, dead_time=0.04, stages=4,
                          area=1e-3),
        ServoActuator("s1", command="x1", bandwidth=5.0),
        ServoActuator("s2", command="x2", bandwidth=5.0, rate_limit=0.01),
        ReleaseSystem("rs", travel="s1.position", cushion=CUSHION, spring=SPRING,
                      touch_point=5e-3),
        ReleaseSystem("rh", travel="x3", cushion=CUSHION, spring=SPRING, touch_point=5e-3,
                      hysteresis=4e-4, t_play=1e-3),
    ], [["m.a", "ground"]])
    return net.build()


def _run(sys_, t_end, **inputs):
    sig = {n: parse_signal(inputs.get(n, "0.0")) for n in sys_.input_names}
    res = simulate(sys_, (0.0, t_end), sig, options=OPTS)
    assert res.outcome == "completed", res.message
    return res


def test_step_responses_of_the_actuators_match_their_closed_forms(bench):
    assert bench.input_names == ("p1", "p2", "x1", "x2", "x3")   # produced: not inputs
    res = _run(bench, 1.5, p1="step(0.1, 1e6)", p2="step(0.1, 1e6)", x2="step(0.1, 0.01)")
    t, d = res.t, res.data
    # rate-limited lag: a ramp at r until (Δ - p)/τ = r, then the exponential
    dp, tau, r = 1e6, 0.05, 2e6
    t1 = 0.1 + (dp - r * tau) / r
    ref = np.where(t < 0.1, 0.0, np.where(t < t1, r * (t - 0.1),
                                          dp - r * tau * np.exp(-(t - t1) / tau)))
    assert np.max(np.abs(d["h1.pressure"] - ref)) < 2e-5 * dp
    # the piston: A·max(p - p_th, 0)
    assert np.allclose(d["h1.force"], 1e-3 * np.maximum(d["h1.pressure"] - 1e5, 0.0))
    # dead time as 4 equal lags: the Erlang distribution function
    ts = np.maximum(t - 0.1, 0.0) / 0.01
    erlang = 1.0 - np.exp(-ts) * sum(ts ** k / math.factorial(k) for k in range(4))
    assert np.max(np.abs(d["h2.delay4"] - dp * erlang)) < 2e-5 * dp
    # rate-limited servo: at 10 mm/s until ω_b·(x_c − x) = v, then the exponential
    wb, v, dx = 2 * math.pi * 5.0, 0.01, 0.01
    t2 = 0.1 + (dx - v / wb) / v
    ref = np.where(t < 0.1, 0.0, np.where(t < t2, v * (t - 0.1),
                                          dx - v / wb * np.exp(-wb * (t - t2))))
    assert np.max(np.abs(d["s2.position"] - ref)) < 1e-5 * dx


def _phasor(t, y, f):
    """Amplitude and phase of the component of ``y`` at ``f`` [Hz] (least squares)."""
    A = np.column_stack([np.sin(2 * np.pi * f * t), np.cos(2 * np.pi * f * t), np.ones_like(t)])
    a, b, _ = np.linalg.lstsq(A, y, rcond=None)[0]
    return math.hypot(a, b), math.atan2(b, a)


def test_servo_bandwidth_and_dead_time_cascade_frequency_responses(bench):
    f_d = 1.0 / (2 * math.pi * 0.04)           # ω·T_d = 1
    res = _run(bench, 3.0, x1="sine(0.001, 5.0)", p2=f"sine(1e5, {f_d!r})")
    keep = res.t > 1.5
    t = res.t[keep]
    gain, phase = _phasor(t, res.data["s1.position"][keep], 5.0)
    assert gain / 0.001 == pytest.approx(1 / math.sqrt(2), rel=1e-4)     # -3 dB
    assert phase == pytest.approx(-math.pi / 4, abs=1e-4)
    gain, phase = _phasor(t, res.data["h2.delay4"][keep], f_d)
    assert gain / 1e5 == pytest.approx((1 + 0.25 ** 2) ** -2, rel=1e-4)   # 0.885
    assert phase == pytest.approx(-4 * math.atan(0.25), abs=1e-4)        # -0.980 rad


def test_series_characteristic_and_play_hysteresis(bench):
    # same force through both springs, travels add: at 2000 N the cushion gives 1.5 mm,
    # the lever spring 0.5 mm, so the force is 2000 N at 5 + 2 = 7 mm (by hand)
    x, f = series((np.array(CUSHION[0]), np.array(CUSHION[1])),
                  (np.array(SPRING[0]), np.array(SPRING[1])))
    assert np.interp(2e-3, x, f) == pytest.approx(2000.0, rel=1e-12)
    res = _run(bench, 2.0, x1="0.007", x3="0.004 + ramp(0.0, 1.0, 0.005) + ramp(1.0, 1.0, -0.005)")
    d, t = res.data, res.t
    assert d["rs.clamp_force"][-1] == pytest.approx(2000.0, rel=1e-6)
    # the play: engaging reads the characteristic at x - h/2, releasing at x + h/2
    stat = lambda xx: np.interp(xx - 5e-3, x, f)
    trav = np.interp(t, [0.0, 1.0, 2.0], [0.004, 0.009, 0.004])
    up = (t > 0.3) & (t < 0.9)
    down = (t > 1.3) & (t < 1.9)
    lag = 0.005 * 1e-3                                   # rate · t_play
    slope = 4000.0 / 1e-3
    assert np.max(np.abs(d["rh.clamp_force"][up] - stat(trav[up] - 2e-4 - lag))) < 0.02 * slope * lag
    assert np.max(np.abs(d["rh.clamp_force"][down] - stat(trav[down] + 2e-4 + lag))) < \
        0.02 * slope * lag


def test_initial_state_reads_the_produced_signals():
    """A release system's play starts at its travel's initial value when the travel is an
    actuator's signal (the plant's outputs at the initial state)."""
    net = Network([Inertia("m", J=1.0), ServoActuator("s", command="xc", bandwidth=5.0,
                                                      x0=7e-3),
                   ReleaseSystem("r", travel="s.position", cushion=CUSHION,
                                 touch_point=5e-3, hysteresis=4e-4)], [["m.a", "ground"]])
    sys_ = net.build({"xc": 7e-3})
    assert sys_.y0[sys_.state_names.index("r.travel_played")] == 7e-3


@pytest.fixture(scope="module")
def loop():
    """A slip loop: a PI controller holds the speed of a driven inertia against a brake it
    commands; a second controller reads a free-spinning inertia (constant error)."""
    model = make_model("coulomb-robust", F_c=100.0, F_s=120.0)
    net = Network([
        TorqueSource("drive", input="tau"), Inertia("a", J=0.1, omega0=30.0),
        Brake("brake", model, "ctrl.command"),
        LaunchController("ctrl", target="r", kp=0.05, ki=0.5, t_track=0.05),
        Inertia("free", J=1.0, omega0=30.0),
        LaunchController("sat", target="r2", kp=0.05, ki=0.5, t_track=0.05, u_max=0.8),
    ], [["drive.flange", "a.a"], ["a.b", "brake.flange", "ctrl.a"], ["free.a", "sat.a"]])
    return net.build()


def test_pi_tracks_a_constant_slip_target_without_steady_error(loop):
    res = _run(loop, 6.0, tau="50.0", r="20.0", r2="20.0")
    assert res.data["omega_a"][-1] == pytest.approx(20.0, abs=1e-6)
    assert res.data["ctrl.command"][-1] == pytest.approx(0.5, rel=1e-6)   # τ / F_c
    assert res.data["error_ctrl"][-1] == pytest.approx(0.0, abs=1e-6)


def test_back_calculation_anti_windup_keeps_the_integral_at_the_limit(loop):
    # the free inertia turns at 30 rad/s: a constant error of +10 rad/s saturates the
    # command at u_max; the integral settles where raw = u_max + ki·t_track·e (closed form
    # of dI/dt = e + (u - raw)/(ki·t_track)), not growing with time; when the target
    # jumps above the speed, the command leaves the limit at once
    res = _run(loop, 2.0, tau="50.0", r="20.0", r2="20.0 + step(1.0, 20.0)")
    t, d = res.t, res.data
    kp, ki, tt, e = 0.05, 0.5, 0.05, 10.0
    i_end = (0.8 + ki * tt * e - kp * e) / ki
    k1 = np.searchsorted(t, 0.999)
    assert d["sat.integral"][k1] == pytest.approx(i_end, rel=1e-6)
    assert d["sat.command"][k1] == pytest.approx(0.8)
    after = np.searchsorted(t, 1.0 + 1e-9)
    assert d["sat.command"][after] < 0.8 - 0.5


def _assert_close(J, Jfd, names, tol):
    err = np.abs(J - Jfd) / np.maximum(np.abs(Jfd), 1.0)
    i, j = np.unravel_index(np.argmax(err), err.shape)
    assert err[i, j] < tol, (f"d {names[i]} / d {names[j]}: exact {J[i, j]:.9g}, "
                             f"differences {Jfd[i, j]:.9g}")


@pytest.mark.parametrize("name, at", [
    ("launch_closed_loop", {"omega_engine": 150.0, "omega_gearbox_input": 60.0,
                            "actuator.position_state": 7.3e-3, "controller.integral": 2.0,
                            "engine.governor_integral": 0.3}),
    ("launch_hydraulic", {"omega_engine": 120.0, "omega_wheels": 40.0 / 14.76,
                          "actuator.pressure_state": 2.1e6, "actuator.delay1": 2.3e6,
                          "actuator.delay2": 2.1e6, "actuator.delay3": 1.9e6,
                          "actuator.delay4": 1.7e6, "driver.integral": 0.4,
                          "engine.governor_integral": 0.3}),
])
def test_exact_jacobian_through_signals_matches_differences(name, at):
    """Consumers chain the producers' partials: clutch ← release system ← actuator ←
    controller ← engine torque (closed loop); engine ← driver, clutch ← actuator force."""
    sc = load_scenario(EXAMPLES / f"{name}.toml")
    sys_ = sc.network("mykhailevych2020").build(sc.inputs0())
    names = sys_.state_names
    y = sys_.y0.copy()
    for k, v in at.items():
        y[names.index(k)] = v
    y[names.index("clutch.phi")] = 1.5e-3
    u = np.array([sc.inputs[n](0.6)[0] for n in sys_.input_names])
    J, Jfd = _jac_fd(sys_, y, u)
    _assert_close(J, Jfd, names, 1e-4)
    # the chain is there: the clutch's speeds depend on the upstream states
    k = names.index("omega_engine")
    up = names.index("actuator.position_state" if "closed" in name else "actuator.pressure_state")
    assert J[k, up] != 0.0


def test_bench_jacobian_matches_differences(bench):
    y = bench.y0.copy()
    names = bench.state_names
    for k, v in {"h1.pressure_state": 3e5, "h2.delay1": 2e5, "h2.delay2": 1e5,
                 "h2.delay3": 0.7e5, "h2.delay4": 0.5e5, "h2.pressure_state": 0.4e5,
                 "s1.position_state": 6.1e-3, "s2.position_state": 2e-3,
                 "rh.travel_played": 6.5e-3}.items():
        y[names.index(k)] = v
    u = np.array([5e5, 3e5, 7e-3, 2.5e-3, 7.2e-3])
    J, Jfd = _jac_fd(bench, y, u)
    _assert_close(J, Jfd, names, 1e-5)


# ---------------------------------------------------------------- bad input
def test_a_loop_of_signals_that_no_state_breaks_is_named():
    with pytest.raises(NetworkError, match=r"loop of signals.*c1 -> c2 -> c1|c2 -> c1 -> c2"):
        Network([Inertia("a", J=1.0), LaunchController("c1", target="c2.command", ki=1.0),
                 LaunchController("c2", target="c1.command", ki=1.0)],
                [["a.a", "c1.a", "c2.a"]]).build()


def _bad(tmp_path, name, old, new):
    text = (EXAMPLES / f"{name}.toml").read_text(encoding="utf-8")
    assert old in text
    text = text.replace(old, new, 1)
    p = tmp_path / f"{name}.toml"
    p.write_text(text, encoding="utf-8")
    with pytest.raises(ScenarioError) as info:
        load_scenario(p)
    line = next(i for i, ln in enumerate(text.splitlines(), 1) if new.splitlines()[-1] in ln)
    return str(info.value), info.value.line, line


@pytest.mark.parametrize("name, old, new, words", [
    ("launch_actuated", "force = [0.0, 300.0, 900.0, 1900.0",
     "force = [0.0, 300.0, 900.0, 800.0",
     ["component[1].cushion",
      "cushion.force[3] = 800 N must be greater than cushion.force[2] = 900 N", "monotone"]),
    ("launch_actuated", "r_inner = 0.075", "r_inner = 0.11",
     ["component[4].r_inner", "= 0.11 m must be below r_outer = 0.1 m", "r_inner < r_outer"]),
    ("launch_hydraulic", "dead_time = 0.04", "dead_time = -0.01",
     ["component[1].dead_time", "= -0.01 s", ">= 0"]),
    ("launch_actuated", 'travel = "actuator.position"', 'travel = "actuator.positon"',
     ["component[1].travel", "'actuator.positon'", "did you mean 'actuator.position'"]),
    ("launch_actuated", 'travel_command = "0.005',
     '"actuator.position" = "0.0"\ntravel_command = "0.005',
     ["inputs.actuator.position", "produced by electromechanical actuator 'actuator'",
      "one source"]),
])
def test_bad_actuation_input_names_key_value_rule_and_line(tmp_path, name, old, new, words):
    msg, line, expected = _bad(tmp_path, name, old, new)
    for w in words:
        assert w in msg, msg
    if "produced" not in words[1]:
        assert line == expected


def test_touch_point_example_finds_the_touch_point():
    """The slow ramp at idle: the travel at the engagement start is the touch point (6 mm)
    plus the travel for 2 % of the torque, within 0.1 mm."""
    from clutchsim.scenario import run_scenario
    r = run_scenario(EXAMPLES / "touch_point.toml", "coulomb-robust")
    t0 = r.metrics["engagement_start_s"]
    x = float(np.interp(t0, r.result.t, r.result.data["actuator.position"]))
    assert 6e-3 < x < 6.1e-3


def test_unstable_controller_gains_warn_with_the_margin():
    """The closed-loop example is stable with a gain margin > 1; the same loop with kp and
    ki raised past that margin is unstable in the linearised model, and the warning names
    the controller, the growth rate and the margin."""
    from dataclasses import replace

    from clutchsim.analysis.actuation import controller_margin, controller_warnings
    from clutchsim.network import compile_network
    from clutchsim.scenario import run_scenario
    sc = load_scenario(EXAMPLES / "launch_closed_loop.toml")
    r = run_scenario(sc, "coulomb-robust")
    assert not any("unstable" in w for w in r.result.warnings)
    system = sc.network("coulomb-robust").build(sc.inputs0())
    plan = compile_network(sc.network("coulomb-robust"))
    [(name, _t, growth, margin)] = controller_margin(sc, system, r.result, plan)
    assert name == "controller" and growth < 1e-3 and 1.0 < margin < 64.0
    p = system.params.copy()
    p[[plan.slot[("controller", "kp")], plan.slot[("controller", "ki")]]] *= 2.0 * margin
    [msg] = controller_warnings(sc, replace(system, params=p), r.result)
    assert "launch controller 'controller'" in msg and "unstable" in msg
    assert f"gain margin {0.5:.3g}" in msg


def test_run_compares_the_closed_loop_launch_with_the_open_loop_one(tmp_path):
    """`clutchsim run` on the closed-loop launch runs the open-loop launch of `[scenario]
    compare` too: one row per launch in quality_comparison.json (and so in the report),
    the chain's figures; closing the loop lowers the jerk and the lock-up shock."""
    import json

    from clutchsim.cli import main
    out = tmp_path / "run"
    assert main(["run", str(EXAMPLES / "launch_closed_loop.toml"), "--model", "coulomb-robust",
                 "--out", str(out), "-q"]) == 0
    doc = json.loads((out / "quality_comparison.json").read_text())
    closed, open_ = doc["launches"].values()
    assert closed["jerk_peak_mps3"] < 0.5 * open_["jerk_peak_mps3"]
    assert abs(closed["lockup_shock_mps2"]) < 0.5 * abs(open_["lockup_shock_mps2"])
    for png in ("characteristic.png", "actuation_coulomb-robust.png", "comparison_launch.png"):
        assert (out / png).stat().st_size > 1000
    assert "quality_comparison.json › launches" in (out / "report.html").read_text()
