"""Lossy gears, gearboxes with shifts and one-way clutches as network components."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from clutchsim.analysis.launch_metrics import energy_balance
from clutchsim.core import SolverOptions, simulate
from clutchsim.core.system import call_jac, call_rhs
from clutchsim.network import Network, NetworkError, compile_network
from clutchsim.network import components as nc
from clutchsim.scenario import resolve_scenario, run_scenario

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _run_example(name):
    sc = resolve_scenario(EXAMPLES / f"{name}.toml")
    net = sc.network(sc.models[0] if sc.models else None)
    u0 = {n: float(np.asarray(s(0.0)).ravel()[0]) for n, s in sc.inputs.items()}
    system = net.build(u0)
    res = simulate(system, (0.0, sc.t_end), {n: sc.inputs[n] for n in system.input_names},
                   solver=sc.solver, options=sc.options)
    assert res.status == "completed", res.message
    return system, res


def _jacobian_error(system, res, rows=30):
    """Largest relative difference between the exact Jacobian and central differences of
    the right-hand side, at ``rows`` states along the run (each mode as it was).  The
    temperature rows are left out: the heat |T·w| has a kink at the zero slip a model-(6)
    clutch sits near after lock-up, where a difference quotient averages both sides."""
    Y = np.column_stack([res[s] for s in system.state_names])
    U = np.column_stack([res[s] for s in system.input_names])
    n = system.n_states
    p = system.params.copy()
    worst = 0.0
    for k in np.linspace(1, len(res.t) - 2, rows).astype(int):
        y, u, t = Y[k].copy(), U[k].copy(), float(res.t[k])
        J = np.zeros((n, n))
        call_jac(system.tag, t, y, u, p, J)
        Jd = np.zeros((n, n))
        for j in range(n):
            h = 1e-8 * (1.0 + abs(y[j]))
            yp, ym = y.copy(), y.copy()
            yp[j] += h
            ym[j] -= h
            fp, fm = np.zeros(n), np.zeros(n)
            call_rhs(system.tag, t, yp, u, p, fp)
            call_rhs(system.tag, t, ym, u, p, fm)
            Jd[:, j] = (fp - fm) / (2.0 * h)
        err = np.abs(J - Jd) / (1.0 + np.abs(Jd))
        err[[i for i, s in enumerate(system.state_names) if s.startswith("theta_")], :] = 0.0
        worst = max(worst, float(np.max(err)))
    return worst


@pytest.mark.parametrize("example", ["lossy_gear_demo1", "lossy_gear_demo3", "tip_out"])
def test_exact_jacobian_of_a_rolling_lossy_gear(example):
    """The loss depends on every torque through the transmitted torque: the generated
    Jacobian carries that (unit-loss response), checked against central differences."""
    system, res = _run_example(example)
    assert _jacobian_error(system, res) < 1e-4


def _shift_net(J1=0.2, J2=1.5, w1=40.0, ratios=(2.0, 1.0), t_shift=0.05):
    comps = [nc.Inertia("inp", J=J1, omega0=w1),
             nc.Gearbox("gb", ratios, shifts=((t_shift, 2),)),
             nc.Inertia("out", J=J2, omega0=w1 / ratios[0])]
    conns = [("inp.b", "gb.a"), ("gb.b", "out.a")]
    return Network(comps, conns, name="shift")


def test_gear_shift_synchroniser_conserves_angular_momentum():
    """Free shafts, gear 1 (ratio 2) -> gear 2 (ratio 1) at 0.05 s: afterwards the output
    speed is (r'·J1·w1 + J2·w2)/(r'²·J1 + J2) (the angular impulse of the synchroniser,
    referred through the new ratio r'), the input r' times that, and the kinetic energy lost
    is W_sync."""
    J1, J2, w1 = 0.2, 1.5, 40.0
    net = _shift_net(J1, J2, w1)
    plan = compile_network(net)
    system = plan.system()
    res = simulate(system, (0.0, 0.1), {}, solver="rodas5p",
                   options=SolverOptions(rtol=1e-10, atol=1e-12))
    assert res.status == "completed", res.message
    assert [e.name for e in res.events] == ["gb: shift to gear 2 at 0.05 s"]
    w2 = w1 / 2.0
    v = (1.0 * J1 * w1 + J2 * w2) / (1.0 * J1 + J2)
    assert res["omega_out"][-1] == pytest.approx(v, rel=1e-12)
    assert res["omega_inp"][-1] == pytest.approx(v, rel=1e-12)
    ke0 = 0.5 * (J1 * w1 ** 2 + J2 * w2 ** 2)
    ke1 = 0.5 * (J1 + J2) * v ** 2
    assert res["W_sync"][-1] == pytest.approx(ke0 - ke1, rel=1e-10)
    assert res["ratio_gb"][0] == 2.0 and res["ratio_gb"][-1] == 1.0
    assert res["gear_gb"][0] == 1.0 and res["gear_gb"][-1] == 2.0
    # the System is unchanged by the run: a second run gives the same answer
    again = simulate(system, (0.0, 0.1), {}, solver="rodas5p",
                     options=SolverOptions(rtol=1e-10, atol=1e-12))
    assert np.array_equal(again["omega_out"], res["omega_out"])


def test_shift_times_are_values_not_structure():
    """Another shift time reuses the compiled plant: only the banks of values change."""
    a = compile_network(_shift_net(t_shift=0.05))
    b = compile_network(_shift_net(t_shift=0.07))
    assert a is b
    res = simulate(a.system(_shift_net(t_shift=0.07).components), (0.0, 0.1), {},
                   solver="rodas5p")
    assert [round(e.t, 9) for e in res.events] == [0.07]


def test_upshift_launch_balances_energy():
    """The 1-2 upshift with a lossy gearbox (model (6) clutch): the energy balance closes
    with W_sync and the gearbox's loss in W_friction."""
    r = run_scenario(EXAMPLES / "shift_1_2.toml", "mykhailevych2020")
    assert r.result.status == "completed", r.result.message
    assert any("shift to gear 2" in e.name for e in r.result.events)
    assert r.metrics["energy_balance_rel"] <= 1e-5
    assert energy_balance(r.result)["W_sync"] > 0.0
    assert r.result["ratio_gearbox"][-1] == pytest.approx(2.1 * 4.1)


def test_one_lossy_gear_per_network():
    comps = [nc.Inertia("a", J=1.0), nc.LossyGear("g1", ratio=2.0,
                                                  loss_table=((0.0, 0.9, 0.9, 0.0, 0.0),)),
             nc.Inertia("b", J=1.0), nc.LossyGear("g2", ratio=2.0,
                                                  loss_table=((0.0, 0.9, 0.9, 0.0, 0.0),)),
             nc.Inertia("c", J=1.0)]
    net = Network(comps, [("a.b", "g1.a"), ("g1.b", "b.a"), ("b.b", "g2.a"), ("g2.b", "c.a")])
    with pytest.raises(NetworkError, match="lossy gear 'g2': a second gear with losses"):
        compile_network(net)


@pytest.mark.parametrize(("kwargs", "match"), [
    ({"loss_table": ((0.0, 0.0, 0.9, 0.0, 0.0),)}, r"eta_mf1\[0\] = 0 must be in \(0, 1\]"),
    ({"loss_table": ((0.0, 0.9, 0.9, -1.0, 0.0),)}, r"tau_bf1\[0\] = -1 N·m must be >= 0"),
    ({"loss_table": ((1.0, 0.9, 0.9, 0.0, 0.0), (0.5, 0.9, 0.9, 0.0, 0.0))},
     r"speed\[1\] = 0.5 rad/s must be greater"),
    ({"ratio": 0.0}, r"ratio = 0 must be in \[-1000, 1000\], non-zero"),
])
def test_lossy_gear_bad_values(kwargs, match):
    args = {"ratio": 2.0, **kwargs}
    with pytest.raises(ValueError, match=match):
        nc.LossyGear("g", **args)


def test_gearbox_and_one_way_bad_values():
    with pytest.raises(ValueError, match=r"gear 4 does not exist; this gearbox has 2 gears"):
        nc.Gearbox("gb", (2.0, 1.0), shifts=((1.0, 4),))
    with pytest.raises(ValueError, match="shift time -1 s must be > 0"):
        nc.Gearbox("gb", (2.0, 1.0), shifts=((-1.0, 2),))
    with pytest.raises(ValueError, match="ratios = .* each ratio > 0"):
        nc.Gearbox("gb", (2.0, -1.0))
    with pytest.raises(ValueError, match=r"peak = 0.5 must be in \[1, 100\]"):
        nc.OneWayClutch("owc", "f", T_slide=1.0, peak=0.5)
    owc = [nc.Inertia("a", J=1.0, omega0=1.0), nc.OneWayClutch("owc", "f", T_slide=1.0),
           nc.Inertia("b", J=1.0, omega0=0.0)]
    net = Network(owc, [("a.b", "owc.a"), ("owc.b", "b.a")])
    with pytest.raises(ValueError, match="omega_b - omega_a = -1 rad/s is negative"):
        compile_network(net).system(inputs0={"f": 0.0})


NETWORK_SCENARIO = """
[scenario]
name = "geared"
t_end = 0.2
expect_lockup = false

[solver]
method = "rodas5p"
rtol = 1e-9
atol = 1e-11

[inputs]
tau = 5.0
f = 0.0

[network]
connect = [
    ["drive.flange", "motor.a"],
    ["motor.b", "gb.a"],
    ["gb.b", "mid.a"],
    ["mid.b", "lg.a"],
    ["lg.b", "free.a"],
    ["free.b", "owc.a"],
    ["owc.b", "out.a"],
]

[[component]]
type = "torque"
name = "drive"
input = "tau"

[[component]]
type = "inertia"
name = "motor"
J = 0.1

[[component]]
type = "gearbox"
name = "gb"
ratios = [3.0, 1.5]
shifts = [{ time = 0.1, gear = 2 }]

[[component]]
type = "inertia"
name = "mid"
J = 0.2

[[component]]
type = "lossy_gear"
name = "lg"
ratio = 2.0
loss_table = { speed = [0.0], eta_mf1 = [0.8], eta_mf2 = [0.8], tau_bf1 = [0.0], tau_bf2 = [0.0] }

[[component]]
type = "inertia"
name = "free"
J = 0.3

[[component]]
type = "one_way_clutch"
name = "owc"
command = "f"
T_slide = 2.0

[[component]]
type = "inertia"
name = "out"
J = 0.5
"""


def test_network_scenario_with_gearbox_lossy_gear_and_one_way_clutch(tmp_path):
    """The three as ``[[component]]`` types: the drive accelerates the line through the
    lossy gear (80 % passes) and locks the freewheel; the shift changes the ratio once."""
    path = tmp_path / "geared.toml"
    path.write_text(NETWORK_SCENARIO)
    r = run_scenario(path)
    res = r.result
    assert res.status == "completed", res.message
    assert r.metrics["energy_balance_rel"] <= 1e-8
    assert [e.name for e in res.events if "shift" in e.name] == ["gb: shift to gear 2 at 0.1 s"]
    # the freewheel blocks (flange a drives b): locked all the way, w_slip 0
    assert np.all(res["owc.locked"] == 1.0)
    assert np.max(np.abs(res["w_slip_owc"])) < 1e-9
    # the lossy gear dissipates (1 - 0.8) of what it takes
    assert np.all(res["P_lg"] >= -1e-12) and res["W_friction"][-1] > 0.0


def test_network_scenario_bad_gearbox_gear_names_file_and_key(tmp_path):
    from clutchsim.scenario import ScenarioError
    path = tmp_path / "bad.toml"
    path.write_text(NETWORK_SCENARIO.replace("gear = 2 }", "gear = 5 }"))
    with pytest.raises(ScenarioError, match=r"bad.toml.*component\[2\].*gear 5 does not exist"):
        resolve_scenario(path).network()
