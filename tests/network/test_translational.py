"""Translational networks (masses, forces, sliding friction, hard stops) and the angle
states of ``[outputs] angles``: Modelica's Translational.Examples.Friction inside the 2e-3
tube with its switch times, a mass against its stops in closed form, angles as the
closed-form integral of a known speed history and through a gear, and the errors."""

import math

import numpy as np
import pandas as pd
import pytest
from _dl_paths import EXAMPLES, shared_dir
from hypothesis import given, settings
from hypothesis import strategies as st
from test_network import _jac_fd

from clutchsim.core import SolverOptions, simulate
from clutchsim.friction import CoulombRobust
from clutchsim.network import Network, NetworkError
from clutchsim.network.components import (
    Force,
    IdealGear,
    Inertia,
    Mass,
    MassWithStopAndFriction,
    SupportFriction,
    TorqueSource,
    TranslationalBrake,
    TranslationalSpringDamper,
)
from clutchsim.scenario import ScenarioError, load_scenario, run_scenario
from clutchsim.signal_expr import parse_signal

REF = (shared_dir() / "reference" / "modelica" / "Modelica" / "Mechanics" / "Translational"
       / "Examples" / "Friction" / "Friction.csv")
TUBE = 2e-3
EXAMPLE = EXAMPLES / "translational_friction.toml"
OPTS = SolverOptions(rtol=1e-10, atol=1e-12, dt_out=0.01)


def tube_error(res, ref, ours, theirs, dt=1e-4):
    """Largest distance of the reference from our signal's range over [t - dt, t + dt]
    (a tube in time as well: the velocity jumps to 0 at a stop), relative to the
    reference's largest magnitude (at least 1)."""
    t, r = ref["time"].to_numpy(), ref[theirs].to_numpy()
    x = [np.interp(t + d, res.t, res[ours]) for d in (-dt, 0.0, dt)]
    lo, hi = np.minimum.reduce(x), np.maximum.reduce(x)
    err = np.maximum(lo - r, 0.0) + np.maximum(r - hi, 0.0)
    return np.max(err) / max(np.max(np.abs(r)), 1.0)


def test_translational_friction_matches_modelica():
    if not REF.exists():
        pytest.skip(f"Modelica reference results not found at {REF} (set CLUTCHSIM_SHARED "
                    "to the shared folder)")
    ref = pd.read_csv(REF).drop_duplicates("time", keep="last")
    r = run_scenario(EXAMPLE)
    res = r.result
    assert res.status == "completed", res.message
    for name in ("mass", "stop1", "stop2"):
        for q in ("s", "v"):
            assert tube_error(res, ref, f"{q}_{name}", f"{name}.{q}") <= TUBE, (name, q)
    # the mode switches of the reference (README; Friction.csv's mode columns)
    ev = [(e.name, e.t) for e in res.events]
    want = [("stop1: breakaway", 0.410143), ("stop1: stop", 2.442689),
            ("stop1: stop", 4.44194), ("friction: breakaway", 0.409668),
            ("friction: stop", 2.442228), ("friction: stop", 4.441544),
            ("stop2: lower stop", 0.060597), ("stop2: stop", 1.045974)]
    for name, t in want:
        assert min(abs(te - t) for n, te in ev if n == name) < 1e-5, (name, t)
    # stop2 rests at its lower stop (centre at smin + L/2) with v = 0 at the impact, and
    # sticks for good at 1.046 s (its spring force inside the break-away limit)
    t_hit = dict(ev)["stop2: lower stop"]
    at = res.t == t_hit
    # (the row before the reset is the located crossing: past the stop by at most its speed
    # times the location tolerance, event_tol = 1e-12 s)
    assert np.min(res["s_stop2"]) >= -0.4 - 1e-12 and np.all(res["s_stop2"][at][1:] == -0.4)
    v_hit = res["v_stop2"][at][0]
    assert v_hit < -6.0 and res["v_stop2"][at][-1] == pytest.approx(0.0, abs=1e-12)
    assert res.final("W_sync") == pytest.approx(0.5 * v_hit ** 2, rel=1e-9)  # the impact
    assert res["stop2.mode"][-1] == 0.0 and abs(500.0 * (res["s_stop2"][-1] + 0.25)) < 8.008
    assert r.metrics["energy_balance_rel"] < 1e-6
    assert res.unit("F_friction") == "N" and res.unit("v_mass") == "m/s"
    assert res.unit("s_mass") == "m"


def test_a_translational_run_draws_its_motion(tmp_path):
    from clutchsim.plot.network import network_panels
    from clutchsim.scenario.outputs import write_runs
    sc = load_scenario(EXAMPLE)
    summary = write_runs(sc, [], tmp_path)
    assert summary["runs"][sc.name]["completed"]
    assert (tmp_path / f"network_{sc.name}.png").stat().st_size > 10_000
    assert not list(tmp_path.glob("launch_*.png"))
    res = run_scenario(EXAMPLE).result
    assert res.metadata["domain"] == "translational"
    panels = {title: (label, names) for title, label, names in network_panels(res)}
    assert panels["positions"] == ("position [m]", ["s_stop1", "s_stop2", "s_mass"])
    assert panels["velocities"] == ("velocity [m/s]", ["v_stop1", "v_stop2", "v_mass"])
    assert {"F_stop1", "F_stop2", "F_friction"} <= set(panels["forces"][1])
    assert panels["forces"][0] == "force [N]"


def _stop_network(m=2.0, smax=1.0, F_Coulomb=2.0):
    stop = MassWithStopAndFriction("m", m=m, smin=-1.0, smax=smax, F_prop=0.0,
                                   F_Coulomb=F_Coulomb, F_Stribeck=0.0, fexp=0.0)
    return Network([Force("f", input="F"), stop], [["f.flange", "m.a"]], name="stops")


@settings(max_examples=8, deadline=None)
@given(st.floats(0.5, 5.0), st.floats(0.1, 3.0), st.floats(0.0, 3.0), st.floats(1.05, 4.0))
def test_impact_time_and_energy_against_a_stop(m, smax, F_c, push):
    """From rest at 0 under a constant F > F_c: the stop at smax is hit at
    √(2·m·smax/(F − F_c)) with the kinetic energy (F − F_c)·smax, which W_sync books; then
    the mass stays there (one topology: the values change, the plant is compiled once)."""
    F = push * (F_c + 0.5)
    sys_ = _stop_network(m, smax, F_c).build()
    res = simulate(sys_, (0.0, 4.0), {"F": parse_signal(f"const({F!r})")}, solver="rodas4",
                   options=SolverOptions(rtol=1e-10, atol=1e-12))
    assert res.status == "completed", res.message
    hits = [e.t for e in res.events if e.name == "m: upper stop"]
    t_hit = math.sqrt(2.0 * m * smax / (F - F_c))
    if t_hit >= 4.0:
        assert not hits
        return
    assert len(hits) == 1 and hits[0] == pytest.approx(t_hit, rel=1e-8)
    assert res.final("W_sync") == pytest.approx((F - F_c) * smax, rel=1e-7)
    assert res.final("s_m") == smax and res.final("v_m") == pytest.approx(0.0, abs=1e-12)


def test_two_break_aways_in_one_step_are_each_located():
    """Two masses pushed by F = 25·sin(πt/2) N, one held by a brake (30.03 N at full
    normal force, commanded at 0.5), one by support friction (15 N): each breaks away where
    F reaches its capacity, t = (2/π)·asin(F_s/25).  The one listed first breaks away
    0.47 ms later: both crossings fall inside one step, and each is located."""
    comps, conns = [], []
    for name, fr in (("late", TranslationalBrake("fr_late", CoulombRobust(F_c=30.03, F_s=30.03),
                                                 command="fn")),
                     ("early", SupportFriction("fr_early", CoulombRobust(F_c=15.0, F_s=15.0)))):
        comps += [Force(f"f_{name}", input="F"), Mass(name, m=1.0), fr]
        conns += [[f"f_{name}.flange", f"{name}.a", f"fr_{name}.flange"]]
    sys_ = Network(comps, conns, name="two_breakaways").build()
    res = simulate(sys_, (0.0, 0.5), {"F": parse_signal("sine(25, 0.25)"),
                                      "fn": parse_signal("const(0.5)")}, solver="rodas4")
    ev = {e.name: e.t for e in res.events}
    for name, cap in (("late", 15.015), ("early", 15.0)):
        t = 2.0 / math.pi * math.asin(cap / 25.0)
        assert ev[f"fr_{name}: breakaway"] == pytest.approx(t, abs=1e-7), name


def test_mass_against_its_stops_in_closed_form():
    """F = +6 N pushes a 2 kg mass (Coulomb 2 N) from rest at 0 to the upper stop at 1 m:
    a = 2 m/s², there at t = 1 s with 2 m/s; it stays there while pushed, leaves at 3 s when
    F = -6 N and reaches the lower stop at 3 + √2 s.  The kinetic energy of both impacts
    (4 J + 8 J) is booked in W_sync."""
    sys_ = _stop_network().build()
    res = simulate(sys_, (0.0, 5.0), {"F": parse_signal("6 + step(3, -12)")},
                   solver="rodas4", options=OPTS)
    assert res.status == "completed", res.message
    ev = {e.name: e.t for e in res.events}
    assert ev["m: upper stop"] == pytest.approx(1.0, abs=1e-7)
    assert ev["m: lower stop"] == pytest.approx(3.0 + math.sqrt(2.0), abs=1e-7)
    t, s, v = res.t, res["s_m"], res["v_m"]
    a = t < 1.0
    assert np.allclose(s[a], t[a] ** 2, atol=1e-8)
    held = (t > 1.001) & (t < 3.0)
    assert np.all(s[held] == 1.0) and np.allclose(v[held], 0.0, atol=1e-12)
    assert np.allclose(res["F_stick_m"][held], 6.0)       # the stop holds the push
    b = (t > 3.001) & (t < 3.0 + math.sqrt(2.0))
    assert np.allclose(s[b], 1.0 - (t[b] - 3.0) ** 2, atol=1e-8)
    assert np.all(s[t > 3.001 + math.sqrt(2.0)] == -1.0)
    f = res.final
    assert f("W_sync") == pytest.approx(12.0, rel=1e-7)
    assert f("W_friction") + f("W_sync") + f("E_kinetic") == pytest.approx(f("W_in"), rel=1e-9)


def test_translational_jacobian_matches_differences():
    sc = load_scenario(EXAMPLE)
    sys_ = sc.network().build(sc.inputs0())
    names = sys_.state_names
    y = sys_.y0.copy()
    for name, v in (("stop1", 3.3), ("stop2", -1.7), ("mass", 3.3)):
        y[names.index(f"v_{name}")] = v
        key = "friction" if name == "mass" else name
        y[names.index(f"{key}.mode")] = math.copysign(1.0, v)
        y[names.index(f"{key}.locked")] = 0.0
    y[names.index("stretch_spring")] = 0.1
    J, Jfd = _jac_fd(sys_, y, np.array([7.0]))
    assert np.max(np.abs(J - Jfd) / np.maximum(np.abs(Jfd), 1.0)) < 1e-6


def _geared(angles):
    return Network([TorqueSource("drive", input="tau"), Inertia("j1", J=2.0, phi0=0.3),
                    IdealGear("gear", ratio=2.5), Inertia("j2", J=5.0, phi0=0.12)],
                   [["drive.flange", "j1.a"], ["j1.b", "gear.a"], ["gear.b", "j2.a"]],
                   name="geared", angles=angles)


def test_angles_are_the_integral_of_the_speed_and_follow_the_gear():
    """τ = 3·sin(2π·0.5·t) on J1 = 2 kg·m², geared 2.5:1 to J2 = 5 kg·m² (J = 2 + 5/2.5²
    at J1): ω1 = A/(J·Ω)·(1 − cos Ωt), φ1 = φ1(0) + A/(J·Ω)·(t − sin(Ωt)/Ω), φ2 = φ1/2.5."""
    sys_ = _geared(True).build()
    # one angle per inertia node (the gear's two sides are two nodes): the speed state of
    # j1 (j2's speed follows the gear), the energy accounts and the two angles, which are
    # quadratures (trailing, outside the implicit solve) like the accounts
    assert [n for n in sys_.state_names if not n.startswith(("W_", "E_"))] == [
        "omega_j1", "phi_j1", "phi_j2"]
    assert sys_.state_names[-2:] == ("phi_j1", "phi_j2") and sys_.quadratures == 6 + 2
    res = simulate(sys_, (0.0, 3.0), {"tau": parse_signal("sine(3, 0.5)")}, solver="rodas4",
                   options=OPTS)
    assert res.status == "completed", res.message
    t, om = res.t, math.pi
    J = 2.0 + 5.0 / 2.5 ** 2
    assert np.allclose(res["phi_j1"], 0.3 + 3.0 / (J * om) * (t - np.sin(om * t) / om),
                       atol=1e-8)
    assert np.allclose(res["phi_j1"], 2.5 * res["phi_j2"], atol=1e-10)
    assert res.unit("phi_j1") == "rad"


def test_default_launch_has_no_angle_states():
    sys_ = load_scenario(None).network().build()
    inertias = [n[len("omega_"):] for n in sys_.state_names if n.startswith("omega_")]
    assert not {f"phi_{n}" for n in inertias} & set(sys_.state_names)


def test_outputs_angles_reaches_the_network_of_a_chain_file(tmp_path):
    p = tmp_path / "launch.toml"
    p.write_text((EXAMPLES / "launch.toml").read_text(encoding="utf-8")
                 + "\n[outputs]\nangles = true\n", encoding="utf-8")
    assert load_scenario(p).network().angles
    assert not load_scenario(None).network().angles
    p.write_text((EXAMPLES / "launch.toml").read_text(encoding="utf-8")
                 + "\n[outputs]\nangle = true\n", encoding="utf-8")
    with pytest.raises(ScenarioError, match="angle"):
        load_scenario(p)


def test_bad_translational_input_is_named(tmp_path):
    with pytest.raises(NetworkError, match="mass 'm' is translational but inertia 'j' is "
                                           "rotational"):
        Network([Inertia("j", J=1.0), Mass("m", m=1.0)], [["j.a", "m.a"]])
    floating = Network([Mass("m", m=1.0), TranslationalSpringDamper("k", c=1.0),
                        Force("f", input="F")], [["m.a", "k.a"], ["k.b", "f.flange"]])
    with pytest.raises(NetworkError, match="k.b, f.flange can move without moving any mass"):
        floating.assemble()
    with pytest.raises(ValueError, match=r"s0 = 2 m must be between the stops.*\[-1, 1\] m"):
        MassWithStopAndFriction("m", m=1.0, smin=-1.0, smax=1.0, s0=2.0)
    text = EXAMPLE.read_text(encoding="utf-8")
    bad = text.replace('friction = { model = "coulomb-robust", overrides = { F_c = 1.0, '
                       'F_s = 1.0, v_s = 0.0, delta = 2.0, sigma2 = 0.0 } }',
                       'friction = { model = "mykhailevych2020", parameter_set = '
                       '"mykhailevych2020_clutch" }')
    assert bad != text
    p = tmp_path / "s.toml"
    p.write_text(bad, encoding="utf-8")
    with pytest.raises(ScenarioError) as info:
        load_scenario(p)
    msg = str(info.value)
    assert "translational units (N, m, m/s)" in msg and "mykhailevych2020_clutch" in msg
    line = next(i for i, s in enumerate(bad.splitlines(), 1) if "mykhailevych2020" in s)
    assert f":{line}" in msg


@pytest.mark.parametrize("key, value", [("component[1].F_Coulomb", 6.0),
                                        ("component[3].smin", -0.8),
                                        ("component[2].stretch0", 0.3)])
def test_sweep_values_of_translational_parts_equal_a_rebuild(key, value):
    """A sweep sets a value on the compiled network (the stop law rebuilt from it): the
    parameters and initial state equal those of the scenario built again with it."""
    from clutchsim.scenario.variants import VariantPlan
    vp = VariantPlan(load_scenario(EXAMPLE))
    direct = vp.system(((key, value),))
    _, again = vp.rebuilt(((key, value),))
    assert direct is not None
    assert np.array_equal(direct.params, again.params) and np.array_equal(direct.y0, again.y0)
    assert not np.array_equal(direct.params, vp.params) or key.endswith("stretch0")
