"""Exit status when some models fail, and SIGTERM: partial outputs removed, sweeps resumable."""

from __future__ import annotations

import json
import os
import signal

import pytest

from clutchsim.cli import main

FAST = ["--set", "scenario.t_end=1.3", "--set", "solver.dt_out=0.005", "-q"]


def test_run_exits_1_when_any_model_fails_and_the_json_says_which(tmp_path, capsys):
    # three models on the default launch; the naive switching model chatters at lock-up
    models = ["--model", "mykhailevych2020", "--model", "coulomb-robust", "--model",
              "coulomb-naive"]
    code = main(["run", *models, "--out", str(tmp_path / "o"), "--json", "--no-plots", "-q"])
    captured = capsys.readouterr()
    assert code == 1, captured.err
    doc = json.loads(captured.out)
    assert doc["failed"] == ["coulomb-naive"]
    assert doc["models"]["coulomb-naive"]["outcome"] == "chatter"
    assert doc["models"]["coulomb-robust"]["outcome"] == "completed"
    assert all(isinstance(m["warnings"], list) for m in doc["models"].values())
    assert json.loads((tmp_path / "o" / "summary.json").read_text())["failed"] == \
        ["coulomb-naive"]
    assert "1 of 3 models did not complete: coulomb-naive (chatter)" in captured.err
    assert (tmp_path / "o" / "report.html").is_file()


def _sigterm_self():
    os.kill(os.getpid(), signal.SIGTERM)


def test_sigterm_during_a_run_removes_the_partial_directory(tmp_path, capsys, monkeypatch):
    from clutchsim.scenario import outputs
    real = outputs.write_runs

    def write_then_terminated(scenario, models, directory, **kw):
        (directory / "half-written.csv").write_text("1,2\n")
        _sigterm_self()
        return real(scenario, models, directory, **kw)

    monkeypatch.setattr(outputs, "write_runs", write_then_terminated)
    out = tmp_path / "o"
    before = signal.getsignal(signal.SIGTERM)
    assert main(["run", "--out", str(out), "--model", "coulomb-robust", "--no-plots"]) == 143
    assert "interrupted (SIGTERM)" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []             # no DIR, no DIR.partial
    assert signal.getsignal(signal.SIGTERM) is before  # the previous handler is back


def test_sigterm_during_a_sweep_keeps_the_chunks_to_resume(tmp_path, capsys, monkeypatch):
    from clutchsim.sweeps import backends
    real = backends.run_chunk
    calls = {"n": 0}

    def chunk_then_terminated(job, runs):
        calls["n"] += 1
        if calls["n"] == 3:
            _sigterm_self()
        return real(job, runs)

    argv = ["sweep", "--vary", "vehicle.mass=1100:1500:40", "--workers", "1",
            "--chunk-size", "8", "--out", str(tmp_path / "s"), "--no-plots", "--json", *FAST]
    monkeypatch.setattr(backends, "run_chunk", chunk_then_terminated)
    assert main(argv) == 143
    err = capsys.readouterr().err
    assert "re-run the same command to resume" in err
    chunks = sorted((tmp_path / "s" / "chunks").iterdir())
    assert 2 <= len(chunks) < 5 and not (tmp_path / "s" / "results.parquet").exists()
    monkeypatch.setattr(backends, "run_chunk", real)
    assert main(argv) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["runs"] == 40 and doc["chunks_resumed"] == len(chunks)
    assert doc["status_counts"] == {"completed": 40}


@pytest.mark.parametrize("interrupt", [KeyboardInterrupt, SystemExit])
def test_atomic_directory_removes_the_partial_on_any_interrupt(tmp_path, interrupt):
    from clutchsim.cli import Terminated
    from clutchsim.core.result import atomic_directory
    for exc in (interrupt, Terminated):
        with pytest.raises(exc), atomic_directory(tmp_path / "d") as part:
            (part / "x").write_text("x")
            raise exc()
        assert list(tmp_path.iterdir()) == []
