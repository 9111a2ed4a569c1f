"""Exit status when some models fail, and SIGTERM: partial outputs removed, sweeps resumable."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time

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
    from clutchsim.studies.sweeps import backends
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


#: a run whose integration takes ~25 s (10 million steps of at most 10 µs) once compiled
LONG = ["run", "--model", "coulomb-robust", "--no-plots", "--set", "solver.dt_out=0.01",
        "--option", "h_max=1e-5", "--option", "max_steps=20000000",
        "--set", "scenario.t_end=100"]


def _clutchsim(*args, **kw):
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    return subprocess.Popen([sys.executable, "-m", "clutchsim", *args], env=env, text=True,
                            stderr=subprocess.PIPE, stdout=subprocess.DEVNULL, **kw)


def _tree(d):
    return {str(p.relative_to(d)): p.read_bytes() if p.is_file() else None
            for p in sorted(d.rglob("*"))}


@pytest.fixture(scope="module")
def earlier_output(tmp_path_factory):
    """A finished run's output directory (its run also compiles or loads the plant)."""
    out = tmp_path_factory.mktemp("signals") / "o"
    with _clutchsim(*LONG[:-6], "--set", "scenario.t_end=0.5", "--out", str(out)) as p:
        err = p.stderr.read()
        assert p.wait(timeout=600) == 0, err
    return out


@pytest.mark.parametrize("sig, code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_a_signal_inside_the_compiled_loop_interrupts_the_run(earlier_output, sig, code):
    """A real signal while the integrator runs: exit 130 / 143 within moments (the loop
    stops; it used to run on to its end, or end in "internal error: SystemError"), one line
    "interrupted", no traceback, and the earlier output exactly as it was."""
    before = _tree(earlier_output.parent)
    p = _clutchsim(*LONG, "--out", str(earlier_output))
    with p:
        err = []
        for line in p.stderr:              # the run starts after this line ...
            err.append(line)
            if line.startswith("running "):
                break
        time.sleep(2.5)                    # ... and the plant is loaded within moments
        assert p.poll() is None, "".join(err)
        sent = time.perf_counter()
        p.send_signal(sig)
        err.append(p.stderr.read())
        rc = p.wait(timeout=120)
        late = time.perf_counter() - sent
    err = "".join(err)
    assert rc == code, err
    assert f"interrupted ({sig.name})" in err
    assert "Traceback" not in err and "internal error" not in err and "SystemError" not in err
    assert late < 5.0, f"the run went on for {late:.1f} s after the signal"
    assert _tree(earlier_output.parent) == before   # no DIR.partial, no lock, no .tmp




def _wait_for(cond, timeout=30.0):
    end = time.perf_counter() + timeout
    while not cond() and time.perf_counter() < end:
        time.sleep(0.01)
    return cond()


@pytest.fixture
def python_sigint():
    """Python's own SIGINT handler, whatever the test runner inherited: a shell that starts
    the suite as a background job ignores SIGINT, and Python then keeps SIG_IGN."""
    original = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, original)


def test_a_deferred_signal_stops_the_loop_and_is_delivered_after_it(python_sigint):
    """``interrupts_deferred`` (what ``simulate`` wraps the compiled loop in): a signal sets
    the loop's stop flag at once and raises only when the block ends; a handler that does
    not stop the program is called late and does not cut the run short."""
    import numpy as np

    from clutchsim.cli import Terminated, _install_sigterm
    from clutchsim.core import cengine as drv
    from clutchsim.core.simulate import interrupts_deferred
    iopt = np.zeros(drv.N_IOPT, dtype=np.int64)
    with pytest.raises(KeyboardInterrupt), interrupts_deferred(iopt):
        os.kill(os.getpid(), signal.SIGINT)
        assert _wait_for(lambda: iopt[drv.I_STOP] == 1)   # raised nothing here
    assert iopt[drv.I_STOP] == 0
    with pytest.raises(KeyboardInterrupt):      # outside a run: at once, as before
        os.kill(os.getpid(), signal.SIGINT)
        time.sleep(1)
    previous = _install_sigterm()
    try:
        with pytest.raises(Terminated), interrupts_deferred(iopt):
            os.kill(os.getpid(), signal.SIGTERM)
            assert _wait_for(lambda: iopt[drv.I_STOP] == 1)
        seen = []
        signal.signal(signal.SIGTERM, lambda s, f: seen.append(s))
        with interrupts_deferred(iopt):
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(0.2)
            assert iopt[drv.I_STOP] == 0 and seen == []
        assert seen == [signal.SIGTERM]
    finally:
        signal.signal(signal.SIGTERM, previous)
