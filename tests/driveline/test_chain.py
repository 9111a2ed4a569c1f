"""Physics of chain drivelines (chain tables read as networks): rigid parts, reflected
inertia, heat, energy."""

import numpy as np
import pytest

from clutchsim.analysis.launch_metrics import energy_balance
from clutchsim.core import Constant, SolverOptions, simulate
from clutchsim.scenario import ScenarioError
from clutchsim.scenario.loader import parse_scenario

OPTS = SolverOptions(rtol=1e-9, atol=1e-10)


def chain(inertia, coupling, thermal=(), inputs=("T",)):
    """The network the chain reader makes of these ``[[inertia]]``/``[[coupling]]``/
    ``[[thermal]]`` tables (``inputs``: the signals they read, 0 in the file)."""
    data = {"scenario": {"name": "chain", "t_end": 1.0}, "inputs": dict.fromkeys(inputs, 0.0),
            "inertia": list(inertia), "coupling": list(coupling)}
    if thermal:
        data["thermal"] = list(thermal)
    return parse_scenario(data).network()


def inertia(name, J, **kw):
    return {"name": name, "J": J, **kw}


def clutch(name, F_c, F_s, command="com", **kw):
    """A clutch coupling with a coulomb-robust model of these capacities [N·m]."""
    return {"name": name, "type": "clutch", "command": command,
            "friction": {"model": "coulomb-robust", "overrides": {"F_c": F_c, "F_s": F_s}},
            **kw}


def gearbox(name, ratios, **kw):
    return {"name": name, "type": "gearbox", "ratios": list(ratios), **kw}


def lossy_gear(name, ratio, row=None):
    """A lossy gear with a one-row loss table ``(speed, eta_mf1, eta_mf2, tau_bf1,
    tau_bf2)`` (None: no losses)."""
    t = {"name": name, "type": "lossy_gear", "ratio": ratio}
    if row is not None:
        t["loss_table"] = dict(zip(("speed", "eta_mf1", "eta_mf2", "tau_bf1", "tau_bf2"),
                                   ([x] for x in row)))
    return t


def test_locked_driveline_accelerates_as_one_inertia_with_reflected_gear_inertia():
    r = 3.0
    net = chain([inertia("a", 0.5, load="T"), inertia("b", 0.2), inertia("c", 2.0)],
                [clutch("clutch", 1e3, 1e3), {"name": "gear", "type": "gear", "ratio": r}],
                inputs=("T", "com"))
    sys_ = net.build({"com": 1.0})
    res = simulate(sys_, (0, 1.0), {"T": 6.0, "com": 1.0}, options=OPTS)
    assert res.status == "completed"
    j_eq = 0.5 + 0.2 + 2.0 / r**2          # J·(1/i)² referred to the input
    assert res["omega_a"][-1] == pytest.approx(6.0 / j_eq, rel=1e-9)
    assert res["omega_c"][-1] == pytest.approx(6.0 / j_eq / r, rel=1e-9)
    # the clutch transmits the torque that accelerates everything behind it
    # (Modelica sign: a positive torque decelerates the downstream side)
    assert -res["T_clutch"][-1] == pytest.approx(6.0 * (0.2 + 2.0 / r**2) / j_eq, rel=1e-9)
    assert energy_balance(res)["energy_balance_rel"] < 1e-8


def test_adiabatic_thermal_node_rise_equals_heat_over_capacity():
    net = chain([inertia("a", 1.0, omega0=50.0), inertia("b", 3.0)],
                [clutch("clutch", 20.0, 25.0, heat=[{"node": "plate", "share": 1.0}])],
                thermal=[{"name": "plate", "capacity": 500.0, "theta0": 20.0}],
                inputs=("com",))
    res = simulate(net.build(), (0, 3.0), {"com": 1.0}, options=OPTS)
    assert res.status == "completed"
    heat = res["W_friction"][-1]
    assert heat == pytest.approx(0.5 * 1.0 * 50**2 - 0.5 * 4.0 * 12.5**2, rel=1e-6)
    # the temperature is a state under error control (rtol 1e-9), the heat a quadrature:
    # they agree to the global error of the run (measured 2e-8 relative)
    assert res["theta_plate"][-1] - 20.0 == pytest.approx(heat / 500.0, rel=1e-7)


def test_spring_damper_energy_balance_and_two_stage_spring():
    net = chain([inertia("a", 1.0, omega0=5.0), inertia("b", 1.0)],
                [{"name": "s", "type": "spring_damper", "c": 100.0, "d": 0.5, "knee": 0.05,
                  "c2": 400.0}], inputs=())
    res = simulate(net.build(), (0, 2.0), {}, options=OPTS)
    eb = energy_balance(res)
    assert eb["W_damping"] > 0
    assert eb["energy_balance_rel"] < 1e-7
    # momentum is conserved by an internal spring
    assert res["omega_a"][-1] + res["omega_b"][-1] == pytest.approx(5.0, rel=1e-9)


def test_chain_rejects_bad_layout():
    with pytest.raises(ScenarioError, match="2 inertias need 1 couplings"):
        chain([inertia("a", 1.0), inertia("b", 1.0)], [])
    with pytest.raises(ScenarioError, match=r"inertia\[0\]\.J: = 0.0 kg·m² is out of range: "
                       "must be > 0 kg·m²"):
        chain([inertia("a", 0.0), inertia("b", 1.0)], [{"name": "g", "type": "gear",
                                                        "ratio": 2.0}])
    assert np.isfinite(Constant(1.0)(0.0)).all()


def test_gearbox_and_ideal_lossy_gear_reflect_inertia_by_ratio_squared():
    # gear 2 of the gearbox (1.5 × final drive 2) and an ideal lossy gear (ratio 0.5):
    # J_eq = J_a + J_b/i1² + J_c/(i1·i2)², all rigid
    i1, i2 = 1.5 * 2.0, 0.5
    net = chain([inertia("a", 0.4, load="T"), inertia("b", 0.9), inertia("c", 1.3)],
                [gearbox("gb", (3.0, 1.5), gear=2, final_drive=2.0), lossy_gear("lg", i2)])
    res = simulate(net.build(), (0, 2.0), {"T": 3.0}, options=OPTS)
    assert res.status == "completed"
    j_eq = 0.4 + 0.9 / i1**2 + 1.3 / (i1 * i2) ** 2
    assert res["omega_a"][-1] == pytest.approx(3.0 * 2.0 / j_eq, rel=1e-10)
    assert res["omega_b"][-1] == pytest.approx(res["omega_a"][-1] / i1, rel=1e-12)
    assert res["omega_c"][-1] == pytest.approx(res["omega_a"][-1] / (i1 * i2), rel=1e-12)
    # the kinetic energy is the work of the torque
    assert energy_balance(res)["energy_balance_rel"] < 1e-9


@pytest.mark.parametrize("eta", [1.0, 0.8, 0.5])
def test_lossy_gear_driving_forward_loses_one_minus_eta(eta):
    # a drives b through mesh efficiency eta: J_b·dw_b/dt = r·eta·T_a, so
    # dw_a/dt = tau / (J_a + J_b/(eta·r²)); the loss power (1-eta)·T_a·w_a is booked
    r, J_a, J_b, tau = 2.0, 0.5, 3.0, 4.0
    net = chain([inertia("a", J_a, omega0=1.0, load="T"), inertia("b", J_b, omega0=0.5)],
                [lossy_gear("g", r, (0.0, eta, 0.9, 0.0, 0.0))])
    res = simulate(net.build(), (0, 1.5), {"T": tau}, options=OPTS)
    assert res.status == "completed", res.message
    alpha = tau / (J_a + J_b / (eta * r**2))
    assert res["omega_a"][-1] == pytest.approx(1.0 + alpha * 1.5, rel=1e-10)
    assert np.all(res["g.mode"] == 1.0)
    t_a = tau - J_a * alpha                                   # torque into flange a
    assert res["T_loss_g"][-1] == pytest.approx((1 - eta) * t_a, rel=1e-9, abs=1e-12)
    eb = energy_balance(res)
    assert eb["W_friction"] == pytest.approx((1 - eta) * t_a * (1.0 * 1.5 + alpha * 1.5**2 / 2),
                                             rel=1e-8, abs=1e-12)
    assert eb["energy_balance_rel"] < 1e-9


def test_lossy_gear_sticks_until_the_load_beats_the_efficiency():
    # drive 10 N·m at a, load at b ramping the other way: with eta = 0.5 the gear stays
    # stuck while the load, referred to a, lies between eta·10 and 10/eta N·m
    from clutchsim.core import Ramp
    r = 2.0
    net = chain([inertia("a", 1.0, load="Ta"), inertia("b", 1.5, load="Tb")],
                [lossy_gear("g", r, (0.0, 0.5, 0.5, 0.0, 0.0))], inputs=("Ta", "Tb"))
    load = Ramp(0.0, 10.0, -60.0)                            # -6 N·m/s at b
    res = simulate(net.build(), (0, 8.0), {"Ta": 10.0, "Tb": load}, options=OPTS)
    assert res.status == "completed", res.message
    t_start_back = [e.t for e in res.events if e.name == "g: breakaway" and e.t > 0]
    # referred to a the load is 3·t N·m: forward rolling stops (the a-drive can no longer
    # push it through eta) and it sticks; it rolls back once 3·t > 10/0.5 = 20 N·m
    assert t_start_back and t_start_back[-1] == pytest.approx(20.0 / 3.0, abs=1e-6)
    stuck = (res["g.locked"] > 0.5)
    # at rest up to the round-off of the lock's projection (the stop is located within
    # event_tol, where the speed is ~1e-13 rad/s past zero; the projection leaves ~1e-29)
    assert np.all(np.abs(res["omega_a"][stuck]) <= 1e-20)
    assert res["omega_a"][-1] < 0.0


def test_one_way_clutch_drives_one_way_and_freewheels_the_other():
    from clutchsim.core import Step
    owc = {"name": "fw", "type": "one_way_clutch", "command": "f", "T_slide": 0.0}  # freewheel
    net = chain([inertia("in", 1.0, load="T"), inertia("out", 3.0)], [owc], inputs=("T", "f"))
    drive = Step(1.0, -6.0, 2.0)                              # +2 N·m, then -4 N·m at 1 s
    res = simulate(net.build({"f": 0.0}), (0, 2.0), {"T": drive, "f": 0.0}, options=OPTS)
    assert res.status == "completed", res.message
    # locked at the start (zero slip): in drives out, both accelerate at 2/4 rad/s²
    i1 = np.flatnonzero(res.t <= 1.0)[-1]
    assert res["omega_in"][i1] == pytest.approx(0.5, rel=1e-9)
    assert res["omega_out"][i1] == pytest.approx(0.5, rel=1e-9)
    # the reversed torque frees it: out keeps its speed, in slows down alone
    assert [e.name for e in res.events] == ["fw: breakaway"]
    assert res["omega_out"][-1] == pytest.approx(0.5, rel=1e-9)
    assert res["omega_in"][-1] == pytest.approx(0.5 - 4.0 * 1.0, rel=1e-9)
    assert np.min(res["w_slip_fw"]) >= -1e-12                 # never backwards


def test_linked_thermal_nodes_conserve_heat_and_equalise():
    net = chain([inertia("a", 1.0, omega0=50.0), inertia("b", 3.0)],
                [clutch("clutch", 20.0, 25.0, heat=[{"node": "surface", "share": 1.0}])],
                thermal=[{"name": "surface", "capacity": 50.0, "theta0": 20.0,
                          "link": "bulk", "link_conductance": 40.0},
                         {"name": "bulk", "capacity": 450.0, "theta0": 20.0}],
                inputs=("com",))
    res = simulate(net.build(), (0, 30.0), {"com": 1.0}, options=OPTS)
    assert res.status == "completed"
    heat = res["W_friction"][-1]
    stored = 50.0 * (res["theta_surface"][-1] - 20.0) + 450.0 * (res["theta_bulk"][-1] - 20.0)
    assert stored == pytest.approx(heat, rel=1e-8)
    # the small surface node runs ahead during slip, then the link equalises them
    assert np.max(res["theta_surface"] - res["theta_bulk"]) > 5.0
    assert res["theta_surface"][-1] == pytest.approx(res["theta_bulk"][-1], abs=1e-6)


# ----------------------------------------------------------------- gearbox efficiency
GB_R, GB_JA, GB_JB = 3.0, 0.2, 1.8


def _gearbox_chain(**losses):
    return chain([inertia("a", GB_JA, omega0=10.0, load="Ta"),
                  inertia("b", GB_JB, omega0=10.0 / GB_R, load="Tb")],
                 [gearbox("gb", (GB_R, 1.0), gear=1, **losses)], inputs=("Ta", "Tb"))


@pytest.mark.parametrize("eta", [1.0, 0.95, 0.7])
def test_gearbox_efficiency_driving_takes_one_minus_eta_of_the_input_torque(eta):
    # input drives output: J_b·dw_b/dt = r·eta·T_in with T_in = tau - J_a·dw_a/dt, so
    # dw_a/dt = tau / (J_a + J_b/(eta·r²)); the loss power (1-eta)·T_in·w_a is booked
    net = _gearbox_chain(efficiency=eta, efficiency_reverse=0.5)
    tau = 5.0
    res = simulate(net.build(), (0, 1.0), {"Ta": tau, "Tb": 0.0}, options=OPTS)
    assert res.status == "completed", res.message
    alpha = tau / (GB_JA + GB_JB / (eta * GB_R**2))
    assert res["omega_a"][-1] == pytest.approx(10.0 + alpha, rel=1e-10)
    assert res["omega_b"][-1] == pytest.approx((10.0 + alpha) / GB_R, rel=1e-12)
    eb = energy_balance(res)
    t_in = tau - GB_JA * alpha
    assert eb["W_friction"] == pytest.approx((1 - eta) * t_in * (10.0 + alpha / 2),
                                             rel=1e-8, abs=1e-12)
    assert eb["energy_balance_rel"] < 1e-9
    # the reverse efficiency alone makes a switching element; without any loss the
    # gearbox is a plain rigid gear
    def loss_elements(ch):
        return [c.name for c in ch.components if getattr(c, "friction", False)]
    assert loss_elements(net) == ["gb"]
    assert loss_elements(_gearbox_chain(efficiency=1.0)) == []


def test_gearbox_efficiency_reverse_applies_when_the_output_drives_the_input():
    # engine braking: the output side drives the input, power flows back through
    # efficiency_reverse: T_in = -J_a·dw_a/dt, output torque r·T_in/eta_rev, so
    # dw_b/dt = tau_b / (J_b + r²·J_a/eta_rev)
    eta_rev = 0.8
    net = _gearbox_chain(efficiency=0.95, efficiency_reverse=eta_rev)
    tau_b = 6.0
    res = simulate(net.build(), (0, 1.0), {"Ta": 0.0, "Tb": tau_b}, options=OPTS)
    assert res.status == "completed", res.message
    alpha_b = tau_b / (GB_JB + GB_R**2 * GB_JA / eta_rev)
    assert res["omega_b"][-1] == pytest.approx(10.0 / GB_R + alpha_b, rel=1e-10)
    t_in = -GB_JA * GB_R * alpha_b
    assert res["T_loss_gb"][-1] == pytest.approx((1 - 1 / eta_rev) * t_in, rel=1e-9)
    assert res["T_loss_gb"][-1] > 0.0                          # a loss, whatever the direction
    assert energy_balance(res)["energy_balance_rel"] < 1e-9


def test_gearbox_with_drag_torque_breaks_away_when_the_drive_beats_it():
    # at rest the drag torque (and the mesh efficiency) hold the gearbox: a ramp torque
    # k·t at the input turns it once k·t > drag/eta
    from clutchsim.core import Ramp
    eta, drag, k = 0.9, 1.8, 4.0
    net = chain([inertia("a", GB_JA, load="Ta"), inertia("b", GB_JB)],
                [gearbox("gb", (GB_R,), efficiency=eta, drag_torque=drag)], inputs=("Ta",))
    res = simulate(net.build(), (0, 1.0), {"Ta": Ramp(0.0, 1.0, k)}, options=OPTS)
    assert res.status == "completed", res.message
    t_break = [e.t for e in res.events if e.name == "gb: breakaway"]
    assert t_break and t_break[0] == pytest.approx(drag / (eta * k), abs=1e-8)
    before = res.t < t_break[0]
    assert np.all(res["omega_a"][before] == 0.0)
    assert res["omega_a"][-1] > 0.0
    assert energy_balance(res)["energy_balance_rel"] < 1e-8


def test_gearbox_efficiency_follows_a_shift():
    # gear 1 until 0.5 s, then gear 2: the ideal synchroniser conserves the angular
    # momentum referred to the output, r2·J_a·w_a + J_b·w_b; in each gear
    # dw_a/dt = tau / (J_a + J_b/(eta·r²)) with that gear's ratio
    eta, r1, r2, tau, ts = 0.9, 3.0, 1.5, 4.0, 0.5
    net = chain([inertia("a", GB_JA, omega0=10.0, load="Ta"),
                 inertia("b", GB_JB, omega0=10.0 / r1)],
                [gearbox("gb", (r1, r2), shifts=[{"time": ts, "gear": 2}], efficiency=eta)],
                inputs=("Ta",))
    res = simulate(net.build(), (0, 1.0), {"Ta": tau}, options=OPTS)
    assert res.status == "completed", res.message
    a1 = tau / (GB_JA + GB_JB / (eta * r1**2))
    a2 = tau / (GB_JA + GB_JB / (eta * r2**2))
    w_a0 = 10.0 + a1 * ts
    w_b0 = w_a0 / r1
    w_sync = (r2 * GB_JA * w_a0 + GB_JB * w_b0) / (r2**2 * GB_JA + GB_JB)
    w_b = w_sync + a2 / r2 * (1.0 - ts)
    assert res["omega_b"][-1] == pytest.approx(w_b, rel=1e-10)
    assert res["omega_a"][-1] == pytest.approx(w_b * r2, rel=1e-12)
    assert energy_balance(res)["energy_balance_rel"] < 1e-9


def test_gearbox_rejects_bad_efficiency_and_a_second_lossy_gear():
    def refusal(**kw):
        with pytest.raises(ScenarioError) as exc:
            chain([inertia("a", 1.0), inertia("b", 1.0)], [gearbox("gb", (3.0,), **kw)],
                  inputs=())
        return str(exc.value)
    assert "coupling[0].efficiency: = 0.0 is out of range: must be > 0" in \
        refusal(efficiency=0.0)
    assert "coupling[0].efficiency_reverse: = 1.1 is out of range: must be <= 1" in \
        refusal(efficiency_reverse=1.1)
    assert "coupling[0].drag_torque: = -1.0 N·m is out of range: must be >= 0 N·m" in \
        refusal(drag_torque=-1.0)
    with pytest.raises(ScenarioError, match=r"coupling\[1\]: lossy gear 'lg': a second gear "
                       r"with losses \(gearbox 'gb' is the first\)"):
        chain([inertia("a", 1.0), inertia("b", 1.0), inertia("c", 1.0)],
              [gearbox("gb", (3.0,), efficiency=0.9),
               lossy_gear("lg", 2.0, (0.0, 0.9, 0.9, 0.0, 0.0))], inputs=())


def test_gear_torque_sign_follows_flange_b_tau_and_input_units():
    # a torque T = 6 N·m drives inertia a; the gear (ratio 3) drives inertia c behind it.
    # Modelica's tau = flange_b.tau: the torque on c is -T_gear, so a gear accelerating the
    # inertia behind it reports a negative T_gear, like a clutch driving its disc.
    r, ja, jc = 3.0, 0.5, 2.0
    net = chain([inertia("a", ja, load="T"), inertia("c", jc)],
                [{"name": "gear", "type": "gear", "ratio": r}])
    res = simulate(net.build(), (0, 1.0), {"T": 6.0}, options=OPTS)
    alpha_c = 6.0 / (ja + jc / r**2) / r            # rad/s² of c
    assert res["omega_c"][-1] == pytest.approx(alpha_c, rel=1e-9)
    assert np.all(res["T_gear"][1:] < 0)
    assert res["T_gear"][-1] == pytest.approx(-jc * alpha_c, rel=1e-9)
    # braking c instead (the load torque reversed): the gear now holds c back, T_gear > 0
    res = simulate(net.build(), (0, 1.0), {"T": -6.0}, options=OPTS)
    assert res["T_gear"][-1] == pytest.approx(+jc * alpha_c, rel=1e-9)
    # the load input is a torque and carries its unit; a command is a fraction
    assert res.unit("T") == "N·m"
    net = chain([inertia("a", ja, load="T"), inertia("c", jc)],
                [clutch("clutch", 5.0, 6.0)], inputs=("T", "com"))
    system = net.build({"com": 1.0})
    assert dict(zip(system.input_names, system.input_units)) == {"T": "N·m", "com": "-"}
