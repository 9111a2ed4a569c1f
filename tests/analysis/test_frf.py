"""Frequency response from an input channel: closed form, time simulation, the CLI."""

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from clutchsim.analysis import frequency_grid, frf_analysis
from clutchsim.analysis.frf import ratio_unit
from clutchsim.driveline.run import run_scenario

REPO = Path(__file__).resolve().parents[2]

# a load torque tau on inertia a, a locked clutch to b (one cluster J1 = Ja + Jb), a shaft
# (k, c) to a damped wheel c: every mode decays at >= 6.4 1/s, the plant is linear
JA, JB, JC, DA, DC, K, C = 0.15, 0.05, 0.5, 0.5, 4.0, 2000.0, 2.0
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
friction = {{ model = "coulomb-robust", overrides = {{ F_c = 400.0, F_s = 500.0 }} }}

[[coupling]]
name = "shaft"
type = "spring_damper"
c = {K}
d = {C}
"""


@pytest.fixture(scope="module")
def scenario_file(tmp_path_factory):
    p = tmp_path_factory.mktemp("frf") / "two.toml"
    p.write_text(SCENARIO, encoding="utf-8")
    return p


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


@pytest.mark.parametrize("freq", [5.0, 18.6, 50.0])
def test_response_matches_a_time_simulation_driven_by_a_sine(scenario_file, freq):
    """The scenario's own input driven by a sine (``tau = sine(1, f)``): the steady-state
    amplitude and phase of the wheel speed and the clutch torque, fitted over the last
    second, against the FRF.  The plant is linear at this point (a locked clutch, a linear
    shaft and dampers), so the only differences are the solver's (rtol 1e-9) and the
    transient left after 2 s (e^-12.8): 1e-3 relative / 1e-3 rad leave a margin of ~100
    over what is measured, and would catch a wrong B, C or D row or a lost merge."""
    over = [f'inputs.tau="sine(1, {freq!r})"']
    fr = {out: frf_analysis(scenario_file, input="tau", output=out, freqs_hz=[freq],
                            overrides=over) for out in ("omega_c", "T_clutch")}
    run = run_scenario(scenario_file, overrides=over)
    res = run.result
    assert res.status == "completed"
    sel = res.t >= 2.0
    t = res.t[sel]
    basis = np.column_stack([np.sin(2 * np.pi * freq * t), np.cos(2 * np.pi * freq * t),
                             np.ones_like(t)])
    for out, f in fr.items():
        (s_, c_, _), *_ = np.linalg.lstsq(basis, res[out][sel], rcond=None)
        assert math.hypot(s_, c_) == pytest.approx(f.magnitude[0], rel=1e-3), out
        phase = math.atan2(c_, s_)           # x = |X|·sin(ωt + φ): φ is the phase of H
        assert abs(np.angle(np.exp(1j * (phase - math.radians(f.phase_deg[0]))))) < 1e-3, out


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
                        "warnings"}
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
