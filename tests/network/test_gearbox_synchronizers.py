"""A gearbox whose shifts go through its synchronizers (`synchronizer` table of a `gearbox`,
clutchsim.scenario.composites; docs/components.md, "Gearbox with synchronizers")."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from test_shift_elements import (
    test_bad_input_names_key_value_rule_file_and_line_and_exits_2 as _bad_input,
)

from clutchsim.scenario import load_scenario, run_scenario
from clutchsim.scenario.composites import Expansion, expand

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
R_M, ALPHA, MU = 0.04, 6.5, 0.1
WEDGE = R_M / math.sin(math.radians(ALPHA))
R1, R2, FD = 3.6, 2.1, 4.1


def _balance(res) -> float:
    bal = (res["W_in"] - res["W_friction"] - res["W_damping"] - res["W_road"] - res["W_sync"]
           - (res["E_kinetic"] - res["E_kinetic"][0]))
    return float(np.max(np.abs(bal)) / res["W_in"][-1])


def _blocker_held(res, name: str, w_sync: float) -> None:
    """Every engagement of ``name`` happened inside the blocker's window (the slip on the
    row the integrator writes at the event, before its reset)."""
    for e in res.events:
        if e.name == f"{name}: engage":
            before = res[f"w_slip_{name}"][np.flatnonzero(res.t == e.t)[0]]
            assert abs(before) <= w_sync * (1.0 + 1e-6), (e.t, before)


def test_the_gearbox_builds_the_synchronizers_written_by_hand():
    """examples/amt_upshift_gearbox.toml (one `gearbox` with a `synchronizer` table) and
    examples/amt_upshift_sleeve.toml (pinions, idlers and a double-sided sleeve by hand)
    are the same car and the same shift: the same events at the same times and the same
    speeds (bit for bit: the same equations), the energy balance closed."""
    by = {}
    for name in ("amt_upshift_gearbox", "amt_upshift_sleeve"):
        res = run_scenario(load_scenario(EXAMPLES / f"{name}.toml"), None).result
        assert res.status == "completed", res.message
        assert not res.warnings
        by[name] = res
    made, hand = by["amt_upshift_gearbox"], by["amt_upshift_sleeve"]
    rename = {"gearbox_sync1": "sync1", "gearbox_sync2": "sync2"}
    events = [(re.sub(r"gearbox_sync\d", lambda m: rename[m.group(0)], e.name), e.t)
              for e in made.events]
    assert events == [(e.name, e.t) for e in hand.events]
    for col in ("omega_engine", "omega_input_shaft", "omega_output", "omega_wheels",
                "W_friction", "E_kinetic"):
        assert np.allclose(made[col], hand[col], rtol=1e-12, atol=1e-12), col
    assert np.allclose(made["omega_gearbox_idler2"], hand["omega_idler2"], rtol=1e-12)
    assert _balance(made) <= 1e-8
    _blocker_held(made, "gearbox_sync2", 0.5)


@settings(max_examples=8, deadline=None)
@given(force=st.floats(600.0, 2000.0), neutral=st.floats(0.005, 0.08),
       J_idler=st.floats(0.0, 0.02), shift=st.floats(0.31, 0.36))
def test_a_shift_synchronises_in_the_closed_form_time_and_engages_inside_the_blocker(
        force, neutral, J_idler, shift):
    """Any sleeve force above the blocker's, time in neutral, idler inertia and shift time
    (the clutch open): first gear's sleeve comes out at the shift, second gear's engages
    once, inside the blocker's window, after J_eq·(|Δω| − w_sync)/T_cone from the push
    (1 %: the road load is left out of the closed form; it slows the car by 1 % of the
    slip over a synchronisation of 0.3 s, 400 N: from 600 N), J_eq the input side (input
    shaft, both idlers) reflected to the idler in series with the car at the output shaft;
    the mode of every synchroniser agrees with its slip (the run's invariants) and the
    energy balance closes."""
    sc = load_scenario(EXAMPLES / "amt_upshift_gearbox.toml", overrides=[
        f"component[4].synchronizer.force={force!r}",
        f"component[4].synchronizer.neutral={neutral!r}",
        f"component[4].synchronizer.J_idler={J_idler!r}",
        f"component[4].shifts[0].time={shift!r}"])
    res = run_scenario(sc, None).result
    assert res.status == "completed", res.message
    assert not res.warnings
    ev = [(e.name, e.t) for e in res.events]
    assert ("gearbox_sync1: release", pytest.approx(shift, abs=1e-9)) in ev
    [t_eng] = [t for n, t in ev if n == "gearbox_sync2: engage"]
    assert not [n for n, _ in ev if n == "gearbox_sync1: engage"]
    _blocker_held(res, "gearbox_sync2", 0.5)
    push = shift + neutral
    dw = abs(float(np.interp(push, res.t, res["w_slip_gearbox_sync2"])))
    J_in = J_idler + (0.012 + J_idler / R1**2) * R2**2
    J_out = 0.05 + (1.6 + 1300.0 * 0.3**2) / FD**2
    J_eq = J_in * J_out / (J_in + J_out)
    assert abs((t_eng - push) / (J_eq * (dw - 0.5) / (MU * force * WEDGE)) - 1.0) < 0.01
    assert np.all(res["gearbox_sync2.engaged"][res.t > t_eng + 1e-9] == 1.0)
    assert _balance(res) <= 1e-8


def test_an_upshift_and_back_down_grips_each_cone_in_the_direction_of_its_slip(tmp_path):
    """amt_upshift_gearbox.toml with a second shift back to first gear at 0.62 s (the
    clutch still open): first gear's cone, free since 0.35 s (its slip passed zero with no
    force), is pushed at 0.67 s against the other sign of slip than its mode had; it grips
    in its slip's direction at once (its stop at the push), accelerates the input side and
    engages once, inside the blocker; second gear releases at 0.62 s; every pressed cone
    slides with its slip, no warning, the energy balance closes."""
    text = (EXAMPLES / "amt_upshift_gearbox.toml").read_text(encoding="utf-8")
    one = "shifts = [{ time = 0.35, gear = 2 }]"
    assert one in text
    path = tmp_path / "down.toml"
    path.write_text(text.replace(one, one[:-1] + ", { time = 0.62, gear = 1 }]"),
                    encoding="utf-8")
    res = run_scenario(load_scenario(path), None).result
    assert res.status == "completed", res.message
    assert not res.warnings
    ev = [(e.name, e.t) for e in res.events]
    assert ("gearbox_sync2: release", pytest.approx(0.62, abs=1e-9)) in ev
    assert ("gearbox_sync1: stop", pytest.approx(0.67, abs=1e-9)) in ev      # the grip
    assert [n for n, _ in ev].count("gearbox_sync1: engage") == 1
    assert [n for n, _ in ev].count("gearbox_sync2: engage") == 1
    for name in ("gearbox_sync1", "gearbox_sync2"):
        _blocker_held(res, name, 0.5)
        pressed = (res[f"{name}.locked"] == 0.0) & (res[f"capacity_{name}"] > 0.0)
        assert np.all(res[f"T_{name}"][pressed] * res[f"w_slip_{name}"][pressed] >= 0.0)
    assert res["gearbox_sync1.engaged"][-1] == 1.0 and res["gearbox_sync2.engaged"][-1] == 0.0
    assert _balance(res) <= 1e-8


def test_an_upshift_of_a_chain_file_through_its_synchronizers():
    """examples/shift_1_2_synchronized.toml (a chain file, five gears, mesh efficiency
    0.95 in the final drive): both friction models of the file complete without a warning;
    the four idle synchronisers start at rest with no force, free (not stuck), and every
    pressed cone slides with its slip (the grip at the push); first gear comes out at
    3.0 s, second
    engages once, inside its blocker, before the clutch closes; after it the input turns at
    second gear's ratio of the final drive's input, and the energy balance closes."""
    sc = load_scenario(EXAMPLES / "shift_1_2_synchronized.toml")
    for model in sc.models:
        run = run_scenario(sc, model)
        res = run.result
        assert res.status == "completed", res.message
        assert not res.warnings, res.warnings
        names = [e.name for e in res.events]
        assert names.count("gearbox_sync2: engage") == 1
        assert not [n for n in names if n.endswith(": engage") and "sync2" not in n]
        [t_eng] = [e.t for e in res.events if e.name == "gearbox_sync2: engage"]
        assert 3.02 < t_eng < 3.2
        _blocker_held(res, "gearbox_sync2", 0.5)
        for k in range(1, 6):
            mode, slip = res[f"gearbox_sync{k}.mode"], res[f"w_slip_gearbox_sync{k}"]
            pressed = (res[f"gearbox_sync{k}.locked"] == 0.0) & (
                res[f"capacity_gearbox_sync{k}"] > 0.0)
            assert np.all(mode[pressed] * slip[pressed] >= -1e-9), k
        late = res.t > t_eng + 0.01
        w_in, w_fd = res["omega_gearbox_input"][late], res["omega_final_drive"][late]
        assert np.allclose(w_in, R2 * FD * w_fd, rtol=1e-9, atol=1e-9)
        assert run.metrics["energy_balance_rel"] <= 1e-8


def test_the_expansion_maps_every_generated_key_back_to_the_gearbox():
    data = {"component": [
        {"type": "inertia", "name": "shaft", "J": 0.01, "omega0": 300.0},
        {"type": "gearbox", "name": "gb", "ratios": [3.0, 2.0], "final_drive": 4.0,
         "efficiency": 0.9, "shifts": [{"time": 1.0, "gear": 2}],
         "synchronizer": {"force": 800.0, "J_idler": 0.01, "R_m": 0.04, "alpha": 6.5,
                          "w_sync": 0.5, "F_block": 300.0,
                          "friction": {"model": "coulomb-robust"}}},
        {"type": "inertia", "name": "out", "J": 0.1, "omega0": 25.0}],
        "network": {"connect": [["shaft.b", "gb.a"], ["gb.b", "out.a"]]}}

    def fail(problem, key=""):
        raise AssertionError((problem, key))
    ex = expand(data, fail)
    assert isinstance(ex, Expansion)
    comps = {t["name"]: t for t in ex.data["component"]}
    assert comps["gb"]["type"] == "lossy_gear" and comps["gb"]["ratio"] == 4.0
    assert comps["gb"]["loss_table"]["eta_mf1"] == [0.9]
    assert comps["gb_idler1"]["omega0"] == 100.0 and comps["gb_idler2"]["omega0"] == 150.0
    assert comps["gb_sync1"]["engaged0"] == 1 and "engaged0" not in comps["gb_sync2"]
    assert ex.inputs == {"gb_sleeve1": "800.0 - step(1.0, 800.0)",
                         "gb_sleeve2": "step(1.05, 800.0)"}
    index = {t["name"]: j for j, t in enumerate(ex.data["component"])}
    assert ex.source_key(f"component[{index['gb_sync2']}].R_m") == \
        "component[1].synchronizer.R_m"
    assert ex.source_key(f"component[{index['gb_sync2']}].friction.overrides.F_c") == \
        "component[1].synchronizer.friction.overrides.F_c"
    assert ex.source_key(f"component[{index['gb_gear2']}].ratio") == "component[1].ratios[1]"
    assert ex.source_key(f"component[{index['gb_idler1']}].J") == \
        "component[1].synchronizer.J_idler"
    assert ex.source_key("component[1].ratio") == "component[1].final_drive"
    assert ex.source_key("component[1].loss_table.eta_mf1[0]") == "component[1].efficiency"
    assert ex.source_key("component[2].J") == "component[2].J"
    assert ex.source_key("inputs.x") == "inputs.x"
    connect = ex.data["network"]["connect"]
    assert ["shaft.b", "gb_gear1.a"] in connect and ["gb_gear1.a", "gb_gear2.a"] in connect
    assert ["gb_sync1.b", "gb_sync2.b", "gb.a"] in connect
    assert ["gb.b", "out.a"] in connect
    # a document without one is returned as it is
    plain = {"component": [data["component"][0]], "network": {"connect": []}}
    assert expand(plain, fail).data is plain


SYNC = ("synchronizer = { force = 800.0, neutral = 0.05, J_idler = 0.01, R_m = 0.04, "
        "alpha = 6.5, w_sync = 0.5, F_block = 300.0, friction = { model = \"coulomb-robust\", "
        "overrides = { F_c = 0.10, F_s = 0.12 } } }")
CHAIN_SYNC = ("synchronizer = { force = 1000.0, neutral = 0.02, J_idler = 0.005, R_m = 0.04, "
              "alpha = 6.5, w_sync = 0.5, F_block = 300.0, friction = { model = "
              "\"coulomb-robust\", overrides = { F_c = 0.10, F_s = 0.12 } } }")
CLUTCH = 'clutch_command = "1.0 - ramp(0.2, 0.1, 1.0) + ramp(0.8, 0.3, 1.0)"'
BAD = [
    ("amt_upshift_gearbox", SYNC, SYNC.replace("force = 800.0", "force = 250.0"),
     ["component[4].synchronizer.force", "= 250 N must be > F_block = 300 N"]),
    ("amt_upshift_gearbox", SYNC, SYNC.replace("force = 800.0, ", ""),
     ["component[4].synchronizer", "missing required key 'force'", "> F_block"]),
    ("amt_upshift_gearbox", SYNC, SYNC.replace("R_m = 0.04", "R_n = 0.04"),
     ["component[4].synchronizer.R_n", "unknown key"]),
    ("amt_upshift_gearbox", SYNC, SYNC.replace("alpha = 6.5", "alpha = 95.0"),
     ["component[4].synchronizer.alpha", "95"]),
    ("amt_upshift_gearbox", SYNC, SYNC.replace("J_idler = 0.01", "J_idler = -0.01"),
     ["component[4].synchronizer.J_idler", "must be >= 0"]),
    ("amt_upshift_gearbox", SYNC, SYNC.replace("neutral = 0.05", "neutral = -1.0"),
     ["component[4].synchronizer.neutral", "= -1.0 s is out of range: must be > 0 s"]),
    ("amt_upshift_gearbox", SYNC, SYNC.replace("neutral = 0.05", "neutral = 0.0"),
     ["component[4].synchronizer.neutral", "= 0.0 s is out of range: must be > 0 s"]),
    ("amt_upshift_gearbox", "shifts = [{ time = 0.35, gear = 2 }]",
     "shifts = [{ time = 0.35, gear = 2 }, { time = 0.38, gear = 1 }]",
     ["component[4].shifts[1].time", "must be later than the previous shift's"]),
    ("amt_upshift_gearbox", "shifts = [{ time = 0.35, gear = 2 }]",
     "shifts = [{ time = 0.35, gear = 1 }]",
     ["component[4].shifts[0].gear", "gear 1 is engaged already at 0.35 s"]),
    ("amt_upshift_gearbox", "shifts = [{ time = 0.35, gear = 2 }]",
     "shifts = [{ time = 0.35, gear = 3 }]",
     ["component[4].shifts[0].gear", "gear 3 does not exist"]),
    ("amt_upshift_gearbox", CLUTCH, CLUTCH + '\ngearbox_sleeve2 = "0.0"',
     ["inputs.gearbox_sleeve2", "is the sleeve force signal that gearbox 'gearbox' makes"]),
    ("amt_upshift_gearbox", 'name = "output"', 'name = "gearbox_gear1"',
     ["component[5].name", "= 'gearbox_gear1' is a name that gearbox 'gearbox' gives"]),
    ("shift_1_2_synchronized", CHAIN_SYNC, CHAIN_SYNC.replace("force = 1000.0", "force = 0.0"),
     ["coupling[2].synchronizer.force", "= 0.0 N is out of range: must be > 0 N"]),
    ("shift_1_2_synchronized", CHAIN_SYNC, CHAIN_SYNC.replace("force = 1000.0", "force = 300.0"),
     ["coupling[2].synchronizer.force", "= 300 N must be > F_block = 300 N"]),
    ("shift_1_2_synchronized", CHAIN_SYNC, CHAIN_SYNC.replace("force = 1000.0", "forse = 1000.0"),
     ["coupling[2].synchronizer.forse", "unknown key 'forse'", "force", "neutral", "J_idler",
      "R_m", "F_block"]),
    ("shift_1_2_synchronized", CHAIN_SYNC, CHAIN_SYNC.replace("R_m = 0.04", "R_m = 0.0"),
     ["coupling[2].synchronizer.R_m", "R_m"]),
    ("shift_1_2_synchronized", "efficiency = 0.95",
     "efficiency = 0.95\ndrag_torque = 2.0",
     ["coupling[2].drag_torque", "a gearbox with a synchronizer has no drag torque"]),
]


@pytest.mark.parametrize(("example", "old", "new", "words"), BAD,
                         ids=[f"{b[0]}:{b[3][0]}:{i}" for i, b in enumerate(BAD)])
def test_bad_synchronizer_input_names_key_value_rule_file_and_line(
        tmp_path, capsys, example, old, new, words):
    _bad_input(tmp_path, capsys, example, old, new, words)
