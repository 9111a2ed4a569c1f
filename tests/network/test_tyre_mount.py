"""The vehicle around the driveline (issue 39): the tyre with longitudinal slip (brush-model
force, first-order relaxation length; docs/components.md, tyre) and the powertrain block on
torsional mounts.  Closed forms: the steady force on the brush curve, the first-order
relaxation of the slip over the distance sigma, the mount's damped step response, and the
shuffle frequency of a two-mass driveline whose tyre compliance is in series with the
driveshaft; every run's energy balance closes."""

import math
import re

import numpy as np
import pytest
from _dl_paths import EXAMPLES

from clutchsim.analysis.launch_metrics import energy_balance
from clutchsim.analysis.linear import linearise, modes
from clutchsim.analysis.linear import operating_point as op
from clutchsim.cli import main
from clutchsim.core import SolverOptions, simulate
from clutchsim.network import Network
from clutchsim.network.components import (
    ConstantSpeed,
    Inertia,
    SpringDamper,
    TorqueSource,
    TorsionalMount,
    Tyre,
    Vehicle,
)
from clutchsim.scenario import ScenarioError, load_scenario

OPTS = SolverOptions(rtol=1e-10, atol=1e-12, dt_out=1e-3)
R, FZ, MU, C, SIGMA, VEPS = 0.3, 7650.0, 1.0, 1.2e5, 0.2, 0.1


def brush(kappa):
    """The brush model's force (Pacejka 2012 ch. 3, parabolic pressure), written as
    ``μF_z·(1 − (1 − z)³)·sign κ`` with ``z = min(C|κ|/(3μF_z), 1)``."""
    z = min(C * abs(kappa) / (3.0 * MU * FZ), 1.0)
    return math.copysign(MU * FZ * (1.0 - (1.0 - z) ** 3), kappa)


def held(v, kappa, sigma=SIGMA):
    """Wheel and body held at constant speeds (body ``V = v``) so that the steady slip
    ``(ω_w − ω_b)·r/V_ε`` is ``kappa``."""
    ve = math.hypot(v, VEPS)
    tyre = Tyre("tyre", radius=R, J_wheel=1.0, Fz=FZ, mu=MU, C_kappa=C, sigma=sigma,
                v_eps=VEPS)
    return Network([ConstantSpeed("wheel", w_fixed=(v + kappa * ve) / R), tyre,
                    ConstantSpeed("body", w_fixed=v / R)],
                   [["wheel.flange", "tyre.wheel"], ["tyre.body", "body.flange"]],
                   name="tyre_held")


@pytest.mark.parametrize("kappa", [0.01, 0.05, 0.15, -0.1, 0.4])
def test_steady_force_lies_on_the_brush_curve(kappa):
    """At constant wheel and body speeds the force settles on the slip curve: linear
    ``C_κ·κ`` for small slip, saturated at ``μ·F_z`` beyond ``3μF_z/C_κ`` (0.19 here)."""
    res = simulate(held(10.0, kappa).build(), (0.0, 0.5), {}, options=OPTS)
    assert res.status == "completed", res.message
    assert res["tyre.kappa"][-1] == pytest.approx(kappa, rel=1e-8)
    assert res["F_x_tyre"][-1] == pytest.approx(brush(kappa), rel=1e-8)
    assert res["kappa_practical_tyre"][-1] == pytest.approx(kappa, rel=1e-12)
    if abs(kappa) < 0.02:
        assert res["F_x_tyre"][-1] == pytest.approx(C * kappa, rel=0.1)
    assert energy_balance(res)["energy_balance_rel"] < 1e-8


@pytest.mark.parametrize("v", [2.0, 20.0])
def test_slip_relaxes_in_first_order_over_the_relaxation_length(v):
    """From an undeflected tyre, ``κ'(t) = κ_ss·(1 − exp(−V_ε·t/σ))``: the slip reaches
    63 % of its final value after the distance σ."""
    kappa = 0.05
    res = simulate(held(v, kappa).build(), (0.0, 5 * SIGMA / v), {}, options=OPTS)
    ve = math.hypot(v, VEPS)
    expected = kappa * (1.0 - np.exp(-ve * res.t / SIGMA))
    assert np.max(np.abs(res["tyre.kappa"] - expected)) <= 1e-9
    t63 = np.interp(kappa * (1 - math.exp(-1)), res["tyre.kappa"], res.t)
    assert v * t63 == pytest.approx(SIGMA, rel=2e-3)


def test_tyre_holds_a_torque_at_standstill_as_a_spring():
    """Body held at rest, a torque on the wheel: the carcass deflects to ``F = τ/r`` and the
    wheel creeps at ``v_eps·κ'/r`` (the regularisation).  Linearised, the wheel on the
    carcass is ``λ² + (v_eps/σ)·λ + C_κ·r²/(σ·J_w) = 0``: it rings at
    ``sqrt(C_κ·r²/(σ·J_w))`` and settles at the rate ``v_eps/(2σ)``."""
    tau, jw, veps = 500.0, 1.0, 1.0
    net = Network([TorqueSource("drive", input="tau"), Tyre(
        "tyre", radius=R, J_wheel=jw, Fz=FZ, mu=MU, C_kappa=C, sigma=SIGMA, v_eps=veps)],
        [["drive.flange", "tyre.wheel"], ["tyre.body", "ground"]], name="tyre_standstill")
    system = net.build()
    (m,) = [m for m in modes(linearise(system, 0.0, system.y0, np.zeros(1)))]
    wn = math.sqrt(C * R * R / (SIGMA * jw))        # modes() reports |λ| as the frequency
    assert m.frequency_hz * 2 * math.pi == pytest.approx(wn, rel=1e-9)
    assert m.growth_rate_1_s == pytest.approx(-veps / (2 * SIGMA), rel=1e-9)
    res = simulate(system, (0.0, 12.0), {"tau": tau},
                   options=SolverOptions(rtol=1e-9, atol=1e-11, dt_out=1e-3))
    assert res.status == "completed", res.message
    assert res["F_x_tyre"][-1] == pytest.approx(tau / R, rel=1e-6)
    kss = res["tyre.kappa"][-1]
    assert brush(kss) == pytest.approx(tau / R, rel=1e-6)
    assert res["omega_tyre"][-1] * R == pytest.approx(veps * kss, rel=1e-5)
    assert energy_balance(res)["energy_balance_rel"] < 1e-8


def mount_rig(J=8.0, c=3e4, d=100.0):
    return Network([TorqueSource("engine", input="tau"), Inertia("crank", J=0.2),
                    TorsionalMount("mounts", J=J, c=c, d=d)],
                   [["engine.flange", "crank.a"], ["engine.support", "mounts.block"]],
                   name="mount_rig")


def test_mount_step_response_in_closed_form():
    """A torque step ``τ`` between the crank and the block: the block rolls to ``−τ/c``
    with the damped oscillator's response (``ω_n = sqrt(c/J)``, ``ζ = d/(2·sqrt(c·J))``)
    and the mount passes ``τ`` into the body; the crank accelerates at ``τ/J_crank``."""
    J, c, d, tau = 8.0, 3e4, 100.0, 200.0
    system = mount_rig(J, c, d).build()
    res = simulate(system, (0.0, 3.0), {"tau": tau}, options=OPTS)
    wn, z = math.sqrt(c / J), d / (2 * math.sqrt(c * J))
    wd = wn * math.sqrt(1 - z * z)
    t = res.t
    phi = -tau / c * (1 - np.exp(-z * wn * t) * (np.cos(wd * t) + z / math.sqrt(1 - z * z)
                                                 * np.sin(wd * t)))
    assert np.max(np.abs(res["phi_mounts"] - phi)) <= 1e-6 * tau / c
    assert res["T_mounts"][-1] == pytest.approx(-tau, rel=1e-6)
    assert res["omega_crank"][-1] == pytest.approx(tau / 0.2 * 3.0, rel=1e-9)
    assert energy_balance(res)["energy_balance_rel"] < 1e-8
    lin = linearise(system, 0.0, system.y0, np.array([tau]))
    (m,) = [m for m in modes(lin) if m.frequency_hz > 0]
    assert m.frequency_hz == pytest.approx(wn / (2 * math.pi), rel=1e-9)
    assert m.damping_ratio == pytest.approx(z, rel=1e-9)


def two_mass(sigma, j1=38.0, ks=11000.0, m=1300.0, jw=0.05):
    """Engine side ``j1`` (reflected to the wheels) -> driveshaft ``ks`` -> light wheel ->
    tyre -> vehicle ``m`` (no road load)."""
    return Network([Inertia("engine", J=j1), SpringDamper("shaft", c=ks),
                    Tyre("tyre", radius=R, J_wheel=jw, Fz=FZ, C_kappa=C, sigma=sigma,
                         v_eps=VEPS),
                    Vehicle("car", mass=m, tyre_radius=R)],
                   [["engine.b", "shaft.a"], ["shaft.b", "tyre.wheel"],
                    ["tyre.body", "car.flange"]], name="tyre_two_mass")


def shuffle_closed_form(sigma, j1=38.0, ks=11000.0, m=1300.0):
    """Two masses on the driveshaft and the tyre carcass in series
    (``k_t = C_κ·r²/σ`` at the wheel)."""
    kt = C * R * R / sigma
    k = 1.0 / (1.0 / ks + 1.0 / kt)
    return math.sqrt(k * (1.0 / j1 + 1.0 / (m * R * R))) / (2 * math.pi)


def test_shuffle_frequency_falls_with_tyre_compliance_as_the_two_mass_closed_form():
    """Linearised at rest (the carcass a spring, its series damper ``C_κ/v_eps`` stiff),
    the shuffle mode is the two-mass mode with the tyre's compliance ``σ/(C_κ·r²)`` in
    series with the driveshaft's; it falls as σ grows."""
    found = []
    for sigma in (0.02, 0.1, 0.2, 0.4):
        system = two_mass(sigma).build()
        lin = linearise(system, 0.0, system.y0, np.zeros(0))
        f = min(m.frequency_hz for m in modes(lin) if m.frequency_hz > 0)
        assert f == pytest.approx(shuffle_closed_form(sigma), rel=2e-3), sigma
        found.append(f)
    assert found == sorted(found, reverse=True)
    assert found[-1] < 0.85 * shuffle_closed_form(1e-9)


def _with_sigma(tmp_path, sigma):
    text = (EXAMPLES / "launch_tyre.toml").read_text(encoding="utf-8")
    assert "sigma = 0.2" in text
    p = tmp_path / f"launch_tyre_{sigma}.toml"
    p.write_text(text.replace("sigma = 0.2", f"sigma = {sigma}"), encoding="utf-8")
    return load_scenario(p)


def test_launch_shuffle_mode_after_lockup_follows_the_tyre_compliance(tmp_path):
    """examples/launch_tyre.toml linearised after lock-up (3.5 s, V = 5.5 m/s): the shuffle
    mode (the lowest oscillating mode) lies within 3 % of the two-mass closed form with the
    disc damper, the driveshaft and the tyres in series, for three relaxation lengths
    (measured: 3.052/2.815/2.567 Hz against 3.029/2.830/2.617 Hz; the closed form leaves
    out the tyre's series damper C_κ/V, whose corner V/σ nears the shuffle frequency as σ
    grows, and the block on its mounts), it falls as σ grows, and the linearisation lists
    the mount's roll mode (sqrt(c/J)) and the tyre's own mode."""
    ratio2 = (3.6 * 4.1) ** 2
    j1 = (0.15 + 0.015 + 0.01) * ratio2 + 0.05
    ks = 1.0 / (1.0 / 12000.0 + 1.0 / (600.0 * ratio2))
    freqs = []
    for sigma in (0.05, 0.2, 0.4):
        pt = op(_with_sigma(tmp_path, sigma), None, 3.5)
        assert pt.y[pt.system.state_names.index("clutch.locked")] == 1.0
        ms = [m for m in modes(linearise(pt.system, pt.t_s, pt.y, pt.u)) if m.frequency_hz > 0]
        shuffle = ms[0]                     # the lowest: engine against the vehicle
        assert {"omega_car", "omega_engine"} & set(shuffle.dominant_states), shuffle
        expected = shuffle_closed_form(sigma, j1=j1, ks=ks, m=1300.0 + 1.6 / R ** 2)
        assert shuffle.frequency_hz == pytest.approx(expected, rel=0.03), sigma
        freqs.append(shuffle.frequency_hz)
        names = {s for m in ms for s in m.dominant_states}
        assert {"phi_mounts", "tyres.kappa"} <= names
        (roll,) = [m for m in ms if "phi_mounts" in m.dominant_states]
        assert roll.frequency_hz == pytest.approx(math.sqrt(3e4 / 8.0) / (2 * math.pi),
                                                  rel=0.05)
    assert freqs == sorted(freqs, reverse=True)


def test_launch_tyre_example_runs_and_balances():
    from clutchsim.scenario import run_scenario
    res = run_scenario(EXAMPLES / "launch_tyre.toml").result
    assert res.status == "completed", res.message
    assert energy_balance(res)["energy_balance_rel"] < 1e-8
    assert res["v_vehicle"][-1] > 5.0
    # the launch slips the tyres by a few percent, below the saturation 3μF_z/C_κ
    assert 0.0 < np.max(res["tyres.kappa"]) < 3 * MU * FZ / C


@pytest.mark.parametrize("old, new, words", [
    ("sigma = 0.2", "sigma = -0.1", ["bad.toml:126:", "component[11].sigma", "= -0.1 m",
                                     "must be > 0"]),
    ("radius = 0.3", "radius = 0.31", ["radius = 0.31 m", "tyre_radius = 0.3 m",
                                       "bad.toml:"]),
])
def test_bad_tyre_values_are_refused_with_key_file_and_line(tmp_path, capsys, old, new, words):
    text = (EXAMPLES / "launch_tyre.toml").read_text(encoding="utf-8")
    assert old in text
    path = tmp_path / "bad.toml"
    path.write_text(text.replace(old, new, 1), encoding="utf-8")
    with pytest.raises(ScenarioError) as err:
        load_scenario(path).network(None).build()
    msg = str(err.value)
    for w in words:
        assert w in msg, (w, msg)
    code = main(["run", str(path), "--out", str(tmp_path / "o")])
    cli = capsys.readouterr().err
    assert code == 2, cli
    assert "Traceback" not in cli
    for w in words:
        assert w in cli, (w, cli)
    assert not (tmp_path / "o").exists()


def test_bad_component_values_name_the_parameter_and_the_rule():
    with pytest.raises(ValueError, match=re.escape(
            "tyre 't': sigma = -0.2 m must be in (0, 10] (relaxation length)")):
        Tyre("t", radius=R, J_wheel=1.0, Fz=FZ, C_kappa=C, sigma=-0.2)
    with pytest.raises(ValueError, match=re.escape(
            "torsional mount 'm': c = 0 N·m/rad must be in (0, 1e+09]")):
        TorsionalMount("m", J=1.0, c=0.0)
