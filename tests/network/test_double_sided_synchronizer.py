"""The double-sided synchroniser (issue 38; docs/components.md, "Double-sided
synchroniser"): one sleeve between two gears, two ``synchronizer`` elements on the
sleeve's shaft reading the same sleeve force with ``side`` +1 and -1.  The force's sign
chooses the side: that side's cone synchronises its gear in the closed-form time
``J_eq·Δω/T_cone`` (1 %; to the blocker's window exactly) while the other gear turns
freely; the blocker property on both sides; neutral at zero force; the AMT 1-2 upshift of
``examples/amt_upshift_sleeve.toml`` through one sleeve."""

import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from test_shift_elements import (
    test_bad_input_names_key_value_rule_file_and_line_and_exits_2 as _bad_input,
)

from clutchsim.core import Outcome, SolverOptions, simulate
from clutchsim.core.signals import Step
from clutchsim.friction import CoulombRobust
from clutchsim.network import Network
from clutchsim.network.components import Inertia, Synchronizer, TorqueSource

TIGHT = SolverOptions(rtol=1e-9, atol=1e-10, dt_out=1e-4)
EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
R_M, ALPHA, MU = 0.04, 6.5, 0.1
WEDGE = R_M / math.sin(math.radians(ALPHA))


def _sleeve(J1, J2, Js, w1, w2, ws, w_sync=0.5, F_block=300.0, torque=None):
    """Gear 1 - sync1 (side +1) - shaft - sync2 (side -1) - gear 2, a torque on the shaft."""
    def side(name, s):
        return Synchronizer(name, CoulombRobust(F_c=MU, F_s=1.2 * MU), "f", R_m=R_M,
                            alpha=ALPHA, w_sync=w_sync, F_block=F_block, side=s)
    comps = [Inertia("gear1", J=J1, omega0=w1), side("sync1", 1.0),
             Inertia("shaft", J=Js, omega0=ws), side("sync2", -1.0),
             Inertia("gear2", J=J2, omega0=w2)]
    conn = [["gear1.b", "sync1.a"], ["sync1.b", "shaft.a", "sync2.b"], ["sync2.a", "gear2.b"]]
    if torque is not None:
        comps.append(TorqueSource("drive", input="tau"))
        conn.append(["drive.flange", "shaft.b"])
    return Network(comps, conn)


@pytest.mark.parametrize("side", [1, -1])
def test_the_force_sign_chooses_the_side_that_synchronises_in_the_closed_form_time(side):
    """Sleeve force ±600 N from 0.01 s: the side of its sign synchronises its gear with
    the shaft in J_eq·(Δω − w_sync)/T_cone (1e-9; within 1 % of J_eq·Δω/T_cone) and its
    dog engages; the other gear turns on untouched (its speed exact, its dog out).  Before
    the push (neutral) nothing moves; the momentum of the gear and shaft is kept."""
    J1, J2, Js, w1, w2, ws, F, w_sync = 0.02, 0.015, 0.05, 150.0, 10.0, 90.0, 600.0, 0.5
    net = _sleeve(J1, J2, Js, w1, w2, ws, w_sync)
    res = simulate(net.build({"f": 0.0}), (0.0, 0.2), {"f": Step(0.01, side * F)},
                   options=TIGHT)
    assert res.outcome == Outcome.COMPLETED, res.message
    me, other = ("sync1", "sync2") if side > 0 else ("sync2", "sync1")
    Jg, wg, og, wo = (J1, w1, "gear2", w2) if side > 0 else (J2, w2, "gear1", w1)
    gear = "gear1" if side > 0 else "gear2"
    T = MU * F * WEDGE
    J_eq = Jg * Js / (Jg + Js)
    dw = abs(wg - ws)
    [ev] = res.events
    assert ev.name == f"{me}: engage"
    assert ev.t - 0.01 == pytest.approx(J_eq * (dw - w_sync) / T, rel=1e-9)
    assert abs((ev.t - 0.01) / (J_eq * dw / T) - 1.0) < 0.01
    assert res[f"{me}.engaged"][-1] == 1.0
    assert np.all(res[f"{other}.engaged"] == 0.0)
    assert np.allclose(res[f"omega_{og}"], wo, rtol=1e-12, atol=0)
    neutral = res.t <= 0.01
    assert np.allclose(res[f"omega_{gear}"][neutral], wg, rtol=1e-12, atol=0)
    assert np.allclose(res["omega_shaft"][neutral], ws, rtol=1e-12, atol=0)
    L = Jg * res[f"omega_{gear}"] + Js * res["omega_shaft"]
    assert np.max(np.abs(L - (Jg * wg + Js * ws))) <= 1e-12 * (Jg * wg + Js * ws)
    after = res.t > ev.t + 1e-9
    assert np.allclose(res[f"omega_{gear}"][after], res["omega_shaft"][after], rtol=1e-12)


@settings(max_examples=15, deadline=None)
# all at rest at zero force: each cone starts locked at zero capacity and breaks away at t0
@example(J1=0.25, J2=0.25, Js=0.25, w1=0.0, w2=0.0, torque=1.0, w_sync=1.0, F=0.0,
         F_block=100.0, t_push=0.0)
@given(J1=st.floats(0.01, 0.3), J2=st.floats(0.01, 0.3), Js=st.floats(0.02, 0.3),
       w1=st.floats(-100.0, 100.0), w2=st.floats(-100.0, 100.0),
       torque=st.floats(-20.0, 20.0), w_sync=st.floats(0.05, 3.0),
       F=st.floats(-1000.0, 1000.0), F_block=st.floats(100.0, 600.0),
       t_push=st.floats(0.0, 0.1))
def test_only_the_pressed_side_engages_and_only_inside_its_blocker(J1, J2, Js, w1, w2,
                                                                   torque, w_sync, F,
                                                                   F_block, t_push):
    """Random inertias, speeds, shaft torque, blocker and sleeve force of either sign: the
    side of the force's sign is the only one that ever engages, and it engages only with
    its slip inside the blocker's window (its loss J_eq·w²/2 in W_sync, to 1e-6 of the
    window) and a force of at least F_block; the other side never carries a torque."""
    net = _sleeve(J1, J2, Js, w1, w2, 0.0, w_sync, F_block, torque=True)
    res = simulate(net.build({"f": 0.0, "tau": torque}), (0.0, 0.3),
                   {"f": Step(t_push, F), "tau": torque},
                   options=SolverOptions(rtol=1e-9, atol=1e-10, dt_out=1e-3, h_max=2e-3))
    assert res.outcome == Outcome.COMPLETED, res.message
    me, other = ("sync1", "sync2") if F >= 0.0 else ("sync2", "sync1")
    Jg = J1 if F >= 0.0 else J2
    assert np.all(res[f"{other}.engaged"] == 0.0)
    # a row followed by another at the same instant is the state before a reset (as the
    # physics checks read it): a cone at rest at zero force starts locked and is freed by
    # the event at t0, the row before it holding the lock's torque
    after = np.append(res.t[1:] != res.t[:-1], True)
    assert np.all(res[f"T_{other}"][after] == 0.0)
    if abs(F) < F_block:
        assert np.all(res[f"{me}.engaged"] == 0.0)
    if res[f"{me}.engaged"][-1] == 1.0:
        J_eq = Jg * Js / (Jg + Js)      # the shaft's other gear turns freely
        w_e = math.sqrt(2.0 * max(res["W_sync"][-1], 0.0) / J_eq)
        assert w_e <= w_sync * (1.0 + 1e-6) + 1e-9
        t_eng = res.t[np.argmax(res[f"{me}.engaged"] == 1.0)]
        assert t_eng >= t_push - 1e-12


def test_amt_upshift_through_one_sleeve_synchronises_in_the_closed_form_time():
    """examples/amt_upshift_sleeve.toml: +600 N hold first gear, 0 at 0.35 s (neutral:
    sync1 releases), -800 N from 0.40 s press second gear's cone; sync2 engages once after
    J_eq·(|Δω| − w_sync)/T_cone (1 %; the road load, which the closed form ignores, moves
    it by 0.4 %), J_eq the input side reflected to the idler in series with the car's
    reflected to the output shaft (as amt_upshift.toml); first gear's side never engages
    again; the energy balance closes."""
    from clutchsim.scenario import load_scenario, run_scenario
    res = run_scenario(load_scenario(EXAMPLES / "amt_upshift_sleeve.toml"), None).result
    assert res.status == "completed"
    ev = [(e.name, e.t) for e in res.events]
    assert ("sync1: release", pytest.approx(0.35, abs=1e-9)) in ev
    [t_eng] = [t for n, t in ev if n == "sync2: engage"]
    assert not [n for n, _ in ev if n == "sync1: engage"]
    assert np.all(res["sync1.engaged"][res.t > 0.35 + 1e-9] == 0.0)
    dw = abs(res["w_slip_sync2"][np.searchsorted(res.t, 0.4)])
    r1, r2, fd = 3.6, 2.1, 4.1
    J_in = 0.01 + (0.012 + 0.01 / r1**2) * r2**2
    J_out = 0.05 + (1.6 + 1300.0 * 0.3**2) / fd**2
    J_eq = J_in * J_out / (J_in + J_out)
    T_cone = MU * 800.0 * WEDGE
    assert abs((t_eng - 0.4) / (J_eq * (dw - 0.5) / T_cone) - 1.0) < 0.01
    bal = (res["W_in"] - res["W_friction"] - res["W_damping"] - res["W_road"] - res["W_sync"]
           - (res["E_kinetic"] - res["E_kinetic"][0]))
    assert np.max(np.abs(bal)) <= 1e-8 * res["W_in"][-1]


def test_a_side_other_than_plus_or_minus_one_is_refused(tmp_path, capsys):
    _bad_input(tmp_path, capsys, "amt_upshift_sleeve", "side = -1", "side = 0.5",
               ["component[9].side", "side = 0.5 must be +1 or -1"])
