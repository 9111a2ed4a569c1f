"""Ranges a physical system has (issue 35 §3-4): each value that used to be accepted
silently, or that ran to a misleading number, is one clear line and exit 2 before anything
runs, naming the key, the value, the unit and the rule (the same checks as
``test_bad_inputs.py``)."""

from __future__ import annotations

import pytest
from test_bad_inputs import _files, _listing

from clutchsim.cli import main

FIT = ["fit", "data.csv", "--model", "tanh", "--params", "F_c", "--out", "fit_out"]
#: (argv, words every one of which the message must contain)
CASES = [
    (["run", "--set", 'inputs.throttle="3"', "--out", "o"],
     ["inputs.throttle", "reaches 3", "outside [0, 1]", "throttle"]),
    (["run", "--set", 'inputs.throttle="-1"', "--out", "o"],
     ["inputs.throttle", "reaches -1", "outside [0, 1]"]),
    (["run", "--set", 'inputs.clutch_command="ramp(0.5, 1.2, 5)"', "--out", "o"],
     ["inputs.clutch_command", "reaches 5", "outside [-1, 1]", "COM"]),
    (["run", "--set", "engine.idle_speed=800", "--out", "o"],
     ["idle_speed = 800 rad/s", "must be in [0, 209.44]", "800 rpm = 83.8 rad/s"]),
    (["run", "--set", "coupling[0].mu_temperature={theta=[20.0, 200.0], factor=[1.0, -0.5]}",
      "--out", "o"], ["mu_temperature value -0.5", "must be >= 0"]),
    (["run", "--set", "scenario.models=[]", "--out", "o"],
     ["scenario.models", "= []", "at least one"]),
    (["run", "--set", "coupling[0].r_outer=2", "--out", "o"],
     ["coupling[0].r_outer", "= 2 m", "<= 0.5 m"]),
    (["run", "--set", "solver.dt_out=10", "--out", "o"],
     ["solver.dt_out = 10 s", "<= 0.01 s", "launch metrics"]),
    (FIT + ["--input", "F", "--output", "F"], ["input = output = 'F'", "two different"]),
    (FIT + ["--input", "v", "--output", "F", "--scale", "v=0"],
     ["data.csv", "scale v = 0", "non-zero"]),
]


@pytest.fixture
def scratch(tmp_path, monkeypatch):
    _files(tmp_path)
    monkeypatch.chdir(tmp_path)
    return tmp_path


@pytest.mark.parametrize("argv, words", CASES, ids=[" ".join(a)[:60] for a, _ in CASES])
def test_out_of_range_input_is_one_clear_line_and_exit_2(scratch, capsys, argv, words):
    before = _listing(scratch)
    code = main(argv)
    captured = capsys.readouterr()
    err = captured.err
    assert code == 2, err
    assert "Traceback" not in err and "internal error" not in err
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert lines and lines[-1].startswith(f"clutchsim {argv[0]}: error: "), err
    for w in words:
        assert w in lines[-1], (w, lines[-1])
    assert "running " not in err          # nothing was simulated
    assert captured.out == ""
    assert _listing(scratch) == before


def test_a_range_error_in_a_file_names_the_file_and_line(scratch, capsys):
    from clutchsim.scenario import default_scenario_text
    text = default_scenario_text().replace("idle_speed = 83.78", "idle_speed = 800.0", 1)
    (scratch / "idle.toml").write_text(text, encoding="utf-8")
    assert main(["run", "idle.toml", "--out", "o"]) == 2
    err = capsys.readouterr().err
    line = next(i for i, ln in enumerate(text.splitlines(), 1) if ln.startswith("[engine]"))
    assert f"idle.toml:{line}:" in err and "idle_speed = 800 rad/s" in err, err


def test_a_start_value_outside_its_bounds_gets_a_note(scratch, capsys):
    """It used to pass without a word (the fit silently started from the bound)."""
    import numpy as np
    t = np.arange(0.0, 2.0, 0.001)
    v = np.sin(2 * np.pi * t)
    np.savetxt(scratch / "sine.csv", np.c_[t, v, 3.0 * np.tanh(v / 0.01)], delimiter=",",
               header="t,v,F", comments="")
    code = main(["fit", "sine.csv", "--model", "tanh", "--input", "v", "--output", "F",
                 "--params", "F_c", "--bounds", "F_c=5:10", "--out", "fo", "--no-plots"])
    err = capsys.readouterr().err
    assert code == 0, err
    assert "note: start value F_c = 1 lies outside its bounds [5, 10]" in err, err
