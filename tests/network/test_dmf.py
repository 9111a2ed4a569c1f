"""Dual-mass flywheel (``dual_mass_flywheel``): the quasi-static hysteresis loop of the arc
spring and the friction ring in closed form (all stages and the end stop), isolation above
its resonance and the energy balance with several friction models, the exact Jacobian,
bad input."""

import numpy as np
import pytest
from test_network import _jac_fd

from clutchsim.analysis.launch_metrics import energy_balance
from clutchsim.core import SolverOptions, simulate
from clutchsim.core.signals import Sine
from clutchsim.friction import CoulombRobust, LuGre, TanhFriction
from clutchsim.network import Network
from clutchsim.network.components import DualMassFlywheel, TorqueSource

SPRING = {"c": 300.0, "knee": 0.3, "c2": 1000.0, "stop": 0.35, "c_stop": 1e5}
J1, J2 = 0.12, 0.07


def spring(x):
    """The arc spring's torque [N·m] at twist x >= 0 (stages and stop, SPRING)."""
    c, k, c2, st, cs = (SPRING[k] for k in ("c", "knee", "c2", "stop", "c_stop"))
    if x <= k:
        return c * x
    if x <= st:
        return c * k + c2 * (x - k)
    return c * k + c2 * (st - k) + cs * (x - st)


def twist_at(torque):
    """Inverse of :func:`spring` (bisection)."""
    lo, hi = 0.0, 1.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if spring(mid) < torque else (lo, mid)
    return 0.5 * (lo + hi)


def held_primary(model, d=2.0):
    """The primary held by the housing, a torque on the secondary."""
    dmf = DualMassFlywheel("dmf", model, J_primary=J1, J_secondary=J2, d=d, **SPRING)
    return Network([dmf, TorqueSource("load", input="tau")],
                   [["dmf.primary", "ground"], ["dmf.secondary", "load.flange"]])


@pytest.mark.parametrize("amplitude", [135.0, 160.0])
def test_quasi_static_hysteresis_loop_in_closed_form(amplitude):
    """A slow torque A·sin(2π·0.05 Hz·t) on the secondary: the ring slips while the torque
    exceeds spring + F, so the twist peaks where spring(φ) = A − F (second stage for A =
    135 N·m, on the end stop for A = 160 N·m); then the ring sticks until the torque has
    fallen by 2F: break-away where A·sin = spring(φ_max) − F."""
    F, f = 10.0, 0.05
    sys_ = held_primary(CoulombRobust(F_c=F, F_s=F)).build({"tau": 0.0})
    res = simulate(sys_, (0.0, 8.0), {"tau": Sine(amplitude, f)},
                   options=SolverOptions(rtol=1e-9, atol=1e-11, dt_out=1e-3))
    assert res.status == "completed", res.message
    phi_max = twist_at(amplitude - F)
    assert np.max(res["phi_dmf"]) == pytest.approx(phi_max, abs=2e-4 * phi_max)
    t_break = (np.pi - np.arcsin((spring(phi_max) - F) / amplitude)) / (2 * np.pi * f)
    later = [e.t for e in res.events if e.name == "dmf: breakaway" and e.t > 5.0]
    assert later[0] == pytest.approx(t_break, abs=2e-3)
    stuck = (res.t > 5.2) & (res.t < t_break - 0.05)
    assert np.ptp(res["phi_dmf"][stuck]) < 1e-6 * phi_max
    events = {e.name for e in res.events}
    assert "dmf: arc spring second stage" in events
    assert ("dmf: end stop" in events) == (amplitude > 140.0 + F)
    assert energy_balance(res)["energy_balance_rel"] < 1e-6


@pytest.mark.parametrize("model", [CoulombRobust(F_c=3.0, F_s=4.0),
                                   TanhFriction(F_c=3.0, v_t=0.05, sigma2=0.0),
                                   LuGre(F_c=3.0, F_s=4.0, v_s=0.1, sigma0=2e4, sigma1=20.0,
                                         sigma2=0.0, delta=2.0)],
                         ids=lambda m: m.name)
def test_isolation_above_resonance_and_energy_balance(model):
    """Engine-like firing torque 50 + 80·sin(2π·40 Hz·t) on the primary and 50 N·m taken
    off the secondary, a friction ring of 3-4 N·m: at 40 Hz, far above the DMF's resonance
    (sqrt(c·(1/J1 + 1/J2))/2π = 13 Hz), the secondary's speed ripple is a fraction of the
    primary's; the energy balance closes with each friction model."""
    dmf = DualMassFlywheel("dmf", model, J_primary=J1, J_secondary=J2, d=0.5, omega0=100.0,
                           **SPRING)
    net = Network([TorqueSource("engine", input="tau"), dmf, TorqueSource("load", input="tl")],
                  [["engine.flange", "dmf.primary"], ["dmf.secondary", "load.flange"]])
    res = simulate(net.build({"tau": 50.0, "tl": -50.0}), (0.0, 1.0),
                   {"tau": Sine(80.0, 40.0, offset=50.0), "tl": -50.0},
                   options=SolverOptions(rtol=1e-8, atol=1e-10, dt_out=2e-4))
    assert res.status == "completed", res.message
    late = res.t > 0.5
    ripple1 = np.ptp(res["omega_dmf_primary"][late])
    ripple2 = np.ptp(res["omega_dmf_secondary"][late])
    assert ripple1 > 0.5 and ripple2 < 0.5 * ripple1
    assert energy_balance(res)["energy_balance_rel"] < 1e-6


@pytest.mark.parametrize("phi, w_rel", [(0.1, 0.4), (-0.32, 0.2), (0.36, -0.3), (-0.2, -1.0)])
def test_exact_jacobian_in_every_stage(phi, w_rel):
    sys_ = held_primary(TanhFriction(F_c=10.0, v_t=0.05, sigma2=0.0), d=1.5).build()
    names = sys_.state_names
    y = sys_.y0.copy()
    y[names.index("omega_dmf_secondary")] = w_rel
    y[names.index("phi_dmf")] = phi
    J, Jfd = _jac_fd(sys_, y, np.zeros(1))
    assert np.max(np.abs(J - Jfd) / np.maximum(np.abs(Jfd), 1.0)) < 1e-6


def test_bad_dmf_names_component_key_value_and_rule():
    with pytest.raises(ValueError, match=r"dual mass flywheel 'dmf': stop = 0.2 rad must lie "
                                         r"beyond knee = 0.3 rad"):
        DualMassFlywheel("dmf", CoulombRobust(F_c=1.0, F_s=1.0), J_primary=J1,
                         J_secondary=J2, c=300.0, knee=0.3, c2=1000.0, stop=0.2, c_stop=1e5)
    with pytest.raises(ValueError, match=r"needs c_stop > 0"):
        DualMassFlywheel("dmf", CoulombRobust(F_c=1.0, F_s=1.0), J_primary=J1,
                         J_secondary=J2, c=300.0, stop=0.2)


def test_launch_with_dmf_moves_the_isolating_mode_below_idle():
    """examples/launch_dmf.toml, linearised after lock-up (3.5 s): with the friction ring
    slipping (large amplitudes) the DMF adds a mode at the two-mass estimate
    sqrt(c·(1/J_p + 1/J_s))/2π (J_p: crankshaft + primary; J_s: secondary, disc and
    gearbox input; the driveshaft decouples the rest) below the idle firing frequency,
    where the launch of launch.toml has its disc-damper mode far above it; with the ring
    stuck (small amplitudes) the DMF is rigid.  The shuffle mode stays at ~3.2 Hz."""
    from _dl_paths import EXAMPLES

    from clutchsim.analysis.linear import linearise, modes
    from clutchsim.analysis.linear import operating_point as op
    from clutchsim.scenario import load_scenario
    pt = op(load_scenario(EXAMPLES / "launch_dmf.toml"), "coulomb-robust", 3.5)
    names = pt.system.state_names
    assert pt.y[names.index("dmf.locked")] == 1.0 and pt.y[names.index("clutch.locked")] == 1.0
    found = {}
    for ring in ("stuck", "slipping"):
        y = pt.y.copy()
        y[names.index("dmf.locked")] = 0.0 if ring == "slipping" else 1.0
        # slipping: sliding forward (a constant friction torque); an unlocked ring left in
        # its stuck mode would hold by its stick torque, as the exact Jacobian says
        y[names.index("dmf.mode")] = 1.0 if ring == "slipping" else 0.0
        lin = linearise(pt.system, pt.t_s, y, pt.u)
        found[ring] = [m.frequency_hz for m in modes(lin) if m.frequency_hz > 0.0]
    estimate = np.sqrt(400.0 * (1 / 0.09 + 1 / (0.06 + 0.015 + 0.01))) / (2 * np.pi)
    assert found["stuck"] == [pytest.approx(3.2, abs=0.1)]
    shuffle, dmf_mode = found["slipping"]
    assert shuffle == pytest.approx(3.2, abs=0.1)
    assert dmf_mode == pytest.approx(estimate, rel=0.05)
    idle_firing_hz = 2 * 800.0 / 60.0                  # four cylinders, two firings a turn
    assert dmf_mode < 0.6 * idle_firing_hz
    single = op(load_scenario(EXAMPLES / "launch.toml"), "coulomb-robust", 3.5)
    lin = linearise(single.system, single.t_s, single.y, single.u)
    assert max(m.frequency_hz for m in modes(lin)) > 2 * idle_firing_hz


def test_dmf_stop_inside_the_first_stage_in_a_scenario_gives_file_and_line(tmp_path):
    from _dl_paths import EXAMPLES

    from clutchsim.scenario import ScenarioError, load_scenario
    text = (EXAMPLES / "launch_dmf.toml").read_text(encoding="utf-8")
    old = "stop = 0.6                # end stop at 34° (350 N·m)"
    assert old in text
    path = tmp_path / "dmf.toml"
    path.write_text(text.replace(old, "stop = 0.4"), encoding="utf-8")
    lines = path.read_text(encoding="utf-8").splitlines()
    table = max(i for i, s in enumerate(lines[:lines.index('name = "dmf"')], 1)
                if s == "[[component]]")
    with pytest.raises(ScenarioError) as exc:
        load_scenario(path).network()
    msg = str(exc.value)
    assert f"dmf.toml:{table}: component[2]: dual mass flywheel 'dmf'" in msg
    assert "stop = 0.4 rad must lie beyond knee = 0.5 rad" in msg
