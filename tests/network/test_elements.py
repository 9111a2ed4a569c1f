"""The standard elements of issue 34 §5 (prescribed motion, elastic gap, dampers, the
translational vehicle, speed-dependent and eddy-current torques): closed forms, the exact
Jacobian against central differences at random states, the energy balance, and the rules
of a prescribed node (each a clear error naming the components, with file and line in a
scenario)."""

import math

import numpy as np
import pytest
from test_network import _jac_fd

from clutchsim.core import SolverOptions, simulate
from clutchsim.core.signals import Constant, Sine
from clutchsim.friction import CoulombRobust
from clutchsim.network import Network, NetworkError
from clutchsim.network.components import (
    COMPONENTS,
    Accelerate,
    Clutch,
    ConstantSpeed,
    Damper,
    EddyCurrentBrake,
    ElastoBacklash,
    ElastoGap,
    Force,
    IdealGear,
    Inertia,
    InverseSpeedForce,
    InverseSpeedTorque,
    LinearSpeedForce,
    LinearSpeedTorque,
    LossyGear,
    LossyGearWithLash,
    Mass,
    Move,
    Position,
    QuadraticSpeedForce,
    QuadraticSpeedTorque,
    SignForce,
    SignTorque,
    Speed,
    SpringDamper,
    ThermalNode,
    TorqueSource,
    TranslationalAccelerate,
    TranslationalConstantSpeed,
    TranslationalDamper,
    TranslationalEddyCurrentBrake,
    TranslationalMove,
    TranslationalPosition,
    TranslationalSpeed,
    TranslationalSpringDamper,
    TranslationalVehicle,
)
from clutchsim.scenario import ScenarioError, load_scenario

OPTS = SolverOptions(rtol=1e-10, atol=1e-12, dt_out=0.01)


# ---------------------------------------------------------------- test networks per kind
def _rot_source(src, inputs0):
    """A rotational source driving an inertia, a load torque there, and a spring-damper
    to a free inertia (partials by the prescribed speed reach it)."""
    return Network([src, Inertia("j1", J=0.7), TorqueSource("load", input="tl"),
                    SpringDamper("sd", c=300.0, d=2.0, phi0=0.01),
                    Inertia("j2", J=1.3, omega0=2.0)],
                   [[f"{src.name}.flange", "j1.a", "load.flange", "sd.a"],
                    ["sd.b", "j2.a"]]), {"tl": -0.4, **inputs0}


def _tr_source(src, inputs0):
    return Network([src, Mass("m1", m=0.7), Force("load", input="tl"),
                    TranslationalSpringDamper("sd", c=300.0, d=2.0, stretch0=0.01),
                    Mass("m2", m=1.3, v0=2.0)],
                   [[f"{src.name}.flange", "m1.a", "load.flange", "sd.a"],
                    ["sd.b", "m2.a"]]), {"tl": -0.4, **inputs0}


def _body(cls, name, v0):
    return (Inertia(name, J=1.5, omega0=v0) if cls.domain == "rotational"
            else Mass(name, m=1.5, v0=v0))


def _load(cls, signed):
    """A speed-dependent load between a body and a second body as its support."""
    p = cls.params
    law = cls("law", **{p[0].name: -2.0, p[1].name: 3.0, "signed": float(signed),
                        **({p[3].name: 0.5} if len(p) > 3 else {})})
    return Network([_body(cls, "j1", 2.0), law, _body(cls, "j2", -0.7)],
                   [["j1.a", "law.flange"], ["law.support", "j2.a"]]), {}


def _sign(cls, reg):
    p = cls.params
    law = cls("law", **{p[0].name: -2.0, p[1].name: 1.5, "reg": float(reg)})
    return Network([_body(cls, "j1", 1.0), law], [["j1.a", "law.flange"]]), {}


def _eddy(cls, tn, wn):
    """An eddy-current brake heating a thermal node, its excitation an input."""
    brake = cls("eb", excitation_input="ex", heat="disc",
                **{tn: 40.0, wn: 5.0, "alpha": 0.004, "T_ref": 20.0})
    return Network([_body(cls, "j1", 6.0), brake, ThermalNode("disc", capacity=500.0, theta0=80.0)],
                   [["j1.a", "eb.flange"]]), {"ex": 0.8}


BUILDERS = {
    "speed": lambda: _rot_source(Speed("src", input="wr", f_crit=5.0), {"wr": 1.5}),
    "speed exact": lambda: _rot_source(Speed("src", input="wr", exact=1, derivative="ar"),
                                       {"wr": 1.5, "ar": 0.3}),
    "position": lambda: _rot_source(Position("src", input="pr", f_crit=3.0), {"pr": 0.2}),
    "accelerate": lambda: _rot_source(Accelerate("src", input="ar", w0=1.0), {"ar": 0.3}),
    "move": lambda: _rot_source(Move("src", position="pr", speed="wr", acceleration="ar"),
                                {"pr": 0.2, "wr": 1.5, "ar": 0.3}),
    "constant_speed": lambda: _rot_source(ConstantSpeed("src", w_fixed=2.5), {}),
    "translational_speed": lambda: _tr_source(TranslationalSpeed("src", input="wr"),
                                              {"wr": 1.5}),
    "translational_position": lambda: _tr_source(TranslationalPosition("src", input="pr"),
                                                 {"pr": 0.2}),
    "translational_accelerate": lambda: _tr_source(TranslationalAccelerate("src", input="ar"),
                                                   {"ar": 0.3}),
    "translational_move": lambda: _tr_source(
        TranslationalMove("src", position="pr", speed="wr", acceleration="ar"),
        {"pr": 0.2, "wr": 1.5, "ar": 0.3}),
    "translational_constant_speed": lambda: _tr_source(
        TranslationalConstantSpeed("src", v_fixed=-1.0), {}),
    "damper": lambda: (Network([Inertia("j1", J=1.0, omega0=3.0), Damper("dp", d=0.8),
                                Inertia("j2", J=2.0)], [["j1.b", "dp.a"], ["dp.b", "j2.a"]]),
                       {}),
    "translational_damper": lambda: (Network([Mass("m1", m=1.0, v0=3.0),
                                              TranslationalDamper("dp", d=0.8)],
                                             [["m1.b", "dp.a"], ["dp.b", "ground"]]), {}),
    "elasto_gap": lambda: (Network([Mass("m1", m=1.0, v0=-1.0),
                                    ElastoGap("gap", c=1e3, d=40.0, s_rel0=0.1,
                                              s_rel_start=0.05, n=1.5, s_ref=0.2),
                                    Force("f", input="fi")],
                                   [["gap.a", "ground"], ["gap.b", "m1.a", "f.flange"]]),
                           {"fi": 1.0}),
    **{f"{cls.kind} signed={sg}": (lambda cls=cls, sg=sg: _load(cls, sg)) for sg in (0, 1)
       for cls in (QuadraticSpeedTorque, QuadraticSpeedForce, LinearSpeedTorque,
                   LinearSpeedForce, InverseSpeedTorque, InverseSpeedForce)},
    **{f"{cls.kind} reg={reg}": (lambda cls=cls, reg=reg: _sign(cls, reg)) for reg in range(4)
       for cls in (SignTorque, SignForce)},
    "eddy_current_brake": lambda: _eddy(EddyCurrentBrake, "tau_nominal", "w_nominal"),
    "translational_eddy_current_brake": lambda: _eddy(TranslationalEddyCurrentBrake,
                                                      "f_nominal", "v_nominal"),
    "lossy_gear_with_lash": lambda: (_lash_drive(
        [LossyGearWithLash("gear", ratio=2.0, b=0.02, c=1e4, d=20.0, phi0=0.013,
                           loss_table=((0.0, 0.5, 0.6, 0.2, 0.1),))], [["gear.b", "j2.a"]]),
        {"tau": 3.0, "tl": -1.0}),
    "translational_vehicle": lambda: (Network([
        TranslationalVehicle("car", m=1200.0, R=0.3, A=2.2, Cd=0.3, Cr=0.012, v_wind=1.0,
                             torque="tw", inclination_input="incl", v0=0.0005)], []),
        {"tw": 300.0, "incl": 0.04}),
}


@pytest.mark.parametrize("case", sorted(BUILDERS))
def test_exact_jacobian_matches_central_differences(case):
    """Every entry of the generated Jacobian (energy rows included) against central
    differences of the compiled right-hand side at random states around the start, for a
    network holding the component (tolerance 1e-6 of the column's scale)."""
    net, u0 = BUILDERS[case]()
    sys_ = net.build(u0)
    u = np.array([u0[n] for n in sys_.input_names], dtype=float)
    rng = np.random.default_rng(34)
    for _ in range(12):
        y = sys_.y0.copy()
        y += rng.normal(0.0, 0.3, y.size) * np.maximum(1.0, np.abs(y))
        if case.startswith(("sign_", "inverse_")):     # both sides of the regularisation
            y[0] = rng.uniform(-3.0, 3.0)
        if case == "lossy_gear_with_lash":  # rolling in the direction of its slip (the
            # stuck gear's friction power drops its dτ·w part: docs/network.md, Jacobian)
            names = sys_.state_names
            y[names.index("gear.locked")] = 0.0
            y[names.index("gear.mode")] = math.copysign(1.0, y[names.index("omega_j1")])
        if case == "elasto_gap":        # in contact, open, and both limiter bounds
            y[sys_.state_names.index("s_rel_gap")] = rng.uniform(-0.2, 0.3)
        J, Jfd = _jac_fd(sys_, y, u)
        scale = 1.0 + np.abs(Jfd)
        assert np.all(np.abs(J - Jfd) <= 1e-6 * scale.max(axis=0)), \
            (case, np.argwhere(np.abs(J - Jfd) > 1e-6 * scale.max(axis=0)))


def test_every_new_component_has_a_jacobian_builder():
    """The kinds this module adds are all walked by the Jacobian test above."""
    new = {"speed", "position", "accelerate", "move", "constant_speed", "damper",
           "elasto_gap", "translational_damper", "translational_vehicle"}
    new |= {f"translational_{k}" for k in ("speed", "position", "accelerate", "move",
                                           "constant_speed", "eddy_current_brake")}
    new |= {f"{k}_speed_{d}" for k in ("quadratic", "linear", "inverse")
            for d in ("torque", "force")}
    new |= {"sign_torque", "sign_force", "eddy_current_brake", "lossy_gear_with_lash"}
    assert new <= set(COMPONENTS)
    assert new <= {k.split(" ")[0] for k in BUILDERS}


# ---------------------------------------------------------------- prescribed motion
def test_speed_source_filter_closed_form_and_its_torque():
    """speed: ω = 1 − exp(−ω_c·t) for a unit reference (ω(0) = ω_ref(0) = 0 needs a
    reference starting at 0: a step at 0.1 s), and the torque that holds it,
    J·a − Σ others, here J·ω_c·exp(−ω_c·(t − 0.1)) + 0.4 (the load is −0.4)."""
    wc = 2 * math.pi * 5.0
    net = Network([Speed("src", input="wr", f_crit=5.0), Inertia("j1", J=0.7),
                   TorqueSource("load", input="tl")],
                  [["src.flange", "j1.a", "load.flange"]])
    sys_ = net.build({"wr": 0.0, "tl": -0.4})
    from clutchsim.core.signals import Step
    res = simulate(sys_, (0.0, 0.6), {"wr": Step(0.1, 1.0), "tl": Constant(-0.4)},
                   solver="rodas4", options=OPTS)
    assert res.status == "completed"
    t = res.t
    w = np.where(t > 0.1, 1.0 - np.exp(-wc * (t - 0.1)), 0.0)
    assert np.max(np.abs(res["omega_src"] - w)) < 1e-8
    assert np.max(np.abs(res["omega_j1"] - w)) < 1e-8       # the node moves with it
    tau = np.where(t > 0.1, 0.7 * wc * np.exp(-wc * (t - 0.1)), 0.0) + 0.4
    late = t > 0.12
    assert np.max(np.abs(res["T_src"][late] - tau[late])) < 1e-6


def test_prescribed_source_books_its_power():
    """A speed source driving a spring-damper and a free inertia: the energy balance
    closes (the source books τ·ω with τ = J·a − Σ others)."""
    net, u0 = BUILDERS["speed"]()
    sys_ = net.build(u0)
    res = simulate(sys_, (0.0, 1.0), {"wr": Sine(2.0, 1.5), "tl": Constant(-0.4)},
                   solver="rodas4", options=OPTS)
    assert res.status == "completed"
    ke, pe = res["E_kinetic"], res["E_spring"]
    losses = sum(res[k][-1] for k in ("W_friction", "W_damping", "W_road", "E_grade", "W_sync"))
    resid = res["W_in"][-1] - (ke[-1] - ke[0]) - (pe[-1] - pe[0]) - losses
    assert abs(res["W_in"][-1]) > 0.1
    assert abs(resid) < 1e-7 * max(abs(res["W_in"][-1]), ke.max())


def _error(net):
    with pytest.raises(NetworkError) as err:
        net.compile()
    return str(err.value)


def test_two_prescribed_speeds_on_one_node_are_refused():
    msg = _error(Network([Speed("s1", input="w"), Speed("s2", input="w"), Inertia("j", J=1.0)],
                         [["s1.flange", "s2.flange", "j.a"]]))
    assert "s2" in msg and "s1" in msg and "fight" in msg


def test_a_prescribed_speed_through_a_gear_is_refused():
    msg = _error(Network([Speed("s1", input="w"), IdealGear("g", ratio=2.0), Inertia("j", J=1.0)],
                         [["s1.flange", "g.a"], ["g.b", "j.a"]]))
    assert "'g'" in msg and "s1" in msg and "rigid part" in msg


def test_a_friction_element_on_a_prescribed_node_is_refused():
    msg = _error(Network([Speed("s1", input="w"), Inertia("j0", J=1.0),
                          Clutch("c", CoulombRobust(F_c=1.0, F_s=1.2), command="com"),
                          Inertia("j", J=1.0)],
                         [["s1.flange", "j0.a", "c.a"], ["c.b", "j.a"]]))
    assert "'c'" in msg and "s1" in msg and "lock" in msg


def test_a_prescribed_motion_of_the_ground_is_refused():
    msg = _error(Network([ConstantSpeed("s1", w_fixed=1.0)], [["s1.flange", "ground"]]))
    assert "ground" in msg and "s1" in msg


def test_scenario_errors_name_file_and_line(tmp_path):
    base = """[scenario]
name = "x"
t_end = 0.1
expect_lockup = false
[inputs]
w = "const(1)"
[network]
connect = [["s1.flange", "s2.flange", "m.a"]]
[[component]]
type = "translational_speed"
name = "s1"
input = "w"
[[component]]
type = "translational_speed"
name = "s2"
input = "w"
[[component]]
type = "mass"
name = "m"
m = 1.0
"""
    path = tmp_path / "two.toml"
    path.write_text(base)
    with pytest.raises(ScenarioError) as err:
        load_scenario(path)
    text = str(err.value)
    assert "two.toml:" in text and "s2" in text and "fight" in text
    gap = base.replace('type = "translational_speed"\nname = "s2"\ninput = "w"',
                       'type = "elasto_gap"\nname = "s2"\nc = -5.0')
    gap = gap.replace('["s1.flange", "s2.flange", "m.a"]', '["s1.flange", "s2.a", "m.a"], '
                      '["s2.b", "ground"]')
    path.write_text(gap)
    with pytest.raises(ScenarioError) as err:
        load_scenario(path)
    text = str(err.value)
    assert "two.toml:16" in text and "component[1].c" in text and "-5" in text


def test_exact_speed_needs_its_derivative():
    with pytest.raises(ValueError, match="derivative"):
        Speed("s", input="w", exact=1)
    with pytest.raises(ValueError, match="exact = 1"):
        Speed("s", input="w", derivative="a")


# ---------------------------------------------------------------- elastic gap
def test_elastic_gap_never_pulls_and_books_its_loss():
    """A mass thrown at an elastic gap with heavy damping: the contact force never pulls
    (F <= 0 on flange a's side: it pushes the flanges apart), it lifts off, and the energy
    balance closes with the damping loss."""
    net = Network([Mass("m1", m=1.0, v0=-2.0),
                   ElastoGap("gap", c=1e4, d=400.0, s_rel0=0.0, s_rel_start=0.05)],
                  [["gap.a", "ground"], ["gap.b", "m1.a"]])
    res = simulate(net.build({}), (0.0, 0.3), solver="rodas4", options=OPTS)
    assert res.status == "completed"
    assert np.all(res["F_gap"] <= 1e-12)
    assert res["v_m1"][-1] > 0.0                         # bounced off, slower
    assert res["v_m1"][-1] < 2.0
    ke0, ke1 = 0.5 * 2.0 ** 2, 0.5 * res["v_m1"][-1] ** 2
    assert res["W_damping"][-1] == pytest.approx(ke0 - ke1, rel=1e-6)
    assert any("contact edge" in e.name for e in res.events)


# ---------------------------------------------------------------- loads
def test_eddy_current_brake_kloss_law_and_its_heat():
    """Kloss' characteristic: the braking torque 2·τ_n·e²·x/(1 + x²) with the temperature
    stretching the nominal speed (1 + α·(θ − T_ref)); the loss heats the node: C·Δθ equals
    the booked loss (W_damping) and the kinetic energy the inertia lost."""
    net, u0 = BUILDERS["eddy_current_brake"]()
    sys_ = net.build(u0)
    res = simulate(sys_, (0.0, 2.0), {"ex": Constant(0.8)}, solver="rodas4", options=OPTS)
    assert res.status == "completed"
    w, th = res["omega_j1"], res["theta_disc"]
    x = w / (5.0 * (1.0 + 0.004 * (th - 20.0)))
    assert np.max(np.abs(res["T_eb"] - 2 * 40.0 * 0.64 * x / (1 + x * x))) < 1e-9
    assert res["T_eb"][0] < 2 * 40.0 * 0.64 * 0.5      # hot: x ≠ 1 at w = w_nominal·1.24
    heat = 500.0 * (th[-1] - th[0])
    assert heat == pytest.approx(res["W_damping"][-1], rel=1e-7)
    assert heat == pytest.approx(0.5 * 1.5 * (w[0] ** 2 - w[-1] ** 2), rel=1e-7)


@pytest.mark.parametrize("signed", [0, 1])
def test_speed_laws_in_closed_form(signed):
    """The laws at a few speeds: linear tn·|w|/wn (signed: tn·w/wn), inverse tn·wn/|w|
    beyond w0 and tn·wn/w0 below (signed: tn·wn/w, tn·wn·w/w0²), quadratic tn·(w/wn)²
    (signed: times sign w)."""
    from clutchsim.core.system import call_outputs
    for cls, f in ((LinearSpeedTorque, lambda w: -2.0 * (w if signed else abs(w)) / 3.0),
                   (QuadraticSpeedTorque,
                    lambda w: -2.0 * (w / 3.0) ** 2 * (np.sign(w) if signed else 1.0)),
                   (InverseSpeedTorque,
                    lambda w: (-2.0 * 3.0 * (w / 0.25 if signed else 1.0 / 0.5)
                               if abs(w) < 0.5 else -6.0 / (w if signed else abs(w))))):
        net, _ = _load(cls, signed)
        sys_ = net.build({})
        for w in (-4.0, -0.3, 0.2, 1.0, 5.0):
            y = sys_.y0.copy()
            y[sys_.state_names.index("omega_j1")] = w
            y[sys_.state_names.index("omega_j2")] = 0.0
            out = np.zeros(len(sys_.output_names))
            call_outputs(sys_.tag, 0.0, y, np.zeros(0), sys_.params, out)
            assert out[sys_.output_names.index("T_law")] == pytest.approx(f(w), rel=1e-12), \
                (cls.kind, w)


# ---------------------------------------------------------------- gearbox with lash
def _lash_drive(gear_parts, connect):
    return Network([TorqueSource("drive", input="tau"), Inertia("j1", J=1.0), *gear_parts,
                    Inertia("j2", J=1.5), TorqueSource("load", input="tl")],
                   [["drive.flange", "j1.a"], ["j1.b", "gear.a"], *connect,
                    ["j2.a", "load.flange"]])


def test_gearbox_with_lash_is_the_lossy_gear_and_lash_in_series():
    """lossy_gear_with_lash (Modelica Gearbox) runs as a lossy gear and an elasto-backlash
    joined at a massless node: the same states, events and speeds (to 1e-9)."""
    table = ((0.0, 0.5, 0.6, 0.2, 0.1), (5.0, 0.45, 0.55, 0.3, 0.2))
    one = _lash_drive([LossyGearWithLash("gear", loss_table=table, ratio=2.0, b=0.02, c=1e4,
                                         d=20.0)], [["gear.b", "j2.a"]])
    two = _lash_drive([LossyGear("gear", loss_table=table, ratio=2.0),
                       ElastoBacklash("lash", b=0.02, c=1e4, d=20.0)],
                      [["gear.b", "lash.a"], ["lash.b", "j2.a"]])
    runs = []
    for net in (one, two):
        sys_ = net.build({"tau": 0.0, "tl": -1.0})
        res = simulate(sys_, (0.0, 1.0), {"tau": Sine(10.0, 1.0), "tl": Constant(-1.0)},
                       solver="rodas4", options=SolverOptions(rtol=1e-10, atol=1e-12))
        assert res.status == "completed", res.message
        runs.append(res)
    a, b = runs
    assert len(a.events) == len(b.events) > 2
    for x, y in zip(a.events, b.events):
        assert x.t == pytest.approx(y.t, abs=1e-9)
    for col in ("omega_j1", "omega_j2", "gear.mode", "W_friction", "W_damping"):
        assert np.max(np.abs(a[col] - b[col])) < 1e-9, col
    assert np.max(np.abs(a["phi_gear"] - b["phi_lash"])) < 1e-9
    assert np.max(np.abs(a["T_lash_gear"] - b["T_lash"])) < 1e-7
    with pytest.raises(NetworkError, match="internal to lossy gear with lash 'gear'"):
        _lash_drive([LossyGearWithLash("gear", ratio=2.0, c=1e4, b=0.0)],
                    [["gear.b", "j2.a"], ["gear.mesh", "ground"]]).compile()


def test_position_source_is_msl_bessel_filter():
    """position: φ'' = ((φ_ref − φ)·ω_c − af·φ')·ω_c/bf from φ(0) = φ_ref(0), ω(0) = w0,
    against an independent integration of that filter (scipy), for a step of the reference
    at 0.1 s; the node (an inertia) moves with it."""
    from scipy.integrate import solve_ivp

    from clutchsim.core.signals import Step
    from clutchsim.network.components.prescribed import BESSEL_AF, BESSEL_BF
    wc = 2 * math.pi * 3.0
    net = Network([Position("src", input="pr", f_crit=3.0, w0=0.5), Inertia("j1", J=0.7)],
                  [["src.flange", "j1.a"]])
    sys_ = net.build({"pr": 0.2})
    res = simulate(sys_, (0.0, 1.0), {"pr": Step(0.1, 1.0, 0.2)}, solver="rodas4",
                   options=OPTS)
    assert res.status == "completed"

    def f(t, x, ref):
        return [x[1], ((ref - x[0]) * wc - BESSEL_AF * x[1]) * wc / BESSEL_BF]

    a = solve_ivp(f, (0.0, 0.1), [0.2, 0.5], args=(0.2,), rtol=1e-11, atol=1e-13,
                  dense_output=True)
    b = solve_ivp(f, (0.1, 1.0), a.y[:, -1], args=(1.2,), rtol=1e-11, atol=1e-13,
                  dense_output=True)
    t = res.t
    ref = np.where(t <= 0.1, a.sol(np.minimum(t, 0.1))[0], b.sol(np.maximum(t, 0.1))[0])
    assert np.max(np.abs(res["phi_src"] - ref)) < 1e-7
    assert np.max(np.abs(res["omega_j1"] - res["omega_src"])) == 0.0
    assert res["phi_src"][-1] == pytest.approx(1.2, abs=1e-3)
