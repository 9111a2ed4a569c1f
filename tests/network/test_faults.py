"""Faults (issue 39): time-triggered faults declared per component on clutches and brakes
(``fault_capacity_factor`` from ``fault_time`` on: stuck open, capacity loss, stuck locked)
and on spring-dampers (``fault_stiffness_loss``, ``fault_damping_loss`` over
``fault_duration``); docs/components.md, faults.  Each run's energy balance closes with the
fault's work booked; a stuck-locked clutch is a rigid joint; the fault is an event of the
run (what failed, when) and an output ``fault_<name>``."""

import math

import numpy as np
import pytest
from _dl_paths import EXAMPLES

from clutchsim.analysis.launch_metrics import energy_balance
from clutchsim.cli import main
from clutchsim.core import Ramp, SolverOptions, simulate
from clutchsim.friction import CoulombRobust
from clutchsim.network import Network
from clutchsim.network.components import (
    Clutch,
    Gearbox,
    Inertia,
    SpringDamper,
    ThermalNode,
    TorqueSource,
)
from clutchsim.network.components.friction import FAULT_LOCKED

OPTS = SolverOptions(rtol=1e-10, atol=1e-12, dt_out=1e-3)
JA, JB, TAU, LOAD, FC = 0.2, 0.5, 100.0, 20.0, 40.0


def rig(factor, t_fault=0.5, locked0=None):
    """Drive ``TAU`` on a; a coulomb-robust clutch (sliding ``FC``, static ``1.2·FC``) to b,
    which carries the load ``LOAD``."""
    return Network([TorqueSource("drive", input="tau"), Inertia("a", J=JA),
                    Clutch("clutch", CoulombRobust(F_c=FC, F_s=1.2 * FC), "cmd",
                           fault_time=t_fault, fault_capacity_factor=factor,
                           locked0=locked0),
                    Inertia("b", J=JB), TorqueSource("load", input="tl")],
                   [["drive.flange", "a.a"], ["a.b", "clutch.a"], ["clutch.b", "b.a"],
                    ["b.b", "load.flange"]], name="fault_rig")


def run(net, t_end=1.0):
    res = simulate(net.build(), (0.0, t_end), {"tau": TAU, "tl": -LOAD, "cmd": 1.0},
                   options=OPTS)
    assert res.status == "completed", res.message
    assert energy_balance(res)["energy_balance_rel"] < 1e-8
    return res


def test_stuck_locked_clutch_is_a_rigid_joint():
    """Slipping at its sliding capacity until the fault (0.5 s), the clutch seizes: the slip
    stops at once (momentum kept: the common speed is the momentum-weighted mean) and from
    there a and b turn as one body, ``(J_a + J_b)·dω/dt = τ − τ_load``."""
    res = run(rig(FAULT_LOCKED))
    t = res.t
    before = t < 0.5 - 1e-9
    wa, wb = res["omega_a"], res["omega_b"]
    assert np.allclose(wa[before], (TAU - FC) / JA * t[before], rtol=1e-8, atol=1e-9)
    assert np.allclose(wb[before], (FC - LOAD) / JB * t[before], rtol=1e-8, atol=1e-9)
    w_lock = (JA * (TAU - FC) / JA * 0.5 + JB * (FC - LOAD) / JB * 0.5) / (JA + JB)
    after = t > 0.5 + 1e-3
    rigid = w_lock + (TAU - LOAD) / (JA + JB) * (t[after] - 0.5)
    assert np.allclose(wa[after], rigid, rtol=1e-6)
    assert np.allclose(wb[after], rigid, rtol=1e-6)
    # the torque a rigid joint carries: b's share of the net torque plus the load (on a:
    # against its forward turning, T < 0)
    assert np.allclose(-res["T_friction_clutch"][after], JB * (TAU - LOAD) / (JA + JB) + LOAD,
                       rtol=1e-6)
    names = [e.name for e in res.events]
    assert "clutch: fault, stuck locked at 0.5 s" in names
    assert res["fault_clutch"][0] == 0.0 and res["fault_clutch"][-1] == 1.0


def test_stuck_open_clutch_carries_nothing_from_the_fault_on():
    res = run(rig(0.0, locked0=True), t_end=1.0)
    after = res.t > 0.5 + 1e-9
    assert np.all(res["T_friction_clutch"][after] == 0.0)
    slope = np.polyfit(res.t[after], res["omega_b"][after], 1)[0]
    assert slope == pytest.approx(-LOAD / JB, rel=1e-8)
    assert "clutch: fault, stuck open (no torque) at 0.5 s" in [e.name for e in res.events]


def test_capacity_loss_scales_the_sliding_torque():
    res = run(rig(0.5))
    after = res.t > 0.5 + 1e-9
    assert np.allclose(-res["T_friction_clutch"][after], 0.5 * FC, rtol=1e-9)
    assert np.allclose(res["capacity_clutch"][after], 0.5 * 1.2 * FC, rtol=1e-9)


WN = math.sqrt(1e4 * (1 / JA + 1 / JB))      # the two-mass mode before the fault [rad/s]


CAP, DT, JC = 500.0, 10.0, 0.3


def triggered_rig(shift=None, factor=0.5):
    """As :func:`rig`, with the clutch's heat into an adiabatic node (``CAP`` J/K, from
    20 °C) and a capacity loss triggered at ``20 + DT`` °C; b drives a gearbox (2.0, then
    1.5 from ``shift``) to c, which carries the load."""
    return Network([TorqueSource("drive", input="tau"), Inertia("a", J=JA),
                    Clutch("clutch", CoulombRobust(F_c=FC, F_s=1.2 * FC), "cmd",
                           heat=(("disc", 1.0),), fault_temperature=20.0 + DT,
                           fault_capacity_factor=factor),
                    ThermalNode("disc", capacity=CAP, theta0=20.0), Inertia("b", J=JB),
                    Gearbox("gb", (2.0, 1.5), shifts=() if shift is None else ((shift, 2),)),
                    Inertia("c", J=JC), TorqueSource("load", input="tl")],
                   [["drive.flange", "a.a"], ["a.b", "clutch.a"], ["clutch.b", "b.a"],
                    ["b.b", "gb.a"],
                    ["gb.b", "c.a"], ["c.b", "load.flange"]], name="fault_trigger_rig")


def test_temperature_triggered_fault_strikes_once_when_the_heat_says():
    """A slipping clutch heats an adiabatic node: ``C·ΔT = F_c·α·t²/2`` with the slip
    acceleration ``α = (τ − F_c)/J_a − (F_c − τ_l/r)/(J_b + J_c/r²)`` (the load through the
    gear of ratio r = 2), so the fault strikes at ``t* = sqrt(2·C·ΔT/(F_c·α))``, once, and
    from there the clutch slides at half its torque."""
    r = 2.0
    alpha = (TAU - FC) / JA - (FC - LOAD / r) / (JB + JC / r ** 2)
    t_star = math.sqrt(2.0 * CAP * DT / (FC * alpha))
    res = run(triggered_rig(), t_end=1.5)
    struck = [e for e in res.events if e.name.startswith("clutch: fault")]
    assert [e.name for e in struck] == [
        "clutch: fault, capacity x 0.5 when disc first exceeds 30 °C"]
    assert struck[0].t == pytest.approx(t_star, rel=1e-8)
    after = res.t > t_star + 1e-6
    assert np.allclose(-res["T_friction_clutch"][after], 0.5 * FC, rtol=1e-9)
    before = (res.t > 1e-6) & (res.t < t_star - 1e-6)     # at t = 0 it breaks away
    assert np.allclose(-res["T_friction_clutch"][before], FC, rtol=1e-9)
    assert res["fault_clutch"][0] == 0.0 and res["fault_clutch"][-1] == 1.0


def test_input_triggered_fault_strikes_where_the_signal_crosses_one_half():
    """``fault_input``: the fault strikes where its signal, a ramp from 0 at 0.3 s to 1 at
    0.7 s, first passes 0.5 (0.5 s, located), once, although the signal stays above."""
    net = Network([TorqueSource("drive", input="tau"), Inertia("a", J=JA),
                   Clutch("clutch", CoulombRobust(F_c=FC, F_s=1.2 * FC), "cmd",
                          fault_input="flag", fault_capacity_factor=0.25),
                   Inertia("b", J=JB), TorqueSource("load", input="tl")],
                  [["drive.flange", "a.a"], ["a.b", "clutch.a"], ["clutch.b", "b.a"],
                   ["b.b", "load.flange"]], name="fault_input_rig")
    res = simulate(net.build(), (0.0, 1.0), {"tau": TAU, "tl": -LOAD, "cmd": 1.0,
                                             "flag": Ramp(0.3, 0.4, 1.0)}, options=OPTS)
    assert res.status == "completed", res.message
    assert energy_balance(res)["energy_balance_rel"] < 1e-8
    struck = [e for e in res.events if e.name.startswith("clutch: fault")]
    assert [e.name for e in struck] == [
        "clutch: fault, capacity x 0.25 when flag first rises past 0.5"]
    assert struck[0].t == pytest.approx(0.5, abs=1e-9)
    after = res.t > 0.5 + 1e-6
    assert np.allclose(-res["T_friction_clutch"][after], 0.25 * FC, rtol=1e-9)


def test_a_gear_shift_after_a_triggered_fault_keeps_it_struck():
    """The gearbox's shift is a timed bank of all values; it must not undo the fault that
    its own event struck earlier (nor may the fault undo the shift)."""
    res = run(triggered_rig(shift=1.2), t_end=1.5)
    names = [e.name for e in res.events]
    assert names.index("clutch: fault, capacity x 0.5 when disc first exceeds 30 °C") < \
        next(i for i, n in enumerate(names) if n.startswith("gb"))
    after = res.t > 1.2 + 1e-6
    assert np.allclose(-res["T_friction_clutch"][after], 0.5 * FC, rtol=1e-9)
    assert np.allclose(res["ratio_gb"][after], 1.5)


def test_drag_increase_drags_the_open_clutch():
    """An open clutch (command 0) between a driven and a loaded side: no torque until the
    fault adds 5 N·m of drag, ``5·tanh(w/1 rad/s)``, booked as friction work."""
    net = Network([TorqueSource("drive", input="tau"), Inertia("a", J=JA),
                   Clutch("clutch", CoulombRobust(F_c=FC, F_s=1.2 * FC), "cmd",
                          fault_time=0.5, fault_drag=5.0),
                   Inertia("b", J=JB), TorqueSource("load", input="tl")],
                  [["drive.flange", "a.a"], ["a.b", "clutch.a"], ["clutch.b", "b.a"],
                   ["b.b", "load.flange"]], name="fault_drag")
    res = simulate(net.build(), (0.0, 1.0), {"tau": 10.0, "tl": 0.0, "cmd": 0.0},
                   options=OPTS)
    assert res.status == "completed", res.message
    assert energy_balance(res)["energy_balance_rel"] < 1e-8
    t, w = res.t, res["w_slip_clutch"]
    assert np.all(res["T_friction_clutch"][(t > 0.0) & (t < 0.5 - 1e-9)] == 0.0)  # (t = 0: stuck)
    after = t > 0.5 + 1e-9
    assert np.allclose(res["T_friction_clutch"][after], 5.0 * np.tanh(w[after]), rtol=1e-9)
    assert res["W_friction"][-1] > 0.0
    assert "clutch: fault, drag +5 N·m at 0.5 s" in [e.name for e in res.events]


def two_mass(loss_c=0.75, loss_d=0.0, d=0.0, dur=1e-4, t_fault=4 * math.pi / WN):
    return Network([Inertia("a", J=JA, omega0=0.0),
                    SpringDamper("spring", c=1e4, d=d, phi0=0.02, fault_time=t_fault,
                                 fault_stiffness_loss=loss_c, fault_damping_loss=loss_d,
                                 fault_duration=dur),
                    Inertia("b", J=JB)], [["a.b", "spring.a"], ["spring.b", "b.a"]],
                   name="fault_spring")


def test_stiffness_loss_books_the_released_energy_and_lowers_the_mode():
    """A free two-mass oscillator (``c`` = 1e4 N·m/rad, released from a twist of 0.02 rad)
    loses 75 % of its stiffness after two periods, at the twist's extreme, over 0.1 ms: the
    spring's energy ``c·φ²/2`` = 2 J drops by 75 % and that is booked in ``W_damping``
    (the fault's work, 1.5 J); the oscillation continues at ``sqrt(0.25·c·(1/J_a +
    1/J_b))``."""
    system = two_mass().build()
    res = simulate(system, (0.0, 0.5), {}, options=SolverOptions(rtol=1e-10, atol=1e-12,
                                                                 dt_out=1e-4))
    assert res.status == "completed", res.message
    assert energy_balance(res)["energy_balance_rel"] < 1e-8
    assert res["W_damping"][-1] == pytest.approx(0.75 * 0.5 * 1e4 * 0.02 ** 2, rel=1e-3)
    assert res["E_spring"][-1] + res["E_kinetic"][-1] == pytest.approx(0.5, rel=1e-3)
    # zero crossings of the twist after the fault: half periods of the softened spring
    phi, t = res["phi_spring"], res.t
    late = t > 4 * math.pi / WN + 1e-3
    s = np.sign(phi[late])
    cross = t[late][1:][np.diff(s) != 0]
    period = 2 * np.mean(np.diff(cross))
    wn = math.sqrt(0.25 * 1e4 * (1 / JA + 1 / JB))
    assert 2 * math.pi / period == pytest.approx(wn, rel=1e-3)
    names = [e.name for e in res.events]
    assert any(n.startswith("spring: fault starts, stiffness -75 %") for n in names), names
    assert res["fault_spring"][-1] == 1.0


def test_damping_loss_keeps_the_balance():
    res = simulate(two_mass(0.0, 0.9, d=5.0, dur=0.02).build(), (0.0, 0.3), {},
                   options=SolverOptions(rtol=1e-10, atol=1e-12, dt_out=1e-4))
    assert res.status == "completed", res.message
    assert energy_balance(res)["energy_balance_rel"] < 1e-8


@pytest.mark.parametrize("old, new, words", [
    ('[[component]]\ntype = "clutch"\nname = "clutch"\n',
     ('[[component]]\ntype = "clutch"\nname = "clutch"\nfault_time = 9.0\n'
      'fault_capacity_factor = 0.0\n'),
     ["bad.toml:", "fault_time", "= 9 s is outside the run", "[0, 4) s"]),
    ('[[component]]\ntype = "inertia"\nname = "disc"\n',
     '[[component]]\ntype = "inertia"\nname = "disc"\nfault_time = 1.0\n',
     ["bad.toml:", "fault_time", "cannot have one", "clutch, brake and spring_damper"]),
    ('[[component]]\ntype = "clutch"\nname = "clutch"\n',
     ('[[component]]\ntype = "clutch"\nname = "clutch"\nfault_time = 1.0\n'
      'fault_temperature = 250.0\nfault_capacity_factor = 0.5\n'),
     ["bad.toml:", "fault_temperature", "= 250 °C and fault_time = 1 s are 2 triggers"]),
    ('[[component]]\ntype = "clutch"\nname = "clutch"\n',
     ('[[component]]\ntype = "clutch"\nname = "clutch"\nfault_temperature = 250.0\n'),
     ["bad.toml:", "fault_temperature", "sets no fault to trigger"]),
    ('[[component]]\ntype = "clutch"\nname = "clutch"\n',
     ('[[component]]\ntype = "clutch"\nname = "clutch"\nfault_temperature = 250.0\n'
      'fault_capacity_factor = 0.5\n'),
     ["bad.toml:", "fault_temperature", "needs a thermal node (heat)"]),
    ('[[component]]\ntype = "clutch"\nname = "clutch"\n',
     ('[[component]]\ntype = "clutch"\nname = "clutch"\nfault_input = "throttle"\n'
      'fault_time = 1.0\nfault_capacity_factor = 0.5\n'),
     ["bad.toml:", "fault_input", "= 'throttle' and fault_time = 1 s are 2 triggers"]),
    ('[[component]]\ntype = "clutch"\nname = "clutch"\n',
     ('[[component]]\ntype = "clutch"\nname = "clutch"\nfault_input = "no_such"\n'
      'fault_capacity_factor = 0.5\n'),
     ["bad.toml:", "fault_input", "no_such"]),
])
def test_bad_faults_are_refused_with_key_file_and_line(tmp_path, capsys, old, new, words):
    text = (EXAMPLES / "launch_tyre.toml").read_text(encoding="utf-8")
    assert old in text
    path = tmp_path / "bad.toml"
    path.write_text(text.replace(old, new, 1), encoding="utf-8")
    code = main(["run", str(path), "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert code == 2, err
    assert "Traceback" not in err
    for w in words:
        assert w in err, (w, err)
    assert not (tmp_path / "o").exists()


def test_fault_appears_in_the_summary_report_and_time_series(tmp_path, capsys):
    """What failed and when: summary.json's "faults", a table of report.html, the run's
    event and the output fault_<name>."""
    import json

    import pandas as pd
    text = (EXAMPLES / "launch_tyre.toml").read_text(encoding="utf-8")
    old = '[[component]]\ntype = "clutch"\nname = "clutch"\n'
    path = tmp_path / "fault.toml"
    path.write_text(text.replace(old, old + "fault_time = 3.0\nfault_capacity_factor = 0.3\n"),
                    encoding="utf-8")
    out = tmp_path / "o"
    assert main(["run", str(path), "--out", str(out), "--no-plots", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["faults"] == [{"component": "clutch", "kind": "clutch",
                                  "fault": "capacity x 0.3 at 3 s", "time_s": 3.0}]
    assert "capacity x 0.3 at 3 s" in (out / "report.html").read_text(encoding="utf-8")
    ts = pd.read_csv(out / "timeseries.csv")
    col = next(c for c in ts.columns if c.startswith("fault_clutch"))
    assert ts[col].iloc[0] == 0.0 and ts[col].iloc[-1] == 1.0
    # 0.3 × 240 N·m still holds the car in first gear (2 events: lock-up, the fault)
    assert summary["models"]["coulomb-robust"]["events"] == 2
    assert summary["models"]["coulomb-robust"]["energy_balance_rel"] < 1e-8


@pytest.mark.parametrize("limit, struck", [(41.0, True), (1500.0, False)])
def test_triggered_fault_reports_when_it_struck_or_that_it_never_did(tmp_path, capsys,
                                                                     limit, struck):
    """summary.json's ``time_s`` of a temperature-triggered fault is its event's time in
    the run, and null where the temperature never got there."""
    import json
    text = (EXAMPLES / "hill_start.toml").read_text(encoding="utf-8")
    old = 'name = "clutch"\ntype = "clutch"\n'
    assert old in text
    path = tmp_path / "trig.toml"
    path.write_text(text.replace(old, old + f"fault_temperature = {limit}\n"
                                 "fault_capacity_factor = 0.9\n"), encoding="utf-8")
    out = tmp_path / "o"
    assert main(["run", str(path), "--out", str(out), "--no-plots", "--json", "--model",
                 "coulomb-robust"]) == 0
    summary = json.loads(capsys.readouterr().out)
    (fault,) = summary["faults"]
    assert fault["fault"] == f"capacity x 0.9 when pressure_plate first exceeds {limit:g} °C"
    ts = __import__("pandas").read_csv(out / "timeseries.csv")
    col = next(c for c in ts.columns if c.startswith("fault_clutch"))
    if struck:
        theta = next(c for c in ts.columns if c.startswith("theta_pressure_plate"))
        hot = ts["time [s]"][ts[theta] > limit].iloc[0]
        assert fault["time_s"] is not None and 0.0 < fault["time_s"] <= hot
        assert ts[col].iloc[-1] == 1.0
    else:
        assert fault["time_s"] is None
        assert ts[col].iloc[-1] == 0.0


@pytest.mark.parametrize("make, changes", [
    (lambda **v: Clutch("c", CoulombRobust(F_c=FC, F_s=1.2 * FC), "cmd", **v),
     {"fault_time": 0.5, "fault_capacity_factor": 0.5}),
    (lambda **v: Clutch("c", CoulombRobust(F_c=FC, F_s=1.2 * FC), "cmd", **v),
     {"drag": 2.0}),
    (lambda **v: SpringDamper("s", c=100.0, **v),
     {"fault_time": 0.5, "fault_stiffness_loss": 0.5}),
])
def test_with_values_gives_the_equations_construction_gives(make, changes):
    """A value that decides the equations (a fault, a drag) set by with_values gives the
    same structure and packed values as the component built with it (they were flags set
    once in __init__: a copy kept the equations of the values it was built with)."""
    built, changed = make(**changes), make().with_values(**changes)
    assert changed.options() == built.options()
    assert changed.pack().keys() == built.pack().keys()
