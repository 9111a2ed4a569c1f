"""The exported FMU, run by an independent importer (FMPy): it passes FMPy's compliance
checks, completes with CVode and reproduces clutchsim's own run of the scenario inside the
2e-3 tube (max |FMU - clutchsim| / max(|clutchsim|, 1) on the FMU's output grid), with an
energy balance of its own run below 1e-6; ``clutchsim fmu`` refuses what it cannot export
with exit status 2 and writes nothing."""

import json
import shutil
import zipfile

import numpy as np
import pytest
from _dl_paths import EXAMPLES

from clutchsim.cli import main
from clutchsim.driveline.run import run_scenario
from clutchsim.fmu import export_fmu, input_table

fmpy = pytest.importorskip("fmpy", reason="FMPy (the dev extra) runs the exported FMUs")
from fmpy.validation import validate_fmu

pytestmark = pytest.mark.skipif(shutil.which("cc") is None and shutil.which("gcc") is None,
                                reason="no C compiler on this machine")

TUBE = 2e-3
ENERGY = ("W_in", "W_friction", "W_damping", "W_road", "E_grade", "W_sync")


def tube(f, res, name, mask=None):
    ref = np.interp(f["time"], res.t, res[name])
    err = np.abs(f[name] - ref) / max(float(np.max(np.abs(res[name]))), 1.0)
    return float(np.max(err if mask is None else err[mask]))


def tube_tv(f, res, name, dt):
    """The tube with a width in time as well (as CSV-compare's): how far each FMU sample
    lies outside clutchsim's values within ``dt`` of its time, over the signal's range.
    For a signal that rings or jumps, where a shift by a fraction of a step is a large
    difference in value."""
    t, y = res.t, res[name]
    worst = 0.0
    for ti, xi in zip(f["time"], f[name]):
        lo_i, hi_i = np.searchsorted(t, ti - dt), np.searchsorted(t, ti + dt, side="right")
        vals = np.r_[y[lo_i:hi_i], np.interp([ti - dt, ti + dt], t, y)]
        worst = max(worst, float(vals.min()) - xi, xi - float(vals.max()))
    return worst / max(float(np.max(np.abs(y))), 1.0)


def energy_balance(f):
    resid = f["W_in"] - sum(f[k] for k in ENERGY[1:]) - (f["E_kinetic"] - f["E_kinetic"][0]) \
        - (f["E_spring"] - f["E_spring"][0])
    return abs(resid[-1]) / max(abs(f["W_in"][-1]), float(np.max(f["E_kinetic"])))


def simulate(path, scenario, names, rtol, dt_out):
    md = fmpy.read_model_description(str(path))
    inputs = [v.name for v in md.modelVariables if v.causality == "input"]
    return fmpy.simulate_fmu(str(path), solver="CVode", relative_tolerance=rtol,
                             output_interval=dt_out, output=names,
                             input=input_table(scenario, dt=dt_out / 2, names=inputs))


@pytest.mark.slow
def test_default_launch_fmu_reproduces_clutchsim(tmp_path):
    scenario = EXAMPLES / "launch.toml"
    path = tmp_path / "launch.fmu"
    info = export_fmu(scenario, path, "mykhailevych2020")
    assert validate_fmu(str(path)) == []
    md = fmpy.read_model_description(str(path))
    assert md.fmiVersion == "2.0" and md.modelExchange is not None
    assert md.coSimulation is None
    with zipfile.ZipFile(path) as zf:
        names = set(zf.namelist())
    assert f"binaries/linux64/{info.model_identifier}.so" in names
    assert {"modelDescription.xml", "sources/plant.c", "sources/fmi2_me.c"} <= names
    # variables: clutchsim's names, units, start values
    by = {v.name: v for v in md.modelVariables}
    assert by["throttle"].causality == "input" and float(by["throttle"].start) == 0.1
    assert float(by["clutch_command"].start) == 0.0
    assert by["omega_engine"].unit == "rad/s" and float(by["omega_engine"].start) == 83.78
    assert by["T_clutch"].causality == "output" and by["T_clutch"].unit == "N·m"
    assert by["theta_pressure_plate"].unit == "°C"
    assert by["clutch.friction.T_stat"].variability == "tunable"
    assert by["engine.J"].variability == "constant"      # structural: in M⁻¹
    # model (6) has one set of equations: its only clutch indicator is the zero crossing
    # of the slip, where its reset policy (clamp) re-initialises phi; the other is the
    # engine's stall
    assert md.numberOfEventIndicators == 2
    assert [e for e in info.event_indicators if e.startswith("clutch")] == [
        "clutch: velocity_zero_crossing"]

    r = run_scenario(scenario, "mykhailevych2020")
    res = r.result
    assert res.status == "completed"
    out = ["omega_engine", "omega_disc", "omega_gearbox_input", "omega_wheels", "w_slip_clutch",
           "T_clutch", "theta_pressure_plate", "theta_flywheel", "E_kinetic", "E_spring",
           *ENERGY]
    f = simulate(path, scenario, out, 1e-7, 2e-3)
    assert f["time"][-1] == pytest.approx(4.0)
    for name in out:
        if name != "T_clutch":
            assert tube(f, res, name) <= TUBE, name
    # the clutch torque jumps where the reset re-initialises phi and rings after lock-up
    # (~400 Hz): the tube is given a width of one output interval in time as well
    assert tube_tv(f, res, "T_clutch", 2e-3) <= TUBE
    assert energy_balance(f) < 1e-6
    # lock-up reached in the FMU run as in clutchsim's
    assert abs(f["w_slip_clutch"][-1]) < 1e-2


def run_cli(capsys, *argv):
    code = main(list(argv))
    cap = capsys.readouterr()
    return code, cap.out, cap.err


def test_cli_writes_fmu_and_one_json_document(tmp_path, capsys):
    out = tmp_path / "sub" / "launch.fmu"
    code, stdout, err = run_cli(capsys, "fmu", str(EXAMPLES / "launch.toml"), "--model",
                                "mykhailevych2020", "--out", str(out), "--json")
    assert code == 0, err
    doc = json.loads(stdout)
    assert doc["path"] == str(out) and out.is_file()
    assert doc["fmi"] == "2.0" and doc["kind"] == "me" and doc["model"] == "mykhailevych2020"
    assert "omega_engine" in doc["states"] and "T_clutch" in doc["outputs"]
    assert doc["inputs"] == ["clutch_command", "throttle"]
    assert sorted(p.name for p in out.parent.iterdir()) == ["launch.fmu"]   # no leftovers


@pytest.mark.parametrize(("args", "message"), [
    (["--fmi", "3"], r"--fmi 3: this version writes FMI 2\.0 only"),
    (["--kind", "cs"], r"--kind cs: this version writes Model Exchange FMUs only"),
    (["--model", "no-such-model"], r"no-such-model"),
])
def test_cli_refuses_bad_options(tmp_path, capsys, args, message):
    out = tmp_path / "x.fmu"
    code, stdout, err = run_cli(capsys, "fmu", str(EXAMPLES / "launch.toml"), *args,
                                "--out", str(out))
    assert code == 2, err
    assert stdout == ""
    assert pytest.importorskip("re").search(message, err), err
    assert "Traceback" not in err
    assert list(tmp_path.iterdir()) == []


def test_cli_refuses_scenario_that_cannot_export(tmp_path, capsys):
    out = tmp_path / "owc.fmu"
    code, _, err = run_cli(capsys, "fmu", str(EXAMPLES / "one_way_clutch.toml"), "--out",
                           str(out))
    assert code == 2, err
    assert "cannot export" in err and "one-way clutch" in err
    assert list(tmp_path.iterdir()) == []


def test_cli_without_c_compiler_says_what_it_looked_for(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("CC", "no-such-cc")
    monkeypatch.setenv("PATH", str(tmp_path / "empty"))
    out = tmp_path / "launch.fmu"
    code, _, err = run_cli(capsys, "fmu", str(EXAMPLES / "launch.toml"), "--out", str(out))
    assert code == 2, err
    assert "no C compiler found" in err and "$CC=no-such-cc" in err and "gcc" in err
    assert "apt-get install gcc" in err
    assert not out.exists()
