"""Torque converter (``torque_converter``): the turbine's spin-up in closed form, the torques
against the tables at drive, coast and fade states, the exact Jacobian (with a moving
housing), the launch and lock-up example, bad tables."""

import numpy as np
import pytest
from test_network import _jac_fd

from clutchsim.core import SolverOptions, simulate
from clutchsim.core.system import call_outputs
from clutchsim.network import Network
from clutchsim.network.components import Inertia, TorqueConverter, TorqueSource

#: the example's maps (examples/converter_launch.toml)
MAPS = {"speed_ratio": [0.0, 0.25, 0.5, 0.75, 0.9], "K": [15.0, 15.0, 15.0, 16.0, 18.0],
        "torque_ratio": [2.0, 1.8, 1.5, 1.15, 1.0]}


def rig(maps=MAPS, J_pump=0.2, w_pump=100.0, housing=False):
    comps = [TorqueSource("drive", input="tau"), Inertia("pump", J=J_pump, omega0=w_pump),
             TorqueConverter("tc", **maps), Inertia("turbine", J=0.5)]
    conn = [["drive.flange", "pump.a"], ["pump.b", "tc.pump"], ["tc.turbine", "turbine.a"]]
    if housing:
        comps.append(Inertia("housing", J=3.0))
        conn.append(["tc.support", "housing.a"])
    return Network(comps, conn)


def expected(wp, wt, maps=MAPS):
    """(pump torque, turbine torque) from the tables, written out independently."""
    sr, k, tr = (np.asarray(maps[key]) for key in ("speed_ratio", "K", "torque_ratio"))
    drive = wp >= wt
    hi, lo = (wp, wt) if drive else (wt, wp)
    nu = lo / hi
    fade = 1.0 if nu <= sr[-1] else (1.0 - nu) / (1.0 - sr[-1])
    T = fade * (hi / np.interp(nu, sr, k)) ** 2
    return (T, np.interp(nu, sr, tr) * T) if drive else (-T, -T)


def test_turbine_spin_up_in_closed_form():
    """Constant K = 10 rad/s/sqrt(N·m) and torque ratio 1 up to the coupling point 0.8, the
    pump held at 100 rad/s by a huge inertia, the turbine (0.5 kg·m²) from rest: it gains
    (100/10)²/0.5 = 200 rad/s² until ν = 0.8 (t = 0.4 s), then J·dω/dt = 100·(1 − ν)/0.2
    brings it to the pump's speed with τ = 0.1 s: ω = 100 − 20·exp(−(t − 0.4)/0.1)."""
    maps = {"speed_ratio": [0.0, 0.8], "K": [10.0, 10.0], "torque_ratio": [1.0, 1.0]}
    res = simulate(rig(maps, J_pump=1e8).build(), (0.0, 1.0), {"tau": 0.0},
                   options=SolverOptions(rtol=1e-10, atol=1e-12, dt_out=1e-3))
    assert res.status == "completed", res.message
    t = res.t
    w = np.where(t <= 0.4, 200.0 * t, 100.0 - 20.0 * np.exp(-(t - 0.4) / 0.1))
    assert np.max(np.abs(res["omega_turbine"] - w)) < 1e-4
    assert np.max(np.abs(res["omega_pump"] - 100.0)) < 1e-5


@pytest.mark.parametrize("wp, wt", [(100.0, 0.0), (120.0, 40.0), (150.0, 120.0),
                                    (200.0, 190.0), (60.0, 90.0), (95.0, 100.0), (0.0, 0.0)])
def test_torques_follow_the_tables(wp, wt):
    """Stall (torque ratio 2), converter range, the fade above the coupling point, coast
    (a fluid coupling: the turbine drives the pump) and rest."""
    sys_ = rig().build()
    y = sys_.y0.copy()
    names = sys_.state_names
    y[names.index("omega_pump")], y[names.index("omega_turbine")] = wp, wt
    out = np.zeros(len(sys_.output_names))
    call_outputs(sys_.tag, 0.0, y, np.zeros(1), sys_.params, out)
    got = (out[sys_.output_names.index("T_pump_tc")], out[sys_.output_names.index("T_turbine_tc")])
    want = expected(wp, wt) if max(wp, wt) > 0 else (0.0, 0.0)
    assert got == pytest.approx(want, rel=1e-12, abs=1e-12)


@pytest.mark.parametrize("wp, wt", [(120.0, 40.0), (150.0, 100.0), (200.0, 190.0),
                                    (60.0, 90.0), (100.0, 97.0)])
def test_exact_jacobian_with_a_moving_housing(wp, wt):
    sys_ = rig(housing=True).build()
    names = sys_.state_names
    y = sys_.y0.copy()
    y[names.index("omega_pump")], y[names.index("omega_turbine")] = wp, wt
    y[names.index("omega_housing")] = 3.0
    J, Jfd = _jac_fd(sys_, y, np.zeros(1))
    assert np.max(np.abs(J - Jfd) / np.maximum(np.abs(Jfd), 1.0)) < 1e-6


def test_launch_on_the_converter_and_lock_up_under_load():
    """examples/converter_launch.toml: at stall the turbine gets twice the pump torque;
    from 2.0 s the lock-up clutch slips at its sliding capacity (0.15·400 N·m) while the
    converter carries the rest (the slip phase), then locks after the full apply; locked,
    the converter carries nothing.  Energy balanced."""
    from _dl_paths import EXAMPLES

    from clutchsim.scenario import run_scenario
    r = run_scenario(EXAMPLES / "converter_launch.toml")
    res = r.result
    assert res.status == "completed", res.message
    t, tp, tt = res.t, res["T_pump_converter"], res["T_turbine_converter"]
    assert tt[0] / tp[0] == pytest.approx(2.0, rel=1e-9)
    slip_phase = (t > 2.3) & (t < 3.1)
    assert np.all(np.abs(res["w_slip_lockup"][slip_phase]) > 5.0)
    assert np.allclose(res["T_friction_lockup"][slip_phase], -60.0, rtol=1e-9)
    assert np.all(tp[slip_phase] > 30.0)
    t_lock = r.metrics["lockup_time_s"]
    assert 3.2 < t_lock < 3.5
    assert np.all(np.abs(tp[t > t_lock + 0.01]) < 1e-9)
    assert r.metrics["energy_balance_rel"] < 1e-6


@pytest.mark.parametrize("change, words", [
    ({"speed_ratio": [0.0, 0.5, 0.4, 0.75, 0.9]}, ["breakpoints must be strictly increasing"]),
    ({"K": [15.0, -15.0, 15.0, 16.0, 18.0]}, ["K[1] = -15", "at speed ratio 0.25", "> 0"]),
    ({"speed_ratio": [0.0, 0.25, 0.5, 0.75, 1.0]}, ["must lie in [0, 1)"]),
    ({"torque_ratio": [2.0, 1.8, 1.5, 1.4, 1.3]}, ["efficiency", "> 1"]),
])
def test_bad_converter_tables_name_component_key_value_and_rule(change, words):
    with pytest.raises(ValueError) as exc:
        TorqueConverter("tc", **{**MAPS, **change})
    msg = str(exc.value)
    assert msg.startswith("torque converter 'tc': ")
    for w in words:
        assert w in msg


def test_bad_converter_table_in_a_scenario_gives_file_and_line(tmp_path):
    from _dl_paths import EXAMPLES

    from clutchsim.scenario import ScenarioError, load_scenario
    text = (EXAMPLES / "converter_launch.toml").read_text(encoding="utf-8")
    old = "K = [15.0, 15.0, 15.0, 16.0, 18.0]"
    path = tmp_path / "tc.toml"
    path.write_text(text.replace(old, "K = [15.0, 15.0, -1.0, 16.0, 18.0]"), encoding="utf-8")
    with pytest.raises(ScenarioError) as exc:
        load_scenario(path).network()
    msg = str(exc.value)
    assert "tc.toml:" in msg and "torque converter 'converter': K[2] = -1" in msg
