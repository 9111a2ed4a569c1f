"""Lining wear (clutchsim.network.wear): the quadrature state against closed forms, its
exact Jacobian row, the clamp table at the wear-shifted position, and bad input."""

import math

import numpy as np
import pytest
from test_network import _jac_fd

from clutchsim.core import SolverOptions, simulate
from clutchsim.friction import CoulombRobust
from clutchsim.network import Network
from clutchsim.network.components import Brake, Inertia, ThermalNode
from clutchsim.network.wear import GAS_CONSTANT, WearLaw
from clutchsim.scenario import ScenarioError, load_scenario

T_BRAKE, OMEGA, AREA = 20.0, 100.0, 0.02


def _slipping(law, capacity, theta0=40.0):
    """A brake (coulomb-robust, 20 N·m) slipping under a drum so heavy (1e12 kg·m²) that
    its speed, and the friction power 2 kW, stay constant to 1e-10; all heat into one
    adiabatic node of heat capacity ``capacity``."""
    net = Network([Inertia("drum", J=1e12, omega0=OMEGA),
                   Brake("brake", CoulombRobust(F_c=T_BRAKE, F_s=T_BRAKE), command="f",
                         heat=[("pad", 1.0)], wear=law),
                   ThermalNode("pad", capacity=capacity, theta0=theta0)],
                  [["drum.a", "brake.flange"]])
    return net.build({"f": 1.0})


def test_constant_power_wear_with_arrhenius_factor_matches_closed_form():
    """Constant temperature (a 1e15 J/K node): h = k_w·exp(E_a/R·(1/T_ref − 1/T))·P·t/A."""
    law = WearLaw(k_w=3e-13, area=AREA, reserve=1.5e-3, lining=3e-3, E_a=25e3,
                  theta_ref=100.0)
    sys_ = _slipping(law, 1e15, theta0=180.0)
    res = simulate(sys_, (0.0, 10.0), {"f": 1.0}, options=SolverOptions(rtol=1e-10,
                                                                          atol=1e-14))
    P = T_BRAKE * OMEGA
    k = 3e-13 * math.exp(25e3 / GAS_CONSTANT * (1 / 373.15 - 1 / 453.15))
    assert res["wear_brake"][-1] == pytest.approx(k * P * 10.0 / AREA, rel=1e-8)
    assert law.rate(P, 180.0) == pytest.approx(k * P / AREA, rel=1e-14)


def test_constant_power_wear_past_the_critical_temperature_matches_closed_form():
    """E_a = 0, the node heats at P/C = 2 K/s from 40 °C and passes θ_crit = 50 °C at
    t_c = 5 s: h = k_w·P/A·(t + g·(P/C)·(t − t_c)²/2)."""
    C, g = 1000.0, 0.05
    law = WearLaw(k_w=3e-13, area=AREA, reserve=1.5e-3, lining=3e-3, theta_crit=50.0,
                  crit_gain=g)
    sys_ = _slipping(law, C)
    t = 12.0
    res = simulate(sys_, (0.0, t), {"f": 1.0}, options=SolverOptions(rtol=1e-10, atol=1e-14))
    P = T_BRAKE * OMEGA
    assert res["theta_pad"][-1] == pytest.approx(40.0 + P / C * t, rel=1e-9)
    want = 3e-13 * P / AREA * (t + g * (P / C) * (t - 5.0) ** 2 / 2)
    assert res["wear_brake"][-1] == pytest.approx(want, rel=1e-6)
    # the wear is a quadrature: the last state, outside the implicit solve
    assert sys_.state_names[-1] == "wear_brake" and sys_.quadratures == 7


def test_wear_row_of_the_generated_jacobian_matches_differences():
    sc = load_scenario("examples/launch_wear.toml")
    sys_ = sc.network("mykhailevych2020").build(sc.inputs0())
    names = sys_.state_names
    y = sys_.y0.copy()
    y[names.index("omega_engine")] = 150.0
    y[names.index("omega_disc")] = 120.0
    y[names.index("omega_gearbox_input")] = 120.3
    y[names.index("omega_wheels")] = 120.0 / 14.76
    y[names.index("clutch.phi")] = 1.5e-3
    for th in (180.0, 270.0):           # below and above theta_crit = 250 °C
        y[names.index("theta_pressure_plate")] = th
        u = np.zeros(len(sys_.input_names))
        u[sys_.input_names.index("clutch_command")] = 0.7
        u[sys_.input_names.index("throttle")] = 0.3
        J, Jfd = _jac_fd(sys_, y, u)
        r = names.index("wear_clutch")
        row = Jfd[r]
        assert np.any(row != 0.0)
        assert np.max(np.abs(J[r] - row)) <= 1e-6 * np.max(np.abs(row))


def test_clamp_force_after_wear_is_the_table_at_the_shifted_position():
    """The engaged clutch's capacity output after wear h equals the static capacity times
    the clamp table at 1 + shift·h (np.interp of the table), on the rising and the falling
    side of the Belleville characteristic."""
    sc = load_scenario("examples/launch_wear.toml")
    net = sc.network("coulomb-robust")
    from clutchsim.network import compile_network
    plan = compile_network(net)
    clutch = next(c for c in net.components if c.name == "clutch")
    law = clutch.wear
    xs, ys = clutch.clamp_table
    for h in (0.0, 0.3e-3, 0.6e-3, 1.2e-3, 1.45e-3):
        comps = [c.with_values(wear0=h, installed_shift=law.shift * h) if c.name == "clutch"
                 else c for c in net.components]
        sys_ = plan.system(comps, inputs0=sc.inputs0())
        inputs = {n: 1.0 if n == "clutch_command" else 0.1 for n in sys_.input_names}
        res = simulate(sys_, (0.0, 1e-3), inputs)
        cap = res["capacity_clutch"][0]       # 40 °C: mu(theta) factor 1
        assert cap == pytest.approx(240.0 * np.interp(1.0 + law.shift * h, xs, ys), rel=1e-12)
        assert res["wear_clutch"][0] == h


@pytest.mark.parametrize("key,value,words", [
    ("k_w", -1e-13, ["k_w = -1e-13", "must be >= 0"]),
    ("reserve", 4e-3, ["reserve = 0.004", "lining = 0.003", "cannot exceed"]),
    ("crit_gain", -0.1, ["crit_gain = -0.1", ">= 0"]),
    ("k_wear", 1.0, ["unknown key 'k_wear'"]),
])
def test_bad_wear_law_names_file_line_and_key(tmp_path, key, value, words):
    text = (load_scenario("examples/launch_wear.toml").text)
    line = next(ln for ln in text.splitlines() if ln.startswith("wear = {"))
    if key == "k_wear":
        bad_line = line.replace("k_w = 3e-13", f"k_wear = {value}")
    else:
        import re
        bad_line = re.sub(rf"\b{key} = [^,}}]+", f"{key} = {value}", line)
    f = tmp_path / "bad.toml"
    f.write_text(text.replace(line, bad_line))
    with pytest.raises(ScenarioError) as exc:
        load_scenario(f)
    msg = str(exc.value)
    n = text.splitlines().index(line) + 1
    assert f"{f}:{n}:" in msg and "coupling[0].wear" in msg
    for w in words:
        assert w in msg
