"""``clutchsim fit``: JSON document, output files, and exit status 2 on bad input."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from clutchsim.cli import main
from clutchsim.core import SolverOptions, Table, simulate
from clutchsim.data import shared_dir
from clutchsim.friction import make_model
from clutchsim.rig import make_rig

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def record(tmp_path_factory) -> Path:
    """A synthetic CSV: tanh friction (F_c = 1 N, sigma2 = 3 N·s/m) under a sine velocity."""
    t = np.linspace(0.0, 2.0, 1001)
    v = 0.05 * np.sin(2 * np.pi * t)
    model = make_model("tanh", F_c=1.0, v_t=1e-2, sigma2=3.0)
    res = simulate(make_rig(model, drive="velocity"), (0.0, 2.0),
                   {"v": Table(t, v, hit_knots=False), "scale": 1.0},
                   options=SolverOptions(rtol=1e-10, atol=1e-12, dt_out=0.002))
    F = np.interp(t, res.t, res["F"]) + np.random.default_rng(0).normal(0, 0.01, t.size)
    path = tmp_path_factory.mktemp("cli") / "rec.csv"
    np.savetxt(path, np.column_stack([t, v * 1e3, F]), delimiter=",",
               header="time,v_mm_s,force", comments="")
    return path


def _args(record, out, *extra):
    return ["fit", str(record), "--model", "tanh", "--plant", "rig-velocity",
            "--time", "time", "--column", "v=v_mm_s", "--column", "F=force",
            "--scale", "v=1e-3", "--input", "v", "--output", "F", "--start", "F_c=2",
            "--start", "v_t=1e-2", "--start", "sigma2=1", "--out", str(out), *extra]


def test_json_document_and_output_files(record, tmp_path, capsys):
    out = tmp_path / "fit"
    code = main(_args(record, out, "--params", "F_c,sigma2", "--bounds", "sigma2=0.1:10",
                      "--validate", str(record), "--json", "--quiet"))
    captured = capsys.readouterr()
    assert code == 0, captured.err
    doc = json.loads(captured.out)
    assert set(doc) == {"model", "parameters", "stderr", "nrmse_fit", "nrmse_validation",
                        "nrmse_pooled", "records", "validation", "at_bound", "unidentified",
                        "warnings", "notes"}
    assert doc["model"] == "tanh"
    assert doc["parameters"]["F_c"] == pytest.approx(1.0, rel=0.02)
    assert doc["parameters"]["sigma2"] == pytest.approx(3.0, rel=0.05)
    assert set(doc["stderr"]) == {"F_c", "sigma2"}
    assert doc["nrmse_validation"] == pytest.approx(doc["nrmse_fit"])
    for name in ("fit.json", "fit.png", "residuals.png", "traces.csv", "report.md"):
        assert (out / name).is_file(), name
    full = json.loads((out / "fit.json").read_text())
    assert full["bounds"]["sigma2"] == [0.1, 10.0] and full["plant"] == "rig-velocity"


@pytest.mark.parametrize("extra, message", [
    (["--params", "F_c", "--bounds", "F_c=2:1"], "lo = 2 must be < hi = 1"),
    (["--params", "F_c,sigma9"], "tanh has no parameter 'sigma9'"),
    (["--params", "F_c", "--bounds", "F_c=abc"], "expected NAME=LO:HI"),
    (["--params", "F_c", "--column", "v=speed"], "missing column(s) 'speed'"),
    (["--params", "F_c", "--option", "rtoll=1e-9"],
     "unknown solver option 'rtoll' (did you mean 'rtol'?); options: rtol, atol, h0"),
    (["--params", "F_c", "--option", "max_steps=abc"],
     "--option 'max_steps=abc': 'abc' is not a number"),
])
def test_bad_input_exits_2_with_one_line(record, tmp_path, capsys, extra, message):
    code = main(_args(record, tmp_path / "o", *extra, "--quiet"))
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2
    assert len(err) == 1 and message in err[0], err


def test_solver_options_reach_every_simulation(record, tmp_path, capsys):
    """--option is read into the fit's SolverOptions: 20 steps cannot cover the record, so
    no simulation completes and the command reports exit status 1; with other options the
    fit completes."""
    code = main(_args(record, tmp_path / "o", "--params", "F_c", "--option", "max_steps=20",
                      "--quiet", "--no-plots"))
    err = capsys.readouterr().err
    assert code == 1 and "did not complete" in err, err
    code = main(_args(record, tmp_path / "o2", "--params", "F_c,sigma2", "--option",
                      "rtol=1e-7", "--option", "wall_time=20", "--json", "--quiet",
                      "--no-plots"))
    captured = capsys.readouterr()
    assert code == 0, captured.err
    assert json.loads(captured.out)["parameters"]["F_c"] == pytest.approx(1.0, rel=0.02)


def test_bad_files_exit_2(tmp_path, capsys):
    bad = tmp_path / "bad.csv"
    bad.write_text("t,v,F\n0,1,1\n0.2,1,2\n0.1,1,3\n")
    code = main(["fit", str(bad), "--model", "tanh", "--input", "v", "--output", "F",
                 "--params", "F_c", "--out", str(tmp_path / "o")])
    assert code == 2 and "must increase strictly" in capsys.readouterr().err
    gap = tmp_path / "gap.csv"
    gap.write_text("t,v,F\n0,1,1\n0.1,,2\n0.2,1,3\n")
    code = main(["fit", str(gap), "--model", "tanh", "--input", "v", "--output", "F",
                 "--params", "F_c", "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert code == 2 and "column 'v' has 1 NaN/inf value(s) at row 1" in err
    assert "nan='drop'" in err


def test_entry_point_exit_status_in_subprocess(tmp_path):
    proc = subprocess.run([sys.executable, "-m", "clutchsim", "fit", str(tmp_path / "no.csv"),
                           "--model", "lugre", "--input", "v", "--output", "F", "--params",
                           "F_c", "--out", str(tmp_path / "o")],
                          capture_output=True, text=True, timeout=120, check=False)
    assert proc.returncode == 2
    assert "no such data file" in proc.stderr and proc.stdout == ""


def test_emps_spec_runs_from_the_command_line(tmp_path, capsys):
    if not (shared_dir() / "data" / "emps" / "DATA_EMPS.mat").is_file():
        pytest.skip(f"shared data not available under {shared_dir()} (set CLUTCHSIM_SHARED)")
    code = main(["fit", str(ROOT / "examples" / "fit_emps.toml"), "--model", "tanh",
                 "--params", "F_c,sigma2", "--window", "0:4", "--out", str(tmp_path / "e"),
                 "--json", "--quiet", "--no-plots"])
    captured = capsys.readouterr()
    assert code == 0, captured.err
    doc = json.loads(captured.out)
    assert doc["model"] == "tanh" and doc["nrmse_validation"] is None
    assert 5.0 < doc["parameters"]["F_c"] < 50.0


def _load_records(folder: Path):
    """Two CSV records of tanh friction at loads 0.5 and 1.5 (capacity 0.4 + 0.6·s) and a
    third at load 1 with a fixture force column Fx (declared, absent from the others)."""
    t = np.linspace(0.0, 2.0, 1001)
    v = 0.05 * np.sin(2 * np.pi * t)
    paths = []
    for name, s, fx in (("a", 0.5, 0.0), ("b", 1.5, 0.0), ("c", 1.0, 0.2)):
        model = make_model("tanh", F_c=2.0, v_t=1e-2, sigma2=3.0)
        res = simulate(make_rig(model, drive="velocity"), (0.0, 2.0),
                       {"v": Table(t, v, hit_knots=False), "scale": 0.4 + 0.6 * s},
                       options=SolverOptions(rtol=1e-10, atol=1e-12, dt_out=0.002))
        F = np.interp(t, res.t, res["F"]) + fx * np.cos(3 * t)
        cols = [t, v, F, np.full(t.size, 20.0 * s)] + ([fx * np.cos(3 * t)] if fx else [])
        head = "t,v,F,N" + (",Fx" if fx else "")
        path = folder / f"{name}.csv"
        np.savetxt(path, np.column_stack(cols), delimiter=",", header=head, comments="")
        paths.append(path)
    return paths


def test_spec_with_several_records_and_several_validation_files(tmp_path, capsys):
    _load_records(tmp_path)
    spec = tmp_path / "loads.toml"
    spec.write_text('''[data]
derived = { s = { expr = "N / 20.0", unit = "-" } }

[plant]
kind = "rig-velocity"
options = { scale = "s", load_fraction = 0.9 }

[inputs.Fx]
to = "force"
unit = "N"

[fit]
model = "tanh"
input = "v"
output = "F"

[[records]]
file = "a.csv"

[[records]]
file = "c.csv"

[models.tanh]
start = { F_c = 1.0, v_t = 1e-2, sigma2 = 1.0 }
params = ["F_c", "sigma2", "load_fraction"]
''')
    code = main(["fit", str(spec), "--validate", str(tmp_path / "b.csv"),
                 str(tmp_path / "c.csv"), "--out", str(tmp_path / "o"), "--json", "--quiet",
                 "--no-plots"])
    captured = capsys.readouterr()
    assert code == 0, captured.err
    doc = json.loads(captured.out)
    assert doc["parameters"]["load_fraction"] == pytest.approx(0.6, abs=0.01)
    assert doc["parameters"]["F_c"] == pytest.approx(2.0, rel=0.01)
    assert [Path(r["source"]).name for r in doc["records"]] == ["a.csv", "c.csv"]
    assert [Path(r["source"]).name for r in doc["validation"]] == ["b.csv", "c.csv"]
    assert all(r["nrmse"] < 1e-3 for r in doc["records"] + doc["validation"])
    assert doc["nrmse_pooled"] < 1e-3
    assert any("a.csv" in n and "'Fx'" in n for n in doc["notes"])
    report = (tmp_path / "o" / "report.md").read_text()
    assert "fit 2" in report and "validation 2" in report and "pooled" in report
    # text output: one line per record
    code = main(["fit", str(spec), "--validate", str(tmp_path / "b.csv"),
                 "--out", str(tmp_path / "o2"), "--quiet", "--no-plots"])
    out = capsys.readouterr().out
    assert code == 0 and "NRMSE fit a.csv" in out and "NRMSE pooled" in out
    assert "NRMSE validation b.csv" in out
    # bad input: a declared column that no record has, with the spec file, line and key
    spec.write_text(spec.read_text().replace('file = "c.csv"', 'file = "b.csv"'))
    code = main(["fit", str(spec), "--out", str(tmp_path / "o3"), "--quiet"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1
    assert ("loads.toml:8: [inputs.Fx]: declared input column 'Fx' (to force) is in none "
            "of the records (fitting: ") in err[0]
    # a column only in a validation record is fine (it is zero in the fitting records)
    code = main(["fit", str(spec), "--validate", str(tmp_path / "c.csv"), "--out",
                 str(tmp_path / "o4"), "--quiet", "--no-plots"])
    assert code == 0, capsys.readouterr().err


@pytest.mark.parametrize("table, message", [
    ("[solver]\nmethod = \"dopri5\"\nrtol = 1e-9\nmax_steps = 20\n", None),
    ("[solver]\nmethod = \"rodas9\"\n",
     "spec.toml:15: [solver] method: solver = 'rodas9' is not known (did you mean"),
    ("[solver]\nrtoll = 1e-9\n",
     "[solver] unknown key 'rtoll' (did you mean 'rtol'?); keys: method, rtol, atol"),
    ("[solver]\nrtol = \"tight\"\n",
     "spec.toml:15: [solver] rtol: solver option rtol = 'tight' must be a number"),
    ("", ("spec.toml:11: [fit] rtol: the integrator and its options are written in a "
          "[solver] table, as in a scenario (keys: method, rtol, atol")),
])
def test_a_spec_sets_solver_options_in_its_solver_table(record, tmp_path, capsys, table,
                                                        message):
    spec = tmp_path / "spec.toml"
    fit_rtol = "" if table else "rtol = 1e-8\n"
    spec.write_text(f'''[data]
file = "{record}"
time = "time"
columns = {{ v = "v_mm_s", F = "force" }}
scale = {{ v = 1e-3 }}
[plant]
kind = "rig-velocity"
[fit]
input = "v"
output = "F"
{fit_rtol}[models.tanh]
start = {{ F_c = 2.0, v_t = 1e-2, sigma2 = 1.0 }}
{table}'''.replace("[models.tanh]", "[models.tanh]\nparams = [\"F_c\"]", 1))
    code = main(["fit", str(spec), "--model", "tanh", "--out", str(tmp_path / "o"), "--quiet",
                 "--no-plots"])
    err = capsys.readouterr().err.strip().splitlines()
    if message is None:      # max_steps = 20 from the spec reaches the simulations
        assert code == 1 and "did not complete" in err[-1], err
        return
    assert code == 2 and len(err) == 1 and message in err[0], err
