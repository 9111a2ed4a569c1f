"""Frequency response from an input channel: closed form, time simulation, the CLI."""

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from clutchsim.analysis import frequency_grid
from clutchsim.analysis.frf import ratio_unit
from clutchsim.scenario import run_scenario
from clutchsim.studies.frf import frf_analysis

REPO = Path(__file__).resolve().parents[2]

# a load torque tau on inertia a, a locked clutch to b (one cluster J1 = Ja + Jb), a shaft
# (k, c) to a damped wheel c: every mode decays at >= 6.4 1/s, the plant is linear
JA, JB, JC, DA, DC, K, C = 0.15, 0.05, 0.5, 0.5, 4.0, 2000.0, 2.0
LOCKED = 'friction = { model = "coulomb-robust", overrides = { F_c = 400.0, F_s = 500.0 } }'
# model (6) instead: a smooth clutch, held by its pre-sliding contact (k_c = T_cap/φ0, a
# 404 Hz mode), damped by the extension c_ps (ζ = 0.11); not merged: through its state
SMOOTH = ('friction = { model = "mykhailevych2020", parameter_set = "mykhailevych2020_clutch", '
          'overrides = { c_ps = 20.0 } }')
SCENARIO = f"""\
[scenario]
name = "two-inertia"
description = "A load torque on a locked clutch cluster, a shaft, a damped wheel."
t_end = 3.0
clutch = "clutch"

[solver]
method = "rodas4"
rtol = 1e-9
atol = 1e-11
dt_out = 0.0005

[inputs]
tau = "sine(1, 18)"     # load torque on a [N·m]
com = "const(1)"

[[inertia]]
name = "a"
J = {JA}
load = "tau"
bearing_damping = {DA}

[[inertia]]
name = "b"
J = {JB}

[[inertia]]
name = "c"
J = {JC}
bearing_damping = {DC}

[[coupling]]
name = "clutch"
type = "clutch"
command = "com"
FRICTION

[[coupling]]
name = "shaft"
type = "spring_damper"
c = {K}
d = {C}
"""


def _write(dir_, name, friction):
    p = dir_ / name
    p.write_text(SCENARIO.replace("FRICTION", friction), encoding="utf-8")
    return p


@pytest.fixture(scope="module")
def scenario_file(tmp_path_factory):
    return _write(tmp_path_factory.mktemp("frf"), "locked.toml", LOCKED)


@pytest.fixture(scope="module")
def smooth_file(tmp_path_factory):
    return _write(tmp_path_factory.mktemp("frf"), "smooth.toml", SMOOTH)


def _closed_form(f):
    """Speeds of the cluster and the wheel and the torque the clutch passes to b per unit
    load torque: ``V = (M·s + Cm + K/s)⁻¹·F``."""
    s = 2j * math.pi * np.asarray(f, dtype=float)
    j1 = JA + JB
    out = []
    for sk in s:
        Z = np.array([[j1 * sk + DA + C + K / sk, -(C + K / sk)],
                      [-(C + K / sk), JC * sk + DC + C + K / sk]])
        v = np.linalg.solve(Z, np.array([1.0, 0.0]))
        t_b = JB * sk * v[0] + (C + K / sk) * (v[0] - v[1])    # J_b·ω_b' + shaft torque
        out.append((v[0], v[1], t_b))
    return np.array(out).T


def test_load_torque_response_equals_the_closed_form(scenario_file):
    f = frequency_grid(1.0, 200.0, 60)
    w_a, w_c, t_b = _closed_form(f)
    fa = frf_analysis(scenario_file, input="tau", output="omega_a", freqs_hz=f)
    fc = frf_analysis(scenario_file, input="tau", output="omega_c", freqs_hz=f)
    ft = frf_analysis(scenario_file, input="tau", output="T_clutch", freqs_hz=f)
    np.testing.assert_allclose(fa.response, w_a, rtol=1e-6)
    np.testing.assert_allclose(fc.response, w_c, rtol=1e-6)
    # T_clutch is the torque on the engine side (a): minus what it passes to b
    np.testing.assert_allclose(ft.response, -t_b, rtol=1e-6)
    assert fc.unit == "rad/s/(N·m)" and ft.unit == "-" and fc.input_unit == "N·m"
    assert fc.warnings == () and fc.t_s == 0.0 and fc.model == "coulomb-robust"
    # the peak is refined off the grid: |H| there is the maximum of the closed form
    (peak,) = fc.peaks
    fine = frequency_grid(peak.frequency_hz * 0.99, peak.frequency_hz * 1.01, 2001)
    best = np.max(np.abs(_closed_form(fine)[1]))
    assert peak.magnitude == pytest.approx(best, rel=1e-7)
    assert 15.0 < peak.frequency_hz < 22.0
    doc = fc.as_dict()
    assert doc["kind"] == "frf" and doc["input"] == "tau" and doc["output"] == "omega_c"
    assert len(doc["frequency_hz"]) == len(doc["magnitude"]) == len(doc["phase_deg"]) == 60
    assert doc["peaks"] == [{"frequency_hz": peak.frequency_hz, "magnitude": peak.magnitude}]
    assert not fc.response.flags.writeable


@pytest.mark.parametrize("clutch", ["locked", "smooth"])
@pytest.mark.parametrize("freq", [5.0, 18.6, 50.0])
def test_response_matches_a_time_simulation_driven_by_a_sine(scenario_file, smooth_file,
                                                             clutch, freq):
    """The scenario's own input driven by a sine (``tau = sine(1, f)``, 5 Hz, at the first
    mode, 50 Hz): the steady-state amplitude and phase of three outputs, fitted over the
    last second, against the FRF.  The clutch is locked (merged) or model (6) held by its
    contact (a state, its friction slope).  The plant is linear about this point up to the
    contact's tanh (the twist stays below 2 % of φ0), so what differs is the solver's error
    (rtol 1e-9) and the transient left after 2 s (e^-12.8): measured <= 1e-6 in amplitude
    and phase; 1e-4 relative / 1e-4 rad catch a wrong B, C or D row or a lost merge."""
    path = scenario_file if clutch == "locked" else smooth_file
    over = [f'inputs.tau="sine(1, {freq!r})"']
    outs = ("omega_a", "omega_c", "T_clutch")
    fr = {out: frf_analysis(path, input="tau", output=out, freqs_hz=[freq], overrides=over)
          for out in outs}
    assert fr["T_clutch"].model == ("coulomb-robust" if clutch == "locked" else
                                    "mykhailevych2020")
    res = run_scenario(path, overrides=over).result
    assert res.status == "completed"
    sel = res.t >= 2.0
    t = res.t[sel]
    basis = np.column_stack([np.sin(2 * np.pi * freq * t), np.cos(2 * np.pi * freq * t),
                             np.ones_like(t)])
    for out, f in fr.items():
        (s_, c_, _), *_ = np.linalg.lstsq(basis, res[out][sel], rcond=None)
        assert math.hypot(s_, c_) == pytest.approx(f.magnitude[0], rel=1e-4), out
        phase = math.atan2(c_, s_)           # x = |X|·sin(ωt + φ): φ is the phase of H
        assert abs(np.angle(np.exp(1j * (phase - math.radians(f.phase_deg[0]))))) < 1e-4, out


FINE = ["solver.rtol=1e-9", "solver.atol=1e-11", "solver.dt_out=0.0005"]


@pytest.fixture(scope="module")
def launch_base():
    """The default launch (model (6)), locked from 1.12 s on, run to 4 s at tight tolerances;
    and its shuffle mode at 3 s (for the transient the sine leaves)."""
    from clutchsim.studies.judder import judder_analysis
    shuffle = next(m for m in judder_analysis(None, None, 3.0).modes
                   if 1.0 < m.frequency_hz < 10.0)
    return run_scenario(None, overrides=FINE).result, shuffle.eigenvalue


@pytest.mark.parametrize("freq", [20.0, 60.0])
def test_launch_after_lockup_matches_a_time_simulation(launch_base, freq):
    """The default launch after lock-up with the throttle 0.35 + 0.002·sin(2π·f·(t − 3))
    from 3 s: the difference from the unforced run, fitted over 3.3-4 s (a sine, the shuffle
    transient e^(λt) with λ from the modes, a quadratic drift), against the FRF linearised
    at the window's middle (3.65 s).  60 Hz is at the damper mode (63.7 Hz, ζ = 0.16).
    The launch is no equilibrium: the engine accelerates up its full-load curve, so the
    throttle's gain rises ~2 % over the window (the FRF at 3 s is 2.2 % low; at the middle:
    measured <= 2.2e-4 in amplitude, 2.3e-3 rad in phase).  1 % / 0.01 rad leave that
    margin for the drift and catch a wrong row or sign."""
    base, lam = launch_base
    sig = f'"0.1 + ramp(0.3, 0.5, 0.25) + sine(0.002, {freq!r}, start=3.0)"'
    res = run_scenario(None, overrides=[*FINE, f"inputs.throttle={sig}"]).result
    assert res.status == "completed" and base.status == "completed"
    sel = res.t >= 3.3
    t = res.t[sel]
    tt = t - 3.0
    basis = np.column_stack([np.sin(2 * np.pi * freq * tt), np.cos(2 * np.pi * freq * tt),
                             np.ones_like(tt), tt, tt**2,
                             np.exp(lam.real * tt) * np.sin(lam.imag * tt),
                             np.exp(lam.real * tt) * np.cos(lam.imag * tt)])
    for out in ("a_vehicle", "T_clutch", "omega_engine"):
        fr = frf_analysis(None, None, 3.65, input="throttle", output=out, freqs_hz=[freq])
        assert fr.unit == {"a_vehicle": "m/s²", "T_clutch": "N·m", "omega_engine": "rad/s"}[out]
        x = res[out][sel] - np.interp(t, base.t, base[out])
        (s_, c_, *_), *_ = np.linalg.lstsq(basis, x, rcond=None)
        assert math.hypot(s_, c_) == pytest.approx(0.002 * fr.magnitude[0], rel=0.01), out
        phase = math.atan2(c_, s_)
        assert abs(np.angle(np.exp(1j * (phase - math.radians(fr.phase_deg[0]))))) < 0.01, out


def test_bad_names_and_grids(scenario_file):
    with pytest.raises(ValueError, match=r"input 'tua'.*did you mean 'tau'.*inputs: "):
        frf_analysis(scenario_file, input="tua", output="omega_c")
    with pytest.raises(ValueError, match=r"output 'omega_x'.*outputs: .*omega_c"):
        frf_analysis(scenario_file, input="tau", output="omega_x")
    with pytest.raises(ValueError, match="f_max = 1 Hz must be finite and above f_min = 2"):
        frequency_grid(2.0, 1.0, 10)
    with pytest.raises(ValueError, match="points = 1 must be an integer from 2"):
        frequency_grid(1.0, 2.0, 1)
    with pytest.raises(ValueError, match="f_min = 0 Hz must be a finite frequency > 0"):
        frequency_grid(0.0, 2.0, 10)
    with pytest.raises(ValueError, match="not finite at 0 Hz"):     # the rigid-body mode
        frf_analysis(scenario_file, input="tau", output="omega_c", freqs_hz=[0.0, 1.0],
                     overrides=["inertia[0].bearing_damping=0", "inertia[2].bearing_damping=0"])
    # a lock flag is a discrete state, not a linearised one (the launch's gearbox ratio was
    # a held value on the chain plant; the network plant has no such state)
    coupled = Path(__file__).parents[2] / "examples" / "coupled_clutches.toml"
    with pytest.raises(ValueError, match="'clutch2.locked' is not an output or linearised "
                                         "state"):
        frf_analysis(coupled, model="coulomb-robust", at=0.2, input="tau",
                     output="clutch2.locked")
    assert ratio_unit("m/s²", "N·m") == "m/s²/(N·m)"
    assert ratio_unit("N·m", "N·m") == "-" and ratio_unit("N·m", "-") == "N·m"


def test_a_command_at_zero_is_a_kink(scenario_file):
    """An open clutch (command 0): the capacity is 0 below and rises above: the response
    to the command warns that the plant is not differentiable there."""
    fr = frf_analysis(scenario_file, input="com", output="omega_c", freqs_hz=[5.0],
                      overrides=['inputs.com="const(0)"'])
    assert any("not differentiable in 'com'" in w for w in fr.warnings)


def _cli(*args):
    return subprocess.run([sys.executable, "-m", "clutchsim", "judder", *args], cwd=REPO,
                          check=False, capture_output=True, text=True, timeout=600)


def test_cli_frf_json_csv_and_figure(scenario_file, tmp_path):
    out = tmp_path / "frf"
    p = _cli(str(scenario_file), "--frf", "tau:omega_c", "--f-min", "1", "--f-max", "100",
             "--points", "50", "--json", "--out", str(out))
    assert p.returncode == 0, p.stderr
    doc = json.loads(p.stdout)
    assert set(doc) == {"kind", "model", "t_s", "input", "output", "unit", "input_unit",
                        "output_unit", "frequency_hz", "magnitude", "phase_deg", "peaks",
                        "warnings", "parameters"}
    assert all(r["unit"] is not None for c in doc["parameters"].values() for r in c.values())
    assert doc["kind"] == "frf" and doc["unit"] == "rad/s/(N·m)"
    assert doc["frequency_hz"][0] == 1.0 and doc["frequency_hz"][-1] == pytest.approx(100.0)
    assert len(doc["magnitude"]) == 50 and len(doc["peaks"]) == 1
    assert json.loads((out / "frf.json").read_text()) == doc
    rows = (out / "frf.csv").read_text().splitlines()
    assert rows[0] == "frequency_hz,magnitude [rad/s/(N·m)],phase_deg" and len(rows) == 51
    assert (out / "frf.png").stat().st_size > 1000


@pytest.mark.parametrize(("args", "text"), [
    (("--frf", "tua:omega_c"), "did you mean 'tau'"),
    (("--frf", "tau:omega_x"), "outputs: "),
    (("--frf", "tau"), "expected INPUT:OUTPUT"),
    (("--frf", "tau:omega_c", "--f-min", "10", "--f-max", "5"), "must be finite and above"),
    (("--frf", "tau:omega_c", "--points", "1"), "points = 1 must be an integer from 2"),
    (("--f-min", "3"), "--f-min needs --frf"),
    (("--frf", "tau:omega_c", "--element", "clutch"), "--element does not apply to --frf"),
])
def test_cli_frf_bad_input(scenario_file, args, text):
    p = _cli(str(scenario_file), *args)
    assert p.returncode == 2, p.stderr
    assert text in p.stderr and "Traceback" not in p.stderr
    assert p.stdout == ""
