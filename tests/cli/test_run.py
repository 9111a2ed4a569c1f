"""``clutchsim run`` through the installed entry point (a subprocess)."""

import json
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]


def _run(*args, cwd=REPO):
    return subprocess.run([sys.executable, "-m", "clutchsim", "run", *args], cwd=cwd,
                          capture_output=True, text=True, timeout=600, check=False)


def test_run_coupled_clutches_json_and_outputs(tmp_path):
    out = tmp_path / "cc"
    p = _run("examples/coupled_clutches.toml", "--out", str(out), "--json")
    assert p.returncode == 0, p.stderr
    doc = json.loads(p.stdout)
    m = doc["runs"]["CoupledClutches"]        # not a launch: named by the scenario
    assert m["completed"] and m["energy_balance_rel"] < 1e-6
    for f in ("timeseries.csv", "timeseries.parquet", "summary.json",
              "network_CoupledClutches.png"):
        assert (out / f).exists(), f
    assert not Path(str(out) + ".partial").exists()
    header = (out / "timeseries.csv").read_text().splitlines()[0]
    assert "omega_J1 [rad/s]" in header


def test_run_bad_input_exit_2_one_line(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text((REPO / "examples" / "coupled_clutches.toml").read_text()
                   .replace("t_end = 1.5", "t_end = 1.5\nt_ned = 2"))
    p = _run(str(bad), "--out", str(tmp_path / "o"))
    assert p.returncode == 2
    lines = [ln for ln in p.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and "scenario.t_ned" in lines[0] and "did you mean 't_end'" in lines[0]
    assert f"{bad}:" in lines[0]


def test_run_option_overrides_the_solver_table(tmp_path):
    """``--option`` sets the scenario's [solver] keys for the run: a step budget far below
    what the launch needs ends it with outcome ``budget`` (exit 1), where the same run
    without the option completes."""
    out = tmp_path / "budget"
    p = _run("examples/coupled_clutches.toml", "--option", "max_steps=20", "--out", str(out),
             "--json", "--no-plots")
    assert p.returncode == 1, p.stderr
    m = json.loads(p.stdout)["runs"]["CoupledClutches"]
    assert not m["completed"] and m["outcome"] == "budget", m
    assert "20" in m["message"]
