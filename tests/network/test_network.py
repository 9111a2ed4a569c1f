"""The network: graph checks, the generated plant's exact Jacobian, the chain translation,
values applied to a compiled topology."""

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from clutchsim.core import SolverOptions, simulate
from clutchsim.core.system import call_jac, call_rhs
from clutchsim.friction import CoulombRobust, make_model
from clutchsim.network import Network, NetworkError, compile_network
from clutchsim.network.components import (
    Brake,
    IdealGear,
    Inertia,
    Planetary,
    SpringDamper,
    TorqueSource,
)
from clutchsim.scenario import load_scenario


def two_mass(c=1e3, J2=2.0):
    return Network([TorqueSource("drive", input="tau"), Inertia("a", J=1.0),
                    SpringDamper("k", c=c, d=0.5), Inertia("b", J=J2)],
                   [["drive.flange", "a.a"], ["a.b", "k.a"], ["k.b", "b.a"]])


# ---------------------------------------------------------------- bad networks
@pytest.mark.parametrize("build, words", [
    (lambda: Network([Inertia("a", J=1.0), SpringDamper("k", c=1.0)], [["a.b", "k.a"]]),
     ["spring damper 'k'", "flange 'b'", "connected to nothing"]),
    (lambda: Network([Inertia("a", J=1.0), Inertia("a", J=2.0)], []),
     ["two components are named 'a'"]),
    (lambda: Network([Inertia("a", J=1.0), IdealGear("g1", ratio=2.0), IdealGear("g2", ratio=3.0),
                      Inertia("b", J=1.0)],
                     [["a.b", "g1.a", "g2.a"], ["g1.b", "g2.b", "b.a"]]),
     ["g1", "g2", "loop", "ratios disagree"]),
    (lambda: Network([Inertia("a", J=1.0), SpringDamper("k", c=1.0),
                      TorqueSource("t", input="tau")],
                     [["a.b", "k.a"], ["k.b", "t.flange"]]),
     ["k.b", "t.flange", "without moving any inertia"]),
    (lambda: Network([Inertia("a", J=1.0)], [["a.b", "x.a"]]), ["no component 'x'"]),
    (lambda: Network([Inertia("a", J=1.0), SpringDamper("k", c=1.0)], [["a.b", "k.c"]]),
     ["has no flange 'c'", "a, b"]),
])
def test_bad_networks_name_component_flange_and_rule(build, words):
    with pytest.raises(NetworkError) as exc:
        build().compile()
    for w in words:
        assert w in str(exc.value)


def test_planetary_refuses_impossible_tooth_counts():
    with pytest.raises(ValueError, match="must be even"):
        Planetary("p", z_sun=50, z_ring=75)
    with pytest.raises(ValueError, match="must exceed z_sun"):
        Planetary("p", z_sun=80, z_ring=40)
    assert Planetary("p", z_sun=30, z_ring=72).ratio == pytest.approx(2.4)


def test_unknown_parameter_names_closest():
    with pytest.raises(ValueError, match="did you mean 'J'"):
        Inertia("a", j=1.0)
    with pytest.raises(ValueError, match=r"c = -1 N·m/rad must be in \(0, 1e\+09\]"):
        SpringDamper("k", c=-1.0)


# ---------------------------------------------------------------- physics
def test_two_mass_spring_frequency_and_energy():
    """Free vibration of two inertias on a spring: ω² = c(1/J1 + 1/J2)."""
    net = two_mass(c=1e3, J2=2.0)
    sys_ = net.build()
    y0 = sys_.y0.copy()
    y0[sys_.state_names.index("phi_k")] = 1e-3
    res = simulate(sys_, (0.0, 1.0), {"tau": 0.0}, y0=y0,
                   options=SolverOptions(rtol=1e-10, atol=1e-12, dt_out=1e-4))
    phi = res["phi_k"]
    crossings = np.flatnonzero(np.diff(np.sign(phi - phi.mean())) != 0)
    f = (len(crossings) - 1) / 2 / (res.t[crossings[-1]] - res.t[crossings[0]])
    f0 = np.sqrt(1e3 * (1 / 1.0 + 1 / 2.0)) / (2 * np.pi)
    assert f == pytest.approx(f0 * np.sqrt(1 - (0.5 * (1 / 1.0 + 1 / 2.0)) ** 2 / (4 * 1e3 * 1.5)),
                              rel=2e-3)


def _jac_fd(sys_, y, u):
    n = y.size
    J = np.zeros((n, n))
    call_jac(sys_.tag, 0.1, y, u, sys_.params, J)
    Jfd = np.zeros((n, n))
    for j in range(n):
        h = 1e-6 * max(1.0, abs(y[j]))
        yp, ym = y.copy(), y.copy()
        yp[j] += h
        ym[j] -= h
        fp, fm = np.zeros(n), np.zeros(n)
        call_rhs(sys_.tag, 0.1, yp, u, sys_.params, fp)
        call_rhs(sys_.tag, 0.1, ym, u, sys_.params, fm)
        Jfd[:, j] = (fp - fm) / (2 * h)
    return J, Jfd


@settings(max_examples=15, deadline=None)
@given(st.floats(20.0, 150.0), st.floats(0.05, 5.0), st.booleans(), st.floats(-0.02, 0.02),
       st.floats(30.0, 190.0), st.floats(0.05, 1.0))
def test_generated_jacobian_matches_differences_on_the_launch(w_e, slip, backward, phi, theta,
                                                              com):
    """Every entry of the generated exact Jacobian (energy rows included) against central
    differences at random states of the default launch (away from zero slip, where the
    heat |T·w| has a kink a difference would straddle, below the first kink of μ(θ), and
    off the idle speed, where the governor's torque has one: Hypothesis drew the
    scenario's own 83.78 rad/s there)."""
    slip = -slip if backward else slip
    sc = load_scenario(None)
    net = sc.network("mykhailevych2020")
    idle = next(c.values["idle_speed"] for c in net.components if "idle_speed" in c.values)
    assume(abs(w_e - idle) > 1e-3)
    sys_ = net.build(sc.inputs0())
    names = sys_.state_names
    y = sys_.y0.copy()
    y[names.index("omega_engine")] = w_e
    y[names.index("omega_disc")] = w_e + slip
    y[names.index("omega_gearbox_input")] = w_e + slip + 0.3
    y[names.index("omega_wheels")] = (w_e + slip) / 14.76
    y[names.index("phi_damper")] = phi
    # clutch.phi away from 0: there |T·w| (the heat) has a kink a difference would straddle
    y[names.index("clutch.phi")] = 1.5e-3
    y[names.index("theta_pressure_plate")] = theta
    u = np.zeros(len(sys_.input_names))
    u[sys_.input_names.index("clutch_command")] = com
    u[sys_.input_names.index("throttle")] = 0.3
    J, Jfd = _jac_fd(sys_, y, u)
    scale = np.maximum(np.abs(Jfd), 1.0)
    assert np.max(np.abs(J - Jfd) / scale) < 1e-3


@pytest.mark.parametrize("clutch_locked", [0.0, 1.0])
def test_switching_network_jacobian_with_locked_brake(clutch_locked):
    sc = load_scenario("examples/simple_gear_shift.toml")
    sys_ = sc.network().build({"f_clutch": 0.3, "f_brake": 0.7})
    names = sys_.state_names
    y = sys_.y0.copy()
    y[0], y[1] = 8.0, 8.0 / 2.5      # the ring at rest: the locked brake's constraint
    y[names.index("clutch.mode")] = 0.0 if clutch_locked else -1.0
    y[names.index("clutch.locked")] = clutch_locked
    y[names.index("brake.locked")] = 1.0
    if clutch_locked:       # speeds that satisfy both locks: everything at rest
        y[0] = y[1] = 0.0
    u = np.array([20.0, 0.3, 0.7])
    J, Jfd = _jac_fd(sys_, y, u)
    assert np.max(np.abs(J - Jfd) / np.maximum(np.abs(Jfd), 1.0)) < 1e-5


# ---------------------------------------------------------------- compiled once
def test_values_reuse_the_compiled_topology():
    net1, net2 = two_mass(c=1e3), two_mass(c=4e3)
    p1, p2 = compile_network(net1), compile_network(net2)
    assert p1 is p2                       # same structure: one plant
    s1, s2 = net1.build(), net2.build()
    assert s1.tag == s2.tag and s1.params[p1.slot[("k", "c")]] == 1e3
    assert s2.params[p1.slot[("k", "c")]] == 4e3


def test_chain_translation_keeps_the_launch():
    """The default launch (a chain file) runs on the generated network plant: lock-up of
    model (6) where the chain plant located it (1.1181887 s), energy balanced."""
    from clutchsim.scenario import run_scenario
    r = run_scenario(None, "mykhailevych2020")
    assert r.result.metadata["network"]
    assert r.metrics["lockup_time_s"] == pytest.approx(1.1181887, abs=1e-5)
    assert r.metrics["energy_balance_rel"] < 1e-6
    # the final drive is rigidly tied to the gearbox input: an output, not a state
    assert "omega_final_drive" in r.result.signals


def test_brake_holds_a_loaded_inertia_and_releases():
    """A brake (coulomb-robust, 50 N·m) holds an inertia loaded by a ramp torque until the
    torque reaches its capacity: break-away exactly there (t = 50/100 s)."""
    net = Network([TorqueSource("drive", input="tau"), Inertia("a", J=2.0),
                   Brake("brake", CoulombRobust(F_c=40.0, F_s=50.0), command="f")],
                  [["drive.flange", "a.a", "brake.flange"]])
    from clutchsim.core.signals import Ramp
    res = simulate(net.build({"f": 1.0}), (0.0, 1.0), {"tau": Ramp(0.0, 1.0, 100.0), "f": 1.0},
                   options=SolverOptions(rtol=1e-9, atol=1e-10))
    ev = [e for e in res.events if e.name == "brake: breakaway"]
    assert ev and ev[0].t == pytest.approx(0.5, abs=1e-7)
    assert make_model("coulomb-robust", F_c=1.0, F_s=1.0)  # the registry still builds it
