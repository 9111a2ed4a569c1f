"""Ranges a physical system has (issue 35 §3-4): each value that used to be accepted
silently, or that ran to a misleading number, is one clear line and exit 2 before anything
runs, naming the key, the value, the unit and the rule (the same checks as
``test_bad_inputs.py``)."""

from __future__ import annotations

import pytest
from test_bad_inputs import REPO, _files, _listing

from clutchsim.cli import main
from clutchsim.scenario import default_scenario_text

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
     ["engine.idle_speed", "= 800 rad/s", "must be <= 209.44 rad/s", "physical range"]),
    (["run", "--set", "coupling[0].mu_temperature={theta=[20.0, 200.0], factor=[1.0, -0.5]}",
      "--out", "o"], ["mu_temperature value -0.5", "must be >= 0"]),
    (["run", "--set", "scenario.models=[]", "--out", "o"],
     ["scenario.models", "= []", "at least one"]),
    (["run", "--set", "coupling[0].r_outer=2", "--out", "o"],
     ["coupling[0].r_outer", "= 2 m", "<= 0.5 m"]),
    (["run", "--set", "solver.dt_out=10", "--out", "o"],
     ["solver.dt_out = 10 s", "<= 0.01 s", "launch metrics"]),
    (FIT + ["--input", "F", "--output", "F"], ["input = output = 'F'", "two different"]),
    # weak messages mended: file:line, the key, the unit of the domain, no numpy reprs
    (["run", "tiny_j.toml", "--out", "o"],
     ["tiny_j.toml:", "inertia[1]", "1e-12 kg·m²", "below 1e-12 of the largest"]),
    (["run", "no_gears.toml", "--out", "o"],
     ["no_gears.toml:", "coupling[2].ratios", "= [] lists no gear"]),
    (["run", "two_engines.toml", "--out", "o"],
     ["two_engines.toml:", "engine 'engine2' and engine 'engine_torque' both write",
      "T_engine"]),
    (["run", str(REPO / "examples" / "dct_upshift.toml"), "--set",
      "component[2].friction.overrides.F_c=3000.0", "--out", "o"],
     ["component[2].friction", "F_s = 330 N·m must be >= F_c = 3000 N·m"]),
    (["fit", "gap.csv", "--model", "tanh", "--input", "v", "--output", "F", "--params", "F_c",
      "--out", "fo"], ["gap.csv", "column 'v' has 1 NaN/inf value(s) at row 1", "--nan drop"]),
    (["fit", "binary.csv", "--model", "tanh", "--input", "v", "--output", "F", "--params",
      "F_c", "--out", "fo"], ["binary.csv", "not a text file", "byte 0x80"]),
    (["run", "csv_nan.toml", "--out", "o"],
     ["csv_nan.toml:", "inputs.throttle", "thr.csv", "row 2 (time 1 s, value nan)"]),
    (FIT + ["--input", "v", "--output", "F", "--scale", "v=0"],
     ["data.csv", "scale v = 0", "non-zero"]),
]


def _more_files(d) -> None:
    text = default_scenario_text()
    (d / "tiny_j.toml").write_text(text.replace("J = 0.015", "J = 1e-12", 1))
    (d / "no_gears.toml").write_text(text.replace("ratios = [3.6, 2.1, 1.4, 1.0, 0.8]",
                                                  "ratios = []", 1))
    dmf = (REPO / "examples" / "launch_dmf.toml").read_text(encoding="utf-8")
    i = dmf.index('[[component]]\ntype = "engine"')
    j = dmf.index("[[component]]", i + 5)
    dmf = dmf[:j] + dmf[i:j].replace('name = "engine_torque"', 'name = "engine2"') + dmf[j:]
    dmf = dmf.replace('    ["engine_torque.flange", "engine.a"],',
                      '    ["engine_torque.flange", "engine.a"],\n    ["engine2.flange", "engine.a"],')
    (d / "two_engines.toml").write_text(dmf)
    (d / "gap.csv").write_text("t,v,F\n0,1,1\n0.1,,2\n0.2,1,3\n")
    (d / "binary.csv").write_bytes(bytes(range(256)) * 8)
    (d / "thr.csv").write_text("t,throttle\n0,0.1\n1,nan\n2,0.3\n")
    (d / "csv_nan.toml").write_text(text.replace('throttle = "0.1 + ramp(0.3, 0.5, 0.25)"',
                                                 'throttle = "thr.csv"', 1))


@pytest.fixture
def scratch(tmp_path, monkeypatch):
    _files(tmp_path)
    _more_files(tmp_path)
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
    assert "np.float64" not in err        # no numpy reprs
    assert captured.out == ""
    assert _listing(scratch) == before


def test_a_range_error_in_a_file_names_the_file_and_line(scratch, capsys):
    from clutchsim.scenario import default_scenario_text
    text = default_scenario_text().replace("idle_speed = 83.78", "idle_speed = 800.0", 1)
    (scratch / "idle.toml").write_text(text, encoding="utf-8")
    assert main(["run", "idle.toml", "--out", "o"]) == 2
    err = capsys.readouterr().err
    line = next(i for i, ln in enumerate(text.splitlines(), 1)
                if ln.startswith("idle_speed = 800.0"))
    assert f"idle.toml:{line}:" in err and "engine.idle_speed: = 800.0 rad/s" in err, err


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
