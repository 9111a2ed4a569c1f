"""The wet multi-plate clutch (issue 38, item 3; docs/components.md, "Wet multi-plate
clutch") against its closed forms.

* open-pack drag: the Couette torque of the oil films ``N·π·η·w·(r_o⁴ − r_i⁴)/(2h)`` at
  every output (1e-9), and the slip of two free inertias it couples decaying as
  ``w0·exp(−c·t/J_eq)`` with the drag work ``J_eq·w0²/2·(1 − exp(−2ct/J_eq))``;
* film shrinkage: the drag curve linear up to ``w_c = sqrt(20·ν·q/(π·h³))/r_o``, its peak
  there, the decline ``k·ν·(c²ν²/w³ − r_i⁴·w)`` and the mist's share above
  ``sqrt(c·ν)/r_i``, each at the outputs (1e-9);
* viscosity: Walther's equation (ASTM D341) through the two data-sheet points, straight in
  ``log log(ν + 0.7)`` against ``log T``;
* engagement: the capacity ``N·μ_s·max(0, p·A − F0 − k·stroke)·R_m``, and through a
  hydraulic actuator's lagged pressure (the fill) from the kiss point on;
* a launch whose energy balance closes, with the drag heating the oil and the friction the
  plates (``C·Δθ`` = the work of each);
* bad input, from Python and from a scenario file through ``clutchsim run``.
"""

import math
from pathlib import Path

import numpy as np
import pytest

from clutchsim.analysis.launch_metrics import energy_balance
from clutchsim.core import Outcome, SolverOptions, simulate
from clutchsim.friction import CoulombRobust
from clutchsim.network import Network
from clutchsim.network.components import (
    Inertia,
    ThermalNode,
    TorqueSource,
    WetClutch,
)
from clutchsim.network.components.wet_clutch import couette_drag, walther_nu

TIGHT = SolverOptions(rtol=1e-10, atol=1e-10, dt_out=1e-3)
EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
#: a DCT-sized pack (examples/wet_dct_upshift.toml)
PACK = {"interfaces": 8, "r_inner": 0.075, "r_outer": 0.095, "piston_area": 6e-3,
        "spring_preload": 600.0, "spring_rate": 3e4, "stroke": 1.5e-3, "gap": 0.15e-3}
MU_S = 0.13


def _clutch(**kw):
    return WetClutch("wc", CoulombRobust(F_c=0.12, F_s=MU_S), "p", **{**PACK, **kw})


def _clean(res):
    assert res.outcome == Outcome.COMPLETED, res.message
    assert not [w for w in res.warnings if "physics check" in w], res.warnings
    assert energy_balance(res)["energy_balance_rel"] < 1e-8


def _eta(wc, theta):
    return wc.density * walther_nu(theta, *_walther(wc)) * 1e-6


def _walther(wc):
    """A and B of ``log10 log10(ν + 0.7) = A − B·log10 T`` solved here from the two points."""
    y = [math.log10(math.log10(v + 0.7)) for v in (wc.nu40, wc.nu100)]
    x = [math.log10(t + 273.15) for t in (40.0, 100.0)]
    B = (y[0] - y[1]) / (x[1] - x[0])
    return y[0] + B * x[0], B


@pytest.mark.parametrize("flow", [0.0, 5e-3])
def test_open_pack_drag_is_the_couette_torque_and_decays_the_slip_exponentially(flow):
    """Flooded (flow 0), or a flow whose critical speed (here ~3000 rad/s) is far above the
    slip: the full film.  Two free inertias: ``J_eq·dw/dt = −c·w``."""
    J1, J2, w0, theta = 0.05, 0.02, 200.0, 40.0
    wc = _clutch(flow=flow, oil_temperature=theta)
    net = Network([Inertia("a", J=J1, omega0=w0), wc, Inertia("b", J=J2)],
                  [["a.b", "wc.a"], ["wc.b", "b.a"]])
    res = simulate(net.build({"p": 0.0}), (0.0, 0.5), {"p": 0.0}, options=TIGHT)
    _clean(res)
    eta = _eta(wc, theta)
    w = res["w_slip_wc"]
    closed = np.array([couette_drag(x, eta, PACK["gap"], PACK["r_inner"], PACK["r_outer"],
                                    PACK["interfaces"]) for x in w])
    # couette_drag is the textbook formula; the plant's torque is its own expression
    assert np.max(np.abs(res["T_drag_wc"] - closed)) <= 1e-9 * np.max(np.abs(closed))
    assert np.all(res["r_film_wc"] == PACK["r_outer"])
    c = PACK["interfaces"] * math.pi * eta * (PACK["r_outer"] ** 4 - PACK["r_inner"] ** 4) / (
        2.0 * PACK["gap"])
    J_eq = J1 * J2 / (J1 + J2)
    t = res.t
    assert np.max(np.abs(w + w0 * np.exp(-c * t / J_eq))) <= 1e-7 * w0
    work = 0.5 * J_eq * w0 ** 2 * (1.0 - np.exp(-2.0 * c * t / J_eq))
    assert np.max(np.abs(res["W_drag_wc"] - work)) <= 1e-7 * work[-1]
    # the drag is viscous: W_damping holds it, and nothing is friction
    assert np.allclose(res["W_damping"], res["W_drag_wc"], rtol=1e-12, atol=1e-12)
    assert np.all(res["W_friction"] == 0.0) and np.all(res["F_clamp_wc"] == 0.0)


def _sweep(**kw):
    """The slip swept from 0 by a torque on an inertia against the grounded pack."""
    wc = _clutch(**kw)
    net = Network([TorqueSource("drive", input="tau"), Inertia("rotor", J=0.1), wc],
                  [["drive.flange", "rotor.a"], ["rotor.b", "wc.b"], ["wc.a", "ground"]])
    opts = SolverOptions(rtol=1e-10, atol=1e-10, dt_out=2e-4)
    res = simulate(net.build({"p": 0.0, "tau": 60.0}), (0.0, 0.6), {"p": 0.0, "tau": 60.0},
                   options=opts)
    _clean(res)
    return wc, res


@pytest.mark.parametrize("mist", [0.0, 0.1])
def test_drag_is_linear_up_to_the_critical_speed_peaks_there_and_declines(mist):
    """Film shrinkage (2 l/min, 80 °C): the closed forms of each branch at every output;
    the peak at w_c within one output step."""
    theta, flow = 80.0, 3.3e-5
    wc, res = _sweep(flow=flow, mist=mist, oil_temperature=theta)
    n, ri, ro, h = PACK["interfaces"], PACK["r_inner"], PACK["r_outer"], PACK["gap"]
    eta = _eta(wc, theta)
    nu = eta / wc.density
    a = 20.0 * nu * (flow / n) / (math.pi * h ** 3)        # r_e²·w² [m²/s²]
    w_c, w_i = math.sqrt(a) / ro, math.sqrt(a) / ri
    K = n * math.pi * eta / (2.0 * h)
    w = res["w_slip_wc"]
    assert w[-1] > 1.5 * w_i                 # the sweep crosses every branch
    full = K * w * (ro ** 4 - ri ** 4)
    ws = np.maximum(w, w_c)             # (the shrinking branch is read above w_c only)
    shrink = K * ((1.0 - mist) * a * a / ws ** 3 - ri ** 4 * ws + mist * ro ** 4 * ws)
    empty = K * mist * w * (ro ** 4 - ri ** 4)
    closed = np.where(w <= w_c, full, np.where(w < w_i, shrink, empty))
    T = res["T_drag_wc"]
    assert np.max(np.abs(T - closed)) <= 1e-9 * np.max(closed)
    # linear at low speed: T/w is the Couette constant below w_c
    low = (w > 1.0) & (w < 0.9 * w_c)
    assert np.allclose(T[low] / w[low], K * (ro ** 4 - ri ** 4), rtol=1e-9)
    # the peak: at w_c (within the slip's change over one output step), of the full film
    k = int(np.argmax(T))
    dw = np.max(np.diff(w))
    assert abs(w[k] - w_c) <= dw
    assert T[k] == pytest.approx(K * w_c * (ro ** 4 - ri ** 4), rel=2 * dw / w_c)
    # it declines from there until the film is gone, then grows with the mist alone
    dec = (w > w_c) & (w < w_i)
    assert np.all(np.diff(T[dec]) < 0.0)
    assert np.allclose(res["r_film_wc"][w >= w_i], ri, rtol=1e-12)
    assert np.allclose(res["r_film_wc"][dec], np.sqrt(a) / w[dec], rtol=1e-9)


def test_viscosity_follows_walther_through_the_data_sheet_points():
    """ASTM D341: ν(40 °C) = nu40 and ν(100 °C) = nu100; log10 log10(ν + 0.7) is a straight
    line in log10 T (here at -20, 20, 60 and 150 °C against the line through the points);
    the plant's ν at a warming oil node is the law at the node's temperature."""
    wc = _clutch(nu40=29.6, nu100=6.0)
    assert wc.nu(40.0) == pytest.approx(29.6, rel=1e-12)
    assert wc.nu(100.0) == pytest.approx(6.0, rel=1e-12)
    A, B = _walther(wc)
    for theta in (-20.0, 20.0, 60.0, 150.0):
        y = math.log10(math.log10(wc.nu(theta) + 0.7))
        assert y == pytest.approx(A - B * math.log10(theta + 273.15), rel=1e-12, abs=1e-14)
    # thinner when warmer
    assert wc.nu(20.0) > wc.nu(40.0) > wc.nu(80.0) > wc.nu(100.0) > wc.nu(120.0)
    # in a network: the oil node warms from the drag; ν_oil is the law at theta_oil
    wc = WetClutch("wc", CoulombRobust(F_c=0.12, F_s=MU_S), "p", oil="oil",
                   **{**PACK, "gap": 0.03e-3})
    net = Network([Inertia("a", J=0.5, omega0=300.0), wc, Inertia("b", J=0.5),
                   ThermalNode("oil", capacity=20.0, theta0=20.0)],
                  [["a.b", "wc.a"], ["wc.b", "b.a"]])
    res = simulate(net.build({"p": 0.0}), (0.0, 0.3), {"p": 0.0}, options=TIGHT)
    _clean(res)
    th = res["theta_oil"]
    assert th[-1] > th[0] + 5.0
    assert np.allclose(res["nu_oil_wc"], [wc.nu(x) for x in th], rtol=1e-12)
    # the drag heats the oil: C·Δθ = W_drag
    assert 20.0 * (th[-1] - th[0]) == pytest.approx(res["W_drag_wc"][-1], rel=1e-7)


@pytest.mark.parametrize("p", [0.0, 0.5e5, 1.075e5, 2e5, 10e5])
def test_capacity_follows_the_piston_clamp_force(p):
    """``capacity = N·μ_s·max(0, p·A − F0 − k·stroke)·R_m`` (kiss point 1.075 bar)."""
    wc = _clutch()
    net = Network([Inertia("a", J=0.1, omega0=10.0), wc, Inertia("b", J=0.1)],
                  [["a.b", "wc.a"], ["wc.b", "b.a"]])
    res = simulate(net.build({"p": p}), (0.0, 1e-3), {"p": p}, options=TIGHT)
    assert res.outcome == Outcome.COMPLETED, res.message
    F = max(0.0, p * PACK["piston_area"] - PACK["spring_preload"]
            - PACK["spring_rate"] * PACK["stroke"])
    R_m = 0.5 * (PACK["r_inner"] + PACK["r_outer"])
    cap = PACK["interfaces"] * MU_S * F * R_m
    assert res["F_clamp_wc"][0] == pytest.approx(F, rel=1e-12, abs=1e-9)
    assert res["capacity_wc"][0] == pytest.approx(cap, rel=1e-12, abs=1e-9)
    assert wc.capacity_at(p) == pytest.approx(cap, rel=1e-12, abs=1e-9)


def test_the_fill_through_a_hydraulic_actuator_delays_the_capacity_to_the_kiss_point():
    """The pressure from a hydraulic actuator's first-order lag (``valve.pressure``, τ =
    20 ms, a 6 bar step): ``p(t) = p_c·(1 − exp(−t/τ))``, the capacity 0 until the kiss
    point at ``t_k = −τ·ln(1 − p_kiss/p_c)``, then ``N·μ_s·(p(t)·A − F_spring)·R_m``."""
    from clutchsim.network.components import HydraulicActuator
    tau, pc = 0.02, 6e5
    wc = WetClutch("wc", CoulombRobust(F_c=0.12, F_s=MU_S), "valve.pressure", **PACK)
    net = Network([HydraulicActuator("valve", command="pc", time_constant=tau, area=1e-3),
                   Inertia("a", J=10.0, omega0=100.0), wc, Inertia("b", J=10.0)],
                  [["a.b", "wc.a"], ["wc.b", "b.a"]])
    res = simulate(net.build({"pc": pc}), (0.0, 0.1), {"pc": pc},
                   options=SolverOptions(rtol=1e-10, atol=1e-10, dt_out=1e-4))
    _clean(res)
    t = res.t
    p = pc * (1.0 - np.exp(-t / tau))
    assert np.allclose(res["valve.pressure"], p, rtol=1e-7, atol=1e-6 * pc)
    cap = np.array([wc.capacity_at(x) for x in p])
    assert np.max(np.abs(res["capacity_wc"] - cap)) <= 1e-6 * cap.max()
    t_k = -tau * math.log(1.0 - wc.kiss_pressure / pc)
    first = t[np.flatnonzero(res["capacity_wc"] > 0.0)[0]]
    assert t_k <= first <= t_k + 1e-4
    assert np.all(res["w_slip_wc"] < 0.0)           # slipping throughout


def test_launch_closes_its_energy_balance_with_drag_into_oil_and_friction_into_plates():
    """A torque launches a load through the pack; the pressure rises to 6 bar in 0.3 s; it
    locks.  Adiabatic nodes: C·Δθ of the plates is W_friction, of the oil W_drag; the
    energy balance closes (1e-9)."""
    wc = WetClutch("wc", CoulombRobust(F_c=0.12, F_s=MU_S), "p", oil="oil",
                   heat=(("plates", 1.0),), flow=3.3e-5, mist=0.1, **PACK)
    net = Network([TorqueSource("drive", input="tau"), Inertia("engine", J=0.2, omega0=150.0),
                   wc, Inertia("load", J=2.0),
                   ThermalNode("oil", capacity=4000.0, theta0=60.0),
                   ThermalNode("plates", capacity=1500.0, theta0=60.0)],
                  [["drive.flange", "engine.a"], ["engine.b", "wc.a"], ["wc.b", "load.a"]])
    from clutchsim.core.signals import Ramp
    inputs = {"tau": 80.0, "p": Ramp(0.0, 0.3, 6e5)}
    res = simulate(net.build({"tau": 80.0, "p": 0.0}), (0.0, 1.5), inputs,
                   options=SolverOptions(rtol=1e-9, atol=1e-10, dt_out=1e-3))
    _clean(res)
    assert [e.name for e in res.events if e.name.startswith("wc:")] == ["wc: stop"]
    assert res["W_drag_wc"][-1] > 1.0 and res["W_friction"][-1] > 100.0
    assert 4000.0 * (res["theta_oil"][-1] - 60.0) == pytest.approx(res["W_drag_wc"][-1],
                                                                   rel=1e-7)
    assert 1500.0 * (res["theta_plates"][-1] - 60.0) == pytest.approx(res["W_friction"][-1],
                                                                      rel=1e-7)
    assert energy_balance(res)["energy_balance_rel"] < 1e-9


def test_the_wet_dct_example_reports_its_drag_losses():
    """examples/wet_dct_upshift.toml: both clutches lock once (launch, upshift), each drags
    while open, and the summary reports it (drag_work_J) inside the damping account."""
    from clutchsim.analysis.network_summary import network_summary
    from clutchsim.scenario import load_scenario, run_scenario
    res = run_scenario(load_scenario(EXAMPLES / "wet_dct_upshift.toml"), None).result
    _clean(res)
    s = network_summary(res)
    drag = {f["name"]: f["drag_work_J"] for f in s["friction_elements"]}
    assert drag == {n: pytest.approx(res[f"W_drag_{n}"][-1], rel=1e-12)
                    for n in ("clutch1", "clutch2")}
    assert all(v > 100.0 for v in drag.values())
    assert sum(drag.values()) < s["energies"]["damping_J"]
    locks = [f["lockup_times_s"] for f in s["friction_elements"]]
    assert [len(x) for x in locks] == [1, 1] and locks[0][0] < 3.0 < locks[1][0]


def test_bad_values_are_refused_with_the_key_value_and_rule():
    m = CoulombRobust(F_c=0.12, F_s=MU_S)
    cases = [({"r_inner": 0.1}, r"r_inner = 0\.1 m must be < r_outer = 0\.095 m"),
             ({"interfaces": 2.5}, r"interfaces = 2\.5 must be an integer >= 1"),
             ({"interfaces": 0.0}, r"interfaces = 0 must be in \[1, 100\]"),
             ({"gap": 0.0}, r"gap = 0 m must be in \(0, 0\.01\]"),
             ({"drag_factor": -1.0}, r"drag_factor = -1 must be in \[0, 100\]"),
             ({"nu40": 5.0, "nu100": 6.0}, r"nu100 = 6 mm²/s must be < nu40 = 5 mm²/s")]
    for kw, msg in cases:
        with pytest.raises(ValueError, match=msg):
            WetClutch("wc", m, "p", **{**PACK, **kw})
    with pytest.raises(ValueError, match=r"static level 330 must be a friction coefficient"):
        WetClutch("wc", CoulombRobust(F_c=300.0, F_s=330.0), "p", **PACK)


BAD = [
    # (old text, new text, words of the one error line); clutch1 is component[2]
    ("gap = 0.15e-3", "gap = 0.0", ["component[2].gap", "= 0.0 m", "must be > 0 m"]),
    ("mist = 0.1", "mist = 0.1\ndrag_factor = -0.5",
     ["component[2].drag_factor", "= -0.5", "must be >= 0"]),
    ("r_inner = 0.075", "r_inner = 0.1",
     ["component[2].r_inner", "r_inner = 0.1 m must be < r_outer = 0.095 m"]),
    ("interfaces = 8", "interfaces = 0", ["component[2].interfaces", "= 0", "must be >= 1"]),
]


@pytest.mark.parametrize(("old", "new", "words"), BAD, ids=[b[1].splitlines()[-1] for b in BAD])
def test_bad_input_in_a_scenario_names_key_value_rule_file_and_line_and_exits_2(
        tmp_path, capsys, old, new, words):
    """The error line of ``clutchsim run`` on the example with one value spoilt (the check
    of the other issue-38 elements' files, test_shift_elements.py)."""
    from test_shift_elements import (
        test_bad_input_names_key_value_rule_file_and_line_and_exits_2 as check,
    )
    check(tmp_path, capsys, "wet_dct_upshift", old, new, words)
