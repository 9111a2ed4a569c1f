"""The rig and bench subcommands run through ``python -m clutchsim`` in a subprocess."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest


def cli(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "clutchsim", *args], capture_output=True,
                          text=True, cwd=cwd, timeout=600, check=False)


def test_rig_takes_the_solver_options_of_a_scenario():
    """--option KEY=VALUE: the keys of a scenario's [solver] table (one reader for both)."""
    steps = {}
    for rtol in ("1e-4", "1e-8"):
        p = cli("rig", "--model", "lugre", "--force", "0", "--spring", "2", "--pull-speed", "0.1",
                "--t-end", "20", "--option", f"rtol={rtol}", "--option", "controller=pid",
                "--json")
        assert p.returncode == 0, p.stderr
        steps[rtol] = json.loads(p.stdout)["stats"]["steps"]
    assert steps["1e-8"] > 1.4 * steps["1e-4"]   # measured 581 against 365


def test_rig_json_and_csv(tmp_path):
    out = tmp_path / "rig.csv"
    p = cli("rig", "--model", "lugre", "--force", "0.5 + sine(0.4, 1)", "--t-end", "2",
            "--out", str(out), "--json")
    assert p.returncode == 0, p.stderr
    doc = json.loads(p.stdout)
    assert doc["status"] == "completed"
    assert doc["outcome"] == "completed" and doc["warnings"] == [] and doc["event"] == ""
    assert "x [m]" in doc["final"] and "steps" in doc["stats"]
    header = out.read_text().splitlines()[0].split(",")
    assert header[:4] == ["time [s]", "x [m]", "v [m/s]", "F [N]"]
    assert "z [m]" in header
    # the CSV holds every signal of the JSON (and of Result.to_csv), F_ext and F_spring too
    assert set(header) == {"time [s]", *doc["final"]}
    assert {"F_ext [N]", "F_spring [N]", "force [N]"} <= set(header)


def test_rig_rotational_columns(tmp_path):
    out = tmp_path / "rot.csv"
    # model (6) has a state named phi: the rig's own angle must not clash with it
    p = cli("rig", "--model", "mykhailevych2020", "--params", "mykhailevych2020_clutch",
            "--domain", "rotational", "--mass", "0.2", "--force", "ramp(0, 1, 1)",
            "--t-end", "1", "--out", str(out))
    assert p.returncode == 0, p.stderr
    header = out.read_text().splitlines()[0].split(",")
    assert header[:4] == ["time [s]", "theta [rad]", "omega [rad/s]", "T [N·m]"]
    assert "phi [rad]" in header
    # the model's own (translational) set on the rotational rig: refused, exit 2
    p = cli("rig", "--model", "mykhailevych2020", "--domain", "rotational", "--force", "0",
            "--t-end", "1")
    assert p.returncode == 2 and "Traceback" not in p.stderr
    assert "mykhailevych2020_translational" in p.stderr and "--params" in p.stderr


@pytest.mark.parametrize("content, needle", [
    ("time\n0\n1\n", "bad.csv:2"),
    ("time,value\n0,0\n2,1\n1,1\n", "non-decreasing"),
    ("time,value\n0,0\n1,nan\n", "non-finite"),
])
def test_rig_bad_csv_exit_2(tmp_path, content, needle):
    bad = tmp_path / "bad.csv"
    bad.write_text(content)
    out = tmp_path / "never.csv"
    p = cli("rig", "--model", "lugre", "--force", str(bad), "--t-end", "1", "--out", str(out))
    assert p.returncode == 2
    assert needle in p.stderr and "bad.csv" in p.stderr
    assert len(p.stderr.strip().splitlines()) == 1
    assert not out.exists()


@pytest.mark.parametrize("args, needle", [
    (["--model", "lugr", "--force", "1"], "lugre"),
    (["--model", "lugre", "--force", "__import__('os')"], "__import__"),
    (["--model", "lugre", "--set", "sigma0=-1", "--force", "1"], "sigma0"),
    (["--model", "lugre", "--force", "1", "--option", "rtl=1e-6"], "did you mean 'rtol'"),
    (["--model", "lugre", "--force", "1", "--option", "controller=PI"], "valid kinds"),
    (["--model", "lugre", "--force", "1", "--option", "rtol"], "expected KEY=VALUE"),
])
def test_rig_bad_input_exit_2(args, needle):
    p = cli("rig", *args, "--t-end", "1")
    assert p.returncode == 2
    assert needle in p.stderr
    assert p.stdout == ""


def test_bench_json_and_outputs(tmp_path):
    out = tmp_path / "ss"
    p = cli("bench", "stick-slip", "--model", "lugre", "--out", str(out), "--json")
    assert p.returncode == 0, p.stderr
    doc = json.loads(p.stdout)
    assert doc["benchmark"] == "stick-slip"
    assert doc["results"]["lugre"]["period_s"] == pytest.approx(6.3627, rel=1e-3)
    names = sorted(f.name for f in out.iterdir())
    assert names == [".clutchsim-output.json", "bench.json", "command.txt", "report.html",
                     "stick-slip.png", "stick-slip_traces.csv"]
    manifest = json.loads((out / ".clutchsim-output.json").read_text())
    assert manifest["kind"] == "bench" and manifest["files"] == names[1:]
    assert not (tmp_path / "ss.partial").exists()


def test_bench_drift_json_shape():
    p = cli("bench", "drift", "--model", "elastoplastic", "--json")
    assert p.returncode == 0, p.stderr
    doc = json.loads(p.stdout)
    assert set(doc["results"]["elastoplastic"]) == {"D1", "D2", "outcome", "warnings"}


def test_bench_unknown_names_exit_2(tmp_path):
    p = cli("bench", "drfit", "--out", str(tmp_path / "x"))
    assert p.returncode == 2
    assert "did you mean 'drift'" in p.stderr and "coulomb-analytic" in p.stderr
    assert not (tmp_path / "x").exists()
    p = cli("bench", "drift", "--model", "lugr")
    assert p.returncode == 2 and "lugre" in p.stderr


def test_rig_v0_slides_with_friction_and_scale(tmp_path):
    """coulomb-robust with v0 = 1 m/s: the body slides and friction F_c = 1 N brakes it.

    Before the fix it started stuck (mode 0), applied no friction and slid at 1 m/s for ever.
    With --scale 0.5 the capacity halves: the deceleration is 0.5 m/s², so it stops at 2 s.
    """
    p = cli("rig", "--model", "coulomb-robust", "--force", "0", "--v0", "1", "--t-end", "0.5",
            "--json")
    assert p.returncode == 0, p.stderr
    doc = json.loads(p.stdout)
    assert doc["final"]["v [m/s]"] == pytest.approx(0.5, abs=1e-6)      # 1 - F_c/m·t
    out = tmp_path / "half.csv"
    p = cli("rig", "--model", "coulomb-robust", "--force", "0", "--v0", "1", "--t-end", "3",
            "--scale", "0.5", "--out", str(out), "--json")
    assert p.returncode == 0, p.stderr
    doc = json.loads(p.stdout)
    assert doc["final"]["v [m/s]"] == 0.0                       # stuck after 2 s
    assert doc["final"]["x [m]"] == pytest.approx(1.0, abs=1e-6)   # v0²/(2·0.5)
    assert "scale [-]" in out.read_text().splitlines()[0].split(",")


def test_rig_scale_and_v0_bad_input():
    p = cli("rig", "--model", "coulomb-robust", "--force", "0", "--t-end", "1",
            "--scale", "0.5 - step(0.5, 1)")
    assert p.returncode == 2 and "Traceback" not in p.stderr
    assert "--scale" in p.stderr and "t = 0.5 s" in p.stderr and ">= 0" in p.stderr
    p = cli("rig", "--model", "lugre", "--velocity", "1", "--v0", "1", "--t-end", "1")
    assert p.returncode == 2 and "--v0" in p.stderr and "force drive" in p.stderr
    p = cli("rig", "--model", "lugre", "--force", "0", "--v0", "nan", "--t-end", "1")
    assert p.returncode == 2 and "--v0" in p.stderr
