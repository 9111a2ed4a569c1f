"""``clutchsim sweep``: table on disk, JSON summary, resume, bad input (exit 2)."""

from __future__ import annotations

import json

import pytest

from clutchsim.cli import main
from clutchsim.studies.sweeps import read_results

BASE = ["--set", "scenario.t_end=1.3", "--set", "solver.dt_out=0.005", "-q"]


def test_sweep_writes_the_table_and_resumes(tmp_path, capsys):
    argv = ["sweep", "--vary", "vehicle.mass=uniform(1100,1500)", "--samples", "3",
            "--seed", "5", "--metrics", "lockup_time_s,slip_energy_J", "--out",
            str(tmp_path / "mc"), "--json", "--no-plots", *BASE]
    assert main(argv) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["runs"] == 3 and doc["status_counts"] == {"completed": 3}
    assert doc["outcome_counts"] == {"completed": 3} and doc["runs_with_warnings"] == 0
    assert doc["batched_runs"] == 3      # values on the network: one compiled batch
    t = read_results(tmp_path / "mc")
    assert list(t.columns) == ["run", "vehicle.mass", "status", "outcome", "message",
                               "warnings", "lockup_time_s", "slip_energy_J"]
    assert (t["outcome"] == "completed").all() and (t["warnings"].map(len) == 0).all()
    # like run, bench and fit: the command line and the report
    assert (tmp_path / "mc" / "command.txt").read_text().startswith("clutchsim sweep ")
    assert "<html" in (tmp_path / "mc" / "report.html").read_text()
    assert main(argv) == 0
    again = json.loads(capsys.readouterr().out)
    assert again["chunks_resumed"] == again["chunks"]
    assert read_results(tmp_path / "mc").equals(t)


@pytest.mark.parametrize("vary, words", [
    ("vehicle.mass=1500:1100:3", "LO > HI"),
    ("vehicle.mass=1100:1500:0", "N must be an integer >= 1"),
    ("vehicle.mas=1100:1500:2", "did you mean 'mass'"),
])
def test_bad_input_is_one_line_and_exit_2(tmp_path, capsys, vary, words):
    assert main(["sweep", "--vary", vary, "--out", str(tmp_path / "s"), *BASE]) == 2
    err = capsys.readouterr().err
    assert words in err and err.count("\n") == 1


def test_a_directory_of_another_sweep_is_refused(tmp_path, capsys):
    out = str(tmp_path / "s")
    assert main(["sweep", "--vary", "vehicle.mass=1300", "--out", out, "--no-plots",
                 *BASE]) == 0
    assert main(["sweep", "--vary", "vehicle.mass=1400", "--out", out, *BASE]) == 2
    assert "holds a different sweep" in capsys.readouterr().err
    (tmp_path / "other").mkdir()
    (tmp_path / "other" / "notes.txt").write_text("x")
    assert main(["sweep", "--vary", "vehicle.mass=1400", "--out", str(tmp_path / "other"),
                 *BASE]) == 2
    assert "not a sweep directory" in capsys.readouterr().err


def test_unreachable_dask_scheduler_is_exit_2(tmp_path, capsys):
    import socket
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    assert main(["sweep", "--vary", "vehicle.mass=1300", "--out", str(tmp_path / "s"),
                 "--dask", f"tcp://127.0.0.1:{port}", "--connect-timeout", "1", *BASE]) == 2
    assert "no Dask scheduler answered" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []     # the failed connection leaves nothing behind


def test_option_sets_the_solver_of_every_run(tmp_path, capsys):
    out = tmp_path / "budget"
    assert main(["sweep", "--vary", "vehicle.mass=1200,1400", "--option", "max_steps=50",
                 "--metrics", "steps", "--out", str(out), "--json", "--no-plots",
                 *BASE]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["outcome_counts"] == {"budget": 2}
    t = read_results(out)
    # (the budget counts attempted steps; the metric counts the accepted ones)
    assert ((t["steps"] > 0) & (t["steps"] <= 50)).all()
    assert t.attrs["sweep"]["options"] == {"max_steps": 50}
    # the options are part of the sweep: the same DIR with others is another sweep
    assert main(["sweep", "--vary", "vehicle.mass=1200,1400", "--option", "max_steps=60",
                 "--out", str(out), "--no-plots", *BASE]) == 2
    assert "holds a different sweep" in capsys.readouterr().err


@pytest.mark.parametrize("option, words", [
    ("rtool=1e-7", "unknown solver option 'rtool' (did you mean 'rtol'?)"),
    ("rtol=fast", "'fast' is not a number"),
    ("max_steps=2.5", "must be an integer"),
])
def test_a_bad_option_is_one_line_and_exit_2(tmp_path, capsys, option, words):
    assert main(["sweep", "--vary", "vehicle.mass=1300", "--option", option, "--out",
                 str(tmp_path / "s"), *BASE]) == 2
    err = capsys.readouterr().err
    assert words in err and err.count("\n") == 1
    assert not (tmp_path / "s").exists()
