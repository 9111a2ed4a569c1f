"""Physics of the chain plant: rigid clusters, reflected inertia, heat, energy."""

import numpy as np
import pytest

from clutchsim.core import Constant, SolverOptions, simulate
from clutchsim.driveline import (Chain, FrictionElement, Gear, Inertia, SpringDamper,
                                 ThermalNode)
from clutchsim.driveline.run import energy_balance
from clutchsim.friction import make_model

OPTS = SolverOptions(rtol=1e-9, atol=1e-10)


def test_locked_driveline_accelerates_as_one_inertia_with_reflected_gear_inertia():
    r = 3.0
    strong = make_model("coulomb-robust", F_c=1e3, F_s=1e3)
    chain = Chain([Inertia("a", 0.5, load="T"), Inertia("b", 0.2), Inertia("c", 2.0)],
                  [FrictionElement("clutch", strong, "com"), Gear("gear", r)])
    sys_ = chain.build({"com": 1.0})
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
    slip = make_model("coulomb-robust", F_c=20.0, F_s=25.0)
    chain = Chain([Inertia("a", 1.0, omega0=50.0), Inertia("b", 3.0)],
                  [FrictionElement("clutch", slip, "com", heat=(("plate", 1.0),))],
                  thermal=[ThermalNode("plate", capacity=500.0, theta0=20.0)])
    res = simulate(chain.build(), (0, 3.0), {"com": 1.0}, options=OPTS)
    assert res.status == "completed"
    heat = res["W_friction"][-1]
    assert heat == pytest.approx(0.5 * 1.0 * 50**2 - 0.5 * 4.0 * 12.5**2, rel=1e-6)
    assert res["theta_plate"][-1] - 20.0 == pytest.approx(heat / 500.0, rel=1e-8)


def test_spring_damper_energy_balance_and_two_stage_spring():
    chain = Chain([Inertia("a", 1.0, omega0=5.0), Inertia("b", 1.0)],
                  [SpringDamper("s", c=100.0, d=0.5, knee=0.05, c2=400.0)])
    res = simulate(chain.build(), (0, 2.0), {}, options=OPTS)
    eb = energy_balance(res)
    assert eb["W_damping"] > 0
    assert eb["energy_balance_rel"] < 1e-7
    # momentum is conserved by an internal spring
    assert res["omega_a"][-1] + res["omega_b"][-1] == pytest.approx(5.0, rel=1e-9)


def test_chain_rejects_bad_layout():
    with pytest.raises(ValueError, match="need 1 couplings"):
        Chain([Inertia("a", 1.0), Inertia("b", 1.0)], [])
    with pytest.raises(ValueError, match="J = 0 kg·m² must be > 0"):
        Inertia("a", 0.0)
    assert np.isfinite(Constant(1.0)(0.0)).all()
