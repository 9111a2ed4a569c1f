"""The limited-slip differential (issue 38, item 4; docs/components.md): its torque bias
ratio in slip against the closed form ``(T_case/2 + T_p)/(T_case/2 − T_p)``, ``T_p =
μ·n·R_m·(F_preload + T_case·tan φ/r_ramp)`` (Milliken & Milliken, Race Car Vehicle Dynamics; with no preload
``(1 + 2k)/(1 − 2k)`` whatever the torque), the packs holding below their capacity and
breaking away at the closed-form instant, the friction work and the energy balance."""

import math
from pathlib import Path

import numpy as np
import pytest

from clutchsim.core import Outcome, SolverOptions, simulate
from clutchsim.network import Network
from clutchsim.network.components import Inertia, LimitedSlipDifferential, TorqueSource
from clutchsim.scenario import load_scenario, run_scenario

TIGHT = SolverOptions(rtol=1e-10, atol=1e-10, dt_out=1e-3)
EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _split_mu(F_preload, ramp_angle, J_l=1.2, J_r=0.8):
    lsd = LimitedSlipDifferential("lsd", "tau", ratio=3.5, mu=0.1, mu_s=0.12, n_faces=6,
                                  R_m=0.045, F_preload=F_preload, ramp_angle=ramp_angle,
                                  r_ramp=0.06)
    net = Network([TorqueSource("drive", input="tau"), lsd,
                   Inertia("left", J=J_l, omega0=10.0), TorqueSource("road", input="load"),
                   Inertia("right", J=J_r, omega0=20.0)],
                  [["drive.flange", "lsd.input"], ["lsd.left", "left.a"],
                   ["left.b", "road.flange"], ["lsd.right", "right.a"]])
    return lsd, net


@pytest.mark.parametrize(("F_preload", "ramp_angle", "T"),
                         [(2000.0, 30.0, 600.0), (0.0, 30.0, 600.0), (0.0, 30.0, 150.0),
                          (5000.0, 15.0, 300.0), (0.0, 20.0, 400.0)])
def test_torque_bias_ratio_in_slip_is_the_closed_form(F_preload, ramp_angle, T):
    """The right wheel (on ice) turns faster than the left (held by a road load): the
    packs carry T_p from the fast side to the slow one.  The side torques, read from the
    wheels' accelerations (J·α plus the road load), are T_case/2 ± T_p (1e-8), their
    ratio the bias ratio; with no preload it is (1 + 2k)/(1 − 2k), the same at any
    torque."""
    J_l, J_r, load = 1.2, 0.8, 0.6 * 3.5 * T
    lsd, net = _split_mu(F_preload, ramp_angle, J_l, J_r)
    u = {"tau": T, "load": -load}
    res = simulate(net.build(u), (0.0, 0.05), u, options=TIGHT)
    assert res.outcome == Outcome.COMPLETED, res.message
    assert not res.events                                 # slipping throughout
    T_case = 3.5 * T
    F = F_preload + T_case * math.tan(math.radians(ramp_angle)) / 0.06
    T_p = 0.1 * 6 * 0.045 * F
    assert res["F_clamp_lsd"][-1] == pytest.approx(F, rel=1e-12)
    assert res["T_lsd"][-1] == pytest.approx(T_p, rel=1e-9)
    a_l = (res["omega_left"][-1] - res["omega_left"][0]) / res.t[-1]
    a_r = (res["omega_right"][-1] - res["omega_right"][0]) / res.t[-1]
    T_left, T_right = J_l * a_l + load, J_r * a_r
    assert T_left == pytest.approx(T_case / 2 + T_p, rel=1e-8)
    assert T_right == pytest.approx(T_case / 2 - T_p, rel=1e-8)
    assert T_left / T_right == pytest.approx(lsd.bias_ratio(T), rel=1e-7)
    if F_preload == 0.0:
        k = 0.1 * 6 * 0.045 * math.tan(math.radians(ramp_angle)) / 0.06
        assert lsd.bias_ratio(T) == pytest.approx((1 + 2 * k) / (1 - 2 * k), rel=1e-12)
    # the gears split the case torque equally; the packs dissipate T_p·|w|
    assert res["T_gear_lsd_left"][-1] == pytest.approx(T_case / 2, rel=1e-9)
    assert np.all(res["P_lsd"] > 0.0)
    assert res["W_friction"][-1] == pytest.approx(
        np.trapezoid(res["P_lsd"], res.t), rel=1e-5)


def test_a_ramp_that_holds_half_the_case_torque_locks_at_any_torque():
    """k >= 1/2: the packs' torque reaches T_case/2 and the differential cannot slip:
    the bias ratio is infinite, and a slip at the start stops."""
    lsd, net = _split_mu(0.0, 60.0)
    assert 0.1 * 6 * 0.045 * math.tan(math.radians(60.0)) / 0.06 > 0.5
    assert lsd.bias_ratio(300.0) == math.inf
    u = {"tau": 300.0, "load": -500.0}
    res = simulate(net.build(u), (0.0, 0.2), u, options=TIGHT)
    assert res.outcome == Outcome.COMPLETED, res.message
    assert [e.name for e in res.events] == ["lsd: stop"]
    after = res.t > res.events[0].t
    assert np.allclose(res["omega_left"][after], res["omega_right"][after], rtol=0,
                       atol=1e-9)


def test_split_mu_example_holds_then_breaks_away_at_the_closed_form_instant():
    """examples/lsd_split_mu.toml: drive and road load ramp together (600 and 1500 N·m
    over 20 ms from 0.05 s).  Locked, equal wheels: the stick torque is half the road
    load, 750·s, against the capacity μ_s·n·R_m·(F_preload + gain·600·s); they meet at
    s = 64.8/(750 − 654.715), the break-away; then the bias ratio of 600 N·m.  Friction
    dissipates, and the energy balance closes."""
    sc = load_scenario(EXAMPLES / "lsd_split_mu.toml")
    res = run_scenario(sc, None).result
    assert res.status == "completed"
    gain = 3.5 * math.tan(math.radians(30.0)) / 0.06
    cap = 0.12 * 6 * 0.045
    s = cap * 2000.0 / (750.0 - cap * gain * 600.0)
    [ev] = [e for e in res.events if e.t > 0.0]
    assert ev.name == "lsd: breakaway"
    assert ev.t == pytest.approx(0.05 + 0.02 * s, rel=1e-7)
    held = res.t < ev.t
    assert np.allclose(res["omega_left"][held], res["omega_right"][held], rtol=1e-12, atol=0)
    T_p = 0.1 * 6 * 0.045 * (2000.0 + gain * 600.0)
    assert res["T_lsd"][-1] == pytest.approx(T_p, rel=1e-9)
    # friction dissipates: its power is never negative, its work never falls (held, the
    # slip is a round-off of 1e-14 rad/s)
    P, W = res["P_lsd"], res["W_friction"]
    assert np.all(P >= -1e-12 * P.max()) and np.all(np.diff(W) >= -1e-12 * W[-1])
    assert P[res.t > ev.t + 0.01].min() > 0.0
    balance = (res["W_in"] - res["W_friction"] - res["W_damping"]
               - (res["E_kinetic"] - res["E_kinetic"][0]))
    assert np.max(np.abs(balance)) <= 1e-7 * res["W_in"][-1]
