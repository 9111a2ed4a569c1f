"""The dog clutch's elastic teeth (issue 38: backlash and contact stiffness; docs/components.md,
"Dog clutch") against their closed forms:

* the free play: engaged in the centre of the gap with a slip ``w0``, the teeth cross
  half the gap in ``t1 = (backlash/2)/|w0|`` and the whole gap in ``backlash/|w0|``;
* the contact (no damping): a half period of the two-inertia oscillator on the contact
  stiffness, ``π/ω_n`` with ``ω_n = √(c·(J_a + J_b)/(J_a·J_b))``, after which the flanks
  part with the slip reversed; the peak tooth torque ``|w0|·√(c·J_eq)``; the momentum and
  the kinetic plus spring energy kept;
* with damping, a load held on the flank rings at the damped frequency
  ``ω_n·√(1 − ζ²)``, ``ζ = d/(2·√(c·J_eq))``, with the logarithmic decrement of the
  closed form;
* rigid teeth (the default) lock as before; bad input through a scenario file and the
  CLI.
"""

import itertools
import math
from pathlib import Path

import numpy as np
import pytest
from test_shift_elements import (
    test_bad_input_names_key_value_rule_file_and_line_and_exits_2 as _bad_input,
)

from clutchsim.core import Outcome, SolverOptions, simulate
from clutchsim.network import Network
from clutchsim.network.components import DogClutch, Inertia, TorqueSource

TIGHT = SolverOptions(rtol=1e-10, atol=1e-12, dt_out=1e-5)
EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _clean(res):
    assert res.outcome == Outcome.COMPLETED, res.message
    assert not [w for w in res.warnings if "physics check" in w], res.warnings


def _net(J_a, J_b, w_a, w_b, c, d, backlash, **kw):
    kw = {"window": 0.2, **kw}
    return Network([TorqueSource("drive", input="tau"), Inertia("a", J=J_a, omega0=w_a),
                    DogClutch("dog", "s", w_max=5.0, teeth=20, c_contact=c, d_contact=d,
                              backlash=backlash, **kw),
                    Inertia("b", J=J_b, omega0=w_b)],
                   [["drive.flange", "a.a"], ["a.b", "dog.a"], ["dog.b", "b.a"]])


def test_free_play_and_an_undamped_contact_in_closed_form():
    """Engaged at the centre of the gap (2·b = 0.02 rad) with a slip of 2 rad/s: the +flank
    touches at b/w0 = 5 ms, the contact lasts π/ω_n, the flanks part with the slip
    reversed, and the −flank is reached 2b/w0 = 10 ms later."""
    J_a, J_b, c, b2, w0 = 0.1, 0.3, 1e4, 0.02, 2.0
    J_eq = J_a * J_b / (J_a + J_b)
    wn = math.sqrt(c / J_eq)
    net = _net(J_a, J_b, 10.0, 10.0 + w0, c, 0.0, b2, engaged0=1)
    res = simulate(net.build({"s": 1.0, "tau": 0.0}), (0.0, 0.03), {"s": 1.0, "tau": 0.0},
                   options=TIGHT)
    _clean(res)
    up = [e.t for e in res.events if e.name == "dog: flank +backlash/2"]
    down = [e.t for e in res.events if e.name == "dog: flank -backlash/2"]
    t1 = 0.5 * b2 / w0
    t2 = t1 + math.pi / wn
    assert up[0] == pytest.approx(t1, rel=1e-9)
    assert up[1] == pytest.approx(t2, rel=1e-7)
    assert down[0] == pytest.approx(t2 + b2 / w0, rel=1e-7)
    # in the gap no torque; in contact the peak |w0|·√(c·J_eq)
    gap = res.t < t1 * (1.0 - 1e-6)
    assert np.all(res["T_teeth_dog"][gap] == 0.0) and np.all(res["contact_dog"][gap] == 0.0)
    assert np.max(res["T_teeth_dog"]) == pytest.approx(w0 * math.sqrt(c * J_eq), rel=1e-4)
    after = (res.t > t2 * (1.0 + 1e-6)) & (res.t < t2 + b2 / w0 * (1.0 - 1e-6))
    assert np.allclose(res["w_slip_dog"][after], -w0, rtol=1e-7)
    L = J_a * res["omega_a"] + J_b * res["omega_b"]
    assert np.max(np.abs(L - L[0])) <= 1e-12 * abs(L[0])
    E = res["E_kinetic"] + res["E_spring"]
    assert np.max(np.abs(E - E[0])) <= 1e-8 * E[0]
    assert np.all(res["W_damping"] == 0.0) and np.all(res["W_sync"] == 0.0)
    assert "dog.locked" not in res.signals


def test_a_load_on_the_flank_rings_at_the_damped_contact_frequency():
    """A torque of 50 N·m on side a, the teeth engaged on their −flank, deflected half the
    static deflection: the contact rings about its static deflection at
    ω_d = ω_n·√(1 − ζ²) (the slip's zero crossings half a period apart, 1e-6), its
    amplitude falling by e^{−ζ·π/√(1 − ζ²)} each half period (1e-4), inside its envelope
    about the static torque J_b/(J_a + J_b)·T; the torque's work is the kinetic and spring
    energy plus the damping's work."""
    J_a, J_b, c, d, b2, T = 0.1, 0.3, 2e4, 8.0, 0.01, 50.0
    J_eq = J_a * J_b / (J_a + J_b)
    wn = math.sqrt(c / J_eq)
    zeta = d / (2.0 * math.sqrt(c * J_eq))
    wd = wn * math.sqrt(1.0 - zeta**2)
    tau_s = -T * J_b / (J_a + J_b)              # the static tooth torque (on a)
    phi0 = -0.5 * b2 + 0.5 * tau_s / c          # half the static deflection
    net = _net(J_a, J_b, 0.0, 0.0, c, d, b2, engaged0=1, phi0=phi0)
    res = simulate(net.build({"s": 1.0, "tau": T}), (0.0, 0.08), {"s": 1.0, "tau": T},
                   options=TIGHT)
    _clean(res)
    assert [e.name for e in res.events] == []          # on the flank throughout
    assert np.all(res["contact_dog"] == -1.0)
    t, w = res.t, res["w_slip_dog"]
    i = np.flatnonzero((t[:-1] > 1e-4) & (w[:-1] * w[1:] < 0.0))
    zs = t[i] - w[i] * (t[i + 1] - t[i]) / (w[i + 1] - w[i])
    assert len(zs) >= 10
    assert np.allclose(np.diff(zs), math.pi / wd, rtol=1e-6)
    # the extremes of the spring's torque c·(s + b/2) = T_teeth − d·w about the static one
    spring = res["T_teeth_dog"] - d * w
    dev = np.array([np.max(np.abs(spring[(t > a) & (t < b)] - tau_s))
                    for a, b in itertools.pairwise(zs)])
    assert np.allclose(dev[1:] / dev[:-1], math.exp(-zeta * math.pi / math.sqrt(1 - zeta**2)),
                       rtol=1e-4)
    # inside the decaying envelope about the static torque
    env = 0.5 * abs(tau_s) * np.exp(-zeta * wn * t) / math.sqrt(1.0 - zeta**2)
    assert np.all(np.abs(spring - tau_s) <= env * (1.0 + 1e-6) + 1e-9)
    E = res["E_kinetic"] + res["E_spring"] + res["W_damping"]
    assert np.allclose(E, E[0] + np.cumsum(np.r_[0.0, 0.5 * T * np.diff(t)
                                                 * (res["omega_a"][1:] + res["omega_a"][:-1])]),
                       rtol=0.0, atol=1e-6 * E.max())


def test_elastic_teeth_engage_without_a_lock_and_rigid_teeth_lock():
    """Pushed in with a slip of 1 rad/s inside the window: rigid teeth lock (W_sync =
    J_eq·w²/2), elastic teeth enter the gap with the slip (no loss at engagement, no lock
    state)."""
    J_a, J_b = 0.1, 0.3
    J_eq = J_a * J_b / (J_a + J_b)
    rigid = Network([Inertia("a", J=J_a, omega0=10.0),
                     DogClutch("dog", "s", w_max=5.0, teeth=20, window=2.0 * math.pi / 20),
                     Inertia("b", J=J_b, omega0=11.0)], [["a.b", "dog.a"], ["dog.b", "b.a"]])
    res = simulate(rigid.build({"s": 1.0}), (0.0, 0.01), {"s": 1.0}, options=TIGHT)
    _clean(res)
    assert res["dog.locked"][-1] == 1.0
    assert res["W_sync"][-1] == pytest.approx(0.5 * J_eq * 1.0, rel=1e-9)
    net = _net(J_a, J_b, 10.0, 11.0, 1e4, 1.0, 0.02, window=2.0 * math.pi / 20)
    res = simulate(net.build({"s": 1.0, "tau": 0.0}), (0.0, 0.005), {"s": 1.0, "tau": 0.0},
                   options=TIGHT)
    _clean(res)
    assert res["dog.mode"][-1] == 0.0 and res["W_sync"][-1] == 0.0
    assert "dog.locked" not in res.signals


def test_the_teeth_refuse_free_play_without_stiffness_and_a_gap_wider_than_a_pitch():
    with pytest.raises(ValueError, match=r"backlash = 0\.01 needs a contact stiffness"):
        DogClutch("dog", "s", w_max=1.0, teeth=20, window=0.1, backlash=0.01)
    with pytest.raises(ValueError, match=r"backlash = 0\.4 rad must be < the tooth pitch"):
        DogClutch("dog", "s", w_max=1.0, teeth=20, window=0.1, backlash=0.4, c_contact=1e4)


BAD = [
    ("c_contact = 20000.0", "c_contact = -1.0",
     ["component[2].c_contact", "= -1.0 N·m/rad", "must be >= 0 N·m/rad"]),
    ("backlash = 0.02", "backlash = 0.5",
     ["component[2].backlash", "backlash = 0.5 rad must be < the tooth pitch"]),
]


@pytest.mark.parametrize(("old", "new", "words"), BAD, ids=[b[1] for b in BAD])
def test_bad_teeth_input_names_key_value_rule_file_and_line_and_exits_2(
        tmp_path, capsys, old, new, words):
    _bad_input(tmp_path, capsys, "dog_backlash", old, new, words)
