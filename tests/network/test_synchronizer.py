"""The synchroniser element of issue 38 (``network/components/synchronizer.py``) against its
closed forms (docs/components.md, "Synchronizer"):

* the synchronisation time of a cone between two free inertias, ``t = J_eq·(|Δω| −
  w_sync)/T_cone`` to the blocker's window, within 1 % of issue 38's ``J_eq·Δω/T_cone``;
  the angular momentum kept, the friction work ``J_eq·(Δω² − w_sync²)/2`` and the slip
  left ``J_eq·w_sync²/2`` in ``W_sync``;
* the blocker: a sleeve force below ``F_block`` synchronises and the cone sticks, but the
  dog stays out until the force passes the blocker; the engaged dog holds a torque far
  above the cone's capacity; the force taken off withdraws the sleeve;
* engagement at zero slip conserves the momentum (1e-9);
* a property test: the dog never engages outside the blocker's window or below its force;
* bad input through a scenario file and the CLI (key, value, rule, file, line; exit 2).
"""

import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from test_shift_elements import assert_one_body
from test_shift_elements import (
    test_bad_input_names_key_value_rule_file_and_line_and_exits_2 as _bad_input,
)

from clutchsim.core import Outcome, SolverOptions, simulate
from clutchsim.core.signals import Step
from clutchsim.friction import CoulombRobust, TanhFriction
from clutchsim.network import Network
from clutchsim.network.components import Inertia, Synchronizer, TorqueSource

TIGHT = SolverOptions(rtol=1e-9, atol=1e-10, dt_out=1e-4)
EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
R_M, ALPHA, MU = 0.04, 6.5, 0.1
WEDGE = R_M / math.sin(math.radians(ALPHA))


def _clean(res):
    assert res.outcome == Outcome.COMPLETED, res.message
    assert not [w for w in res.warnings if "physics check" in w], res.warnings


def _sync(w_sync, F_block, **kw):
    return Synchronizer("sync", CoulombRobust(F_c=MU, F_s=1.2 * MU), "f", R_m=R_M,
                        alpha=ALPHA, w_sync=w_sync, F_block=F_block, **kw)


def _events(res, name):
    return [e.t for e in res.events if e.name == f"sync: {name}"]


@pytest.mark.parametrize("w_sync", [1e-3, 0.5])
def test_synchronizer_synchronises_then_engages_in_the_closed_form_time(w_sync):
    """Issue 38: t = J_eq·Δω/T_cone within 1 %; exactly (1e-9) the time to the blocker's
    window J_eq·(Δω − w_sync)/T_cone; momentum kept to round-off; the friction work and
    the engagement's loss in closed form."""
    J1, J2, w1, w2, F = 0.02, 0.05, 150.0, 20.0, 600.0
    T = MU * F * WEDGE
    J_eq = J1 * J2 / (J1 + J2)
    dw = w1 - w2
    net = Network([Inertia("gear", J=J1, omega0=w1), _sync(w_sync, 300.0),
                   Inertia("shaft", J=J2, omega0=w2)],
                  [["gear.b", "sync.a"], ["sync.b", "shaft.a"]])
    res = simulate(net.build({"f": F}), (0.0, 0.15), {"f": F}, options=TIGHT)
    _clean(res)
    # (a window narrower than a step's reach may be crossed with the stop in one step:
    # then the stop engages the dog, at zero slip)
    assert [e.name for e in res.events] in (["sync: engage"], ["sync: stop"])
    t_e = res.events[0].t
    assert abs(t_e / (J_eq * dw / T) - 1.0) < 0.01
    if res.events[0].name == "sync: engage":
        assert t_e == pytest.approx(J_eq * (dw - w_sync) / T, rel=1e-9)
    else:
        assert t_e == pytest.approx(J_eq * dw / T, rel=1e-9)
    sliding = res.t < t_e - 1e-6
    assert np.allclose(res["T_sync"][sliding], -T, rtol=1e-12)     # w = ω_b − ω_a < 0
    assert res["capacity_sync"][0] == pytest.approx(1.2 * T, rel=1e-12)
    L = J1 * res["omega_gear"] + J2 * res["omega_shaft"]
    assert np.max(np.abs(L - (J1 * w1 + J2 * w2))) <= 1e-12 * (J1 * w1 + J2 * w2)
    assert res["omega_gear"][-1] == res["omega_shaft"][-1]
    assert res["sync.engaged"][-1] == 1.0 and res["sync.locked"][-1] == 1.0
    assert np.all(res["sync.engaged"][sliding] == 0.0)
    assert res["W_friction"][-1] + res["W_sync"][-1] == pytest.approx(0.5 * J_eq * dw**2,
                                                                      rel=1e-9)
    assert -1e-12 <= res["W_sync"][-1] <= 0.5 * J_eq * w_sync**2 * (1.0 + 1e-6)
    if w_sync == 0.5:
        assert res["W_sync"][-1] == pytest.approx(0.5 * J_eq * w_sync**2, rel=1e-6)


@pytest.mark.parametrize("tau", [-20.0, 20.0])
def test_a_free_cone_at_zero_slip_grips_in_the_direction_of_its_slip_when_pushed(tau):
    """An idle gear's synchroniser: at zero slip with no sleeve force it starts free (not
    stuck: a free cone holds nothing), its slip leaves zero either way while it carries
    nothing, and its mode follows nothing; when the sleeve pushes it (0.1 s), it grips in
    the direction of its slip, whichever mode it had (the cone's torque opposes the slip,
    no physics warning), and the dog engages once after J_eq·(|Δω| − w_sync)/T_cone."""
    J1, J2, w0, F = 0.02, 0.05, 100.0, 600.0
    T = MU * F * WEDGE
    J_eq = J1 * J2 / (J1 + J2)
    net = Network([Inertia("gear", J=J1, omega0=w0), _sync(0.5, 300.0),
                   Inertia("shaft", J=J2, omega0=w0), TorqueSource("src", input="tau")],
                  [["gear.b", "sync.a"], ["sync.b", "shaft.a"], ["src.flange", "gear.a"]])
    inputs = {"f": Step(0.1, F), "tau": Step(0.05, -tau, tau)}
    res = simulate(net.build({"f": 0.0, "tau": tau}), (0.0, 0.3), inputs, options=TIGHT)
    _clean(res)
    assert res["sync.locked"][0] == 0.0 and res["sync.engaged"][0] == 0.0
    dw = tau * 0.05 / J1                       # ω_gear − ω_shaft at the push
    assert res["w_slip_sync"][np.searchsorted(res.t, 0.1) - 1] == pytest.approx(-dw)
    pressed = (res.t > 0.1) & (res["sync.engaged"] == 0.0)
    assert np.all(res["T_sync"][pressed] * res["w_slip_sync"][pressed] > 0.0)
    assert _events(res, "engage") == [pytest.approx(0.1 + J_eq * (abs(dw) - 0.5) / T,
                                                    rel=1e-6)]
    L = J1 * res["omega_gear"] + J2 * res["omega_shaft"]
    assert L[-1] == pytest.approx((J1 + J2) * w0 + tau * 0.05, rel=1e-12)


def test_the_blocker_holds_the_sleeve_below_its_force_then_the_dog_holds_any_torque():
    """600 N against a 800 N blocker: the cone synchronises and sticks (stop at
    J_eq·Δω/T) but the dog stays out; at 0.12 s the force steps to 900 N: the dog engages
    at once (zero slip, W_sync 0).  At 0.15 s a torque of 10 times the cone's capacity
    turns both as one body; at 0.2 s the force is taken off and the sleeve is withdrawn."""
    J1, J2, w1, w2 = 0.02, 0.05, 150.0, 20.0
    T = MU * 600.0 * WEDGE
    J_eq = J1 * J2 / (J1 + J2)
    load = 10.0 * 1.2 * MU * 900.0 * WEDGE
    net = Network([TorqueSource("drive", input="tau"), Inertia("gear", J=J1, omega0=w1),
                   _sync(0.5, 800.0), Inertia("shaft", J=J2, omega0=w2)],
                  [["drive.flange", "gear.a"], ["gear.b", "sync.a"], ["sync.b", "shaft.a"]])
    force = Step(0.0, 600.0) + Step(0.12, 300.0) + Step(0.2, -900.0)
    tau = Step(0.15, load) + Step(0.2, -load)
    res = simulate(net.build({"f": 600.0, "tau": 0.0}), (0.0, 0.25),
                   {"f": force, "tau": tau}, options=TIGHT)
    _clean(res)
    assert [e.name for e in res.events] == ["sync: stop", "sync: engage", "sync: release"]
    assert _events(res, "stop")[0] == pytest.approx(J_eq * (w1 - w2) / T, rel=1e-9)
    assert _events(res, "engage") == [pytest.approx(0.12, abs=1e-12)]
    assert _events(res, "release") == [pytest.approx(0.2, abs=1e-12)]
    waiting = (res.t > 0.09) & (res.t < 0.12 - 1e-6)
    assert np.all(res["sync.engaged"][waiting] == 0.0)
    assert np.all(res["sync.locked"][waiting] == 1.0)
    held = (res.t > 0.15 + 1e-6) & (res.t < 0.2 - 1e-6)
    assert np.all(res["sync.engaged"][held] == 1.0)
    w_end = (J1 * w1 + J2 * w2) / (J1 + J2)
    assert np.allclose(res["omega_shaft"][held],
                       w_end + load * (res.t[held] - 0.15) / (J1 + J2), rtol=1e-9)
    assert np.allclose(res["T_sync"][held], -load * J2 / (J1 + J2), rtol=1e-9)
    assert abs(res["W_sync"][-1]) <= 1e-12
    assert res["sync.engaged"][-1] == 0.0 and res["sync.locked"][-1] == 0.0


def test_synchronizer_engagement_at_zero_slip_conserves_momentum():
    """Issue 38: both sides at one speed, the sleeve force passes the blocker at 0.02 s:
    the dog engages at once, no energy is lost, and with a torque on one side afterwards
    the two turn as one body: the momentum is L0 + ∫T dt within 1e-9."""
    J_a, J_b, w0, T = 0.2, 0.5, 50.0, 30.0
    net = Network([TorqueSource("drive", input="tau"), Inertia("a", J=J_a, omega0=w0),
                   _sync(0.5, 300.0), Inertia("b", J=J_b, omega0=w0)],
                  [["drive.flange", "a.a"], ["a.b", "sync.a"], ["sync.b", "b.a"]])
    res = simulate(net.build({"f": 0.0, "tau": 0.0}), (0.0, 0.2),
                   {"f": Step(0.02, 400.0), "tau": Step(0.05, T)}, options=TIGHT)
    _clean(res)
    # the dog goes in at the push: the blocker's event, or the free cone's stop there
    # (its grip, at zero slip inside the window: it engages the dog)
    [t_in] = [e.t for e in res.events if e.name in ("sync: engage", "sync: stop")]
    assert t_in == pytest.approx(0.02, abs=1e-12)
    assert res["sync.engaged"][np.searchsorted(res.t, t_in, "right") - 1] == 1.0
    assert res["W_sync"][-1] == pytest.approx(0.0, abs=1e-12)
    assert_one_body(res, J_a, J_b, w0, T, 0.05)


#: the largest step of the property test [s] (the event functions are checked at the ends
#: of the steps)
H_MAX = 2e-3


def _engagements_inside_the_blocker(J_a, J_b, w0, torque, w_sync, F, F_block, t_push,
                                    w_built=None):
    """Run a synchroniser pushed with F from t_push (the blocker's window ``w_built``, by
    default ``w_sync``); return the engagement times and whether each was inside the
    window ``w_sync`` and at a force of at least ``F_block``."""
    net = Network([TorqueSource("drive", input="tau"), Inertia("a", J=J_a, omega0=0.0),
                   _sync(w_sync if w_built is None else w_built, F_block),
                   Inertia("b", J=J_b, omega0=w0)],
                  [["drive.flange", "a.a"], ["a.b", "sync.a"], ["sync.b", "b.a"]])
    res = simulate(net.build({"f": 0.0, "tau": torque}), (0.0, 0.3),
                   {"f": Step(t_push, F), "tau": torque},
                   options=SolverOptions(rtol=1e-9, atol=1e-10, dt_out=H_MAX / 2.0,
                                         h_max=H_MAX))
    _clean(res)
    # a stop that engages the dog: read on the row its reset wrote (the last at its time;
    # the next row can lie past a later engage: a stop at 1e-12 s before a push at 1e-6 s)
    eng = _events(res, "engage") + [t for t in _events(res, "stop")
                                    if res["sync.engaged"][np.searchsorted(res.t, t,
                                                                           "right") - 1] == 1.0]
    # the slip at the engagement from its loss: the lock books J_eq·w²/2 in W_sync
    J_eq = J_a * J_b / (J_a + J_b)
    w_e = math.sqrt(2.0 * max(res["W_sync"][-1], 0.0) / J_eq)
    ok = [w_e <= w_sync * (1.0 + 1e-6) + 1e-9 and te >= t_push - 1e-12 and F >= F_block
          for te in eng]
    return res, eng, ok


@settings(max_examples=20, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(J_a=st.floats(0.02, 0.5), J_b=st.floats(0.02, 0.5), w0=st.floats(-100.0, 100.0),
       torque=st.floats(-20.0, 20.0), w_sync=st.floats(0.05, 3.0),
       F=st.floats(50.0, 1000.0), F_block=st.floats(100.0, 600.0),
       t_push=st.floats(0.0, 0.1))
def test_the_blocker_never_lets_the_dog_engage_outside_its_window(J_a, J_b, w0, torque,
                                                                    w_sync, F, F_block,
                                                                    t_push):
    """Random inertias, initial slip, drive torque, blocker window and force, sleeve force
    and push time.  At every engagement the slip was within the blocker's window, the
    sleeve pushed and its force past the blocker (the property fails with the blocker
    removed, a window of 1e3 rad/s: the dog then engages at the push, at any slip).  Once
    engaged the dog stays in (the force is held), and an engagement below F_block never
    happens."""
    res, eng, ok = _engagements_inside_the_blocker(J_a, J_b, w0, torque, w_sync, F, F_block,
                                                   t_push)
    assert len(eng) <= 1
    assert all(ok), (eng, ok)
    if eng:
        assert np.all(res["sync.engaged"][res.t > eng[0] + 1e-9] == 1.0)
    if F < F_block:
        assert np.all(res["sync.engaged"] == 0.0)


def test_the_synchronizer_refuses_another_friction_model_and_a_missing_blocker():
    with pytest.raises(ValueError, match=r"friction model 'tanh' must be coulomb-robust"):
        Synchronizer("sync", TanhFriction(F_c=0.1, v_t=0.5), "f", R_m=R_M, alpha=ALPHA,
                     w_sync=0.5, F_block=300.0)
    with pytest.raises(ValueError, match=r"parameter 'F_block' \[N\] is required"):
        Synchronizer("sync", CoulombRobust(F_c=0.1, F_s=0.1), "f", R_m=R_M, alpha=ALPHA,
                     w_sync=0.5)
    s = _sync(0.5, 300.0).with_values(alpha=30.0, F_block=100.0)
    assert s.model.block_scale == pytest.approx(100.0 * R_M / 0.5, rel=1e-12)


def test_the_example_synchronises_engages_and_withdraws():
    """examples/synchronizer.toml: pushed at 10 ms, engaged after J_eq·(Δω − w_sync)/T,
    withdrawn at 0.15 s; the energy balance closes."""
    from clutchsim.scenario import load_scenario, run_scenario
    run = run_scenario(load_scenario(EXAMPLES / "synchronizer.toml"), None)
    res = run.result
    _clean(res)
    J_eq = 0.02 * 0.05 / 0.07
    T = 0.1 * 600.0 * WEDGE
    assert [e.name for e in res.events] == ["sync: engage", "sync: release"]
    assert res.events[0].t == pytest.approx(0.01 + J_eq * (130.0 - 0.5) / T, rel=1e-9)
    assert res.events[1].t == pytest.approx(0.15, abs=1e-12)
    assert res["W_sync"][-1] == pytest.approx(0.5 * J_eq * 0.25, rel=1e-6)
    assert run.metrics["energy_balance_rel"] <= 1e-9


# ------------------------------------------------------------------ bad input, file and CLI
BAD = [
    # (old text, new text, words of the one error line)
    ("F_block = 300.0", "F_block = 0.0", ["component[1].F_block", "= 0.0 N", "must be > 0 N"]),
    ("w_sync = 0.5", "w_sync = -0.5",
     ["component[1].w_sync", "= -0.5 rad/s", "must be > 0 rad/s"]),
    ("alpha = 6.5", "alpha = 90.0", ["component[1].alpha", "= 90.0 °", "must be <= 89.9 °"]),
    ('model = "coulomb-robust", overrides = { F_c = 0.10, F_s = 0.12 }',
     'model = "tanh", overrides = { F_c = 0.10, v_t = 0.5, sigma2 = 0.0 }',
     ["component[1].friction", "friction model 'tanh' must be coulomb-robust"]),
]


@pytest.mark.parametrize(("old", "new", "words"), BAD, ids=[b[1] for b in BAD])
def test_bad_synchronizer_input_names_key_value_rule_file_and_line_and_exits_2(
        tmp_path, capsys, old, new, words):
    _bad_input(tmp_path, capsys, "synchronizer", old, new, words)


def test_a_synchronizer_without_a_blocker_force_is_refused_at_its_table(tmp_path, capsys):
    """Issue 38: "a synchronizer without a blocker force": the key, its meaning, the file
    and the line of the component's table; exit 2, nothing written."""
    from clutchsim.cli import main
    bad = (EXAMPLES / "synchronizer.toml").read_text(encoding="utf-8").replace(
        "F_block = 300.0\n", "", 1)
    path = tmp_path / "bad.toml"
    path.write_text(bad, encoding="utf-8")
    line = bad[:bad.index('type = "synchronizer"')].count("\n")       # [[component]]
    assert main(["run", str(path), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip().splitlines()[-1]
    assert err.startswith(f"clutchsim run: error: {path}:{line}: component[1]: missing "
                          "required key 'F_block' (Blocker force"), err
    assert not (tmp_path / "out").exists()
