"""Every user mistake is one clear line and exit status 2: no traceback, no partial output.

A table of bad inputs (files, paths, --set edits, formulas, sizes, flags) run through
``clutchsim.cli.main`` in a scratch directory; property tests feed random scenario edits
and random signal formulas to the loader and the formula parser.
"""

from __future__ import annotations

import json
import re
import shlex
import time
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from clutchsim.cli import EPILOG, build_parser, main
from clutchsim.scenario import ScenarioError, default_scenario_text, load_scenario
from clutchsim.signal_expr import parse_signal

REPO = Path(__file__).resolve().parents[2]
SCENARIO = default_scenario_text()


def _files(d: Path) -> None:
    """The inputs the table refers to, written into the scratch directory ``d``."""
    (d / "deep.toml").write_text("v = " + "[" * 5000 + "]" * 5000 + "\n")
    (d / "binary.toml").write_bytes(bytes(range(256)) * 8)
    huge = "+".join(["0.001"] * 200_000)
    (d / "huge_expr.toml").write_text(
        re.sub(r'throttle = "[^"]*"', f'throttle = "{huge}"', SCENARIO, count=1))
    (d / "syntax.toml").write_text(SCENARIO.replace("[engine]", "[engine", 1))
    (d / "afile").write_text("not a directory\n")
    (d / "adir.csv").mkdir()
    (d / "adir.toml").mkdir()
    (d / "data.csv").write_text("t,v,F\n0,0,0\n0.1,1,1\n0.2,2,2\n")
    # output directories: a user's folder, a clutchsim run's (its manifest), a damaged one,
    # a user's file with the name of an output, a link to nowhere
    from clutchsim._util import MANIFEST
    for name, files in (("userdir", {"notes.txt": "mine\n"}),
                        ("runout", {"summary.json": "{}", MANIFEST: json.dumps(
                            {"kind": "run", "files": ["summary.json"]})}),
                        ("damaged", {"summary.json": "{bad", MANIFEST: json.dumps(
                            {"kind": "run", "files": ["summary.json"]})}),
                        ("clash", {"summary.json": "{}"}),
                        ("notout", {"a.json": "{}"})):
        (d / name).mkdir()
        for f, text in files.items():
            (d / name / f).write_text(text)
    (d / "dangling").symlink_to(d / "nowhere")


RIG = ["rig", "--model", "lugre", "--t-end", "1"]
FIT = ["fit", "data.csv", "--model", "tanh", "--input", "v", "--output", "F", "--params",
       "F_c", "--out", "fit_out"]
SWEEP = ["sweep", "--out", "sw"]

#: (argv, words every one of which the message must contain)
CASES = [
    # files
    (["run", "deep.toml", "--out", "o"], ["deep.toml", "nested too deeply"]),
    (["run", "binary.toml", "--out", "o"], ["binary.toml", "not a text file"]),
    (["run", "huge_expr.toml", "--out", "o"], ["inputs.throttle", "1,199,999 characters", "CSV"]),
    (["run", "syntax.toml", "--out", "o"], ["syntax.toml", "not valid TOML"]),
    (["run", "missing.toml", "--out", "o"], ["missing.toml", "cannot read"]),
    (["run", "adir.toml", "--out", "o"], ["adir.toml", "is a directory"]),
    # output paths
    (["run", "--out", "afile/sub"], ["--out", "afile", "is a file, not a directory"]),
    (["run", "--out", "afile"], ["--out", "afile", "not a directory"]),
    (["run", "--out", "/proc/clutchsim-test"], ["--out", "cannot write in"]),
    (RIG + ["--force", "1", "--out", "adir.csv"], ["--out", "adir.csv", "is a directory"]),
    (RIG + ["--force", "1", "--out", "afile/x.csv"], ["afile", "is a file"]),
    (RIG + ["--force", "1", "--out", "x.txt"], ["--out", "x.txt", ".csv"]),
    (["bench", "drift", "--out", "afile"], ["--out", "afile", "not a directory"]),
    (FIT[:-1] + ["afile/fit"], ["--out", "afile", "is a file"]),
    # --set edits and physical ranges
    (["run", "--set", "vehicle.mass=1e300", "--out", "o"],
     ["vehicle.mass", "1e+300", "<= 1e+06 kg", "physical range", "--set vehicle.mass=1e300"]),
    (["run", "--set", "vehicle.mass=abc", "--out", "o"],
     ["vehicle.mass", "'abc'", "--set vehicle.mass=abc"]),
    (["run", "--set", "vehicl.mass=1", "--out", "o"], ["vehicle", "--set vehicl.mass=1"]),
    (["run", "--set", "a b=1", "--out", "o"], ["--set", "not a key path"]),
    (["run", "--set", "novalue", "--out", "o"], ["--set", "expected key.path=value"]),
    (["run", "--set", "inertia[9].J=1", "--out", "o"], ["--set", "inertia[9] does not exist"]),
    (["run", "--set", "inertia[0]=5", "--out", "o"], ["inertia[0]", "must be a table"]),
    (["run", "--set", "scenario.t_end=1e9", "--out", "o"],
     ["scenario.t_end", "<= 1e+06 s", "--set"]),
    (["run", "--set", "vehicle.grade=200", "--out", "o"], ["vehicle.grade", "<= 100 %"]),
    (["run", "--set", "inertia[0].J=-1", "--out", "o"], ["inertia[0].J", "> 0 kg·m²"]),
    (["run", "--set", 'solver.method="rk99"', "--out", "o"], ["solver.method", "rk99"]),
    (["run", "--set", 'coupling[0].friction="lugre"', "--out", "o"],
     ["coupling[0].friction", 'friction = { model = "lugre" }']),
    (["run", "--set", "inputs.throttle=\"" + "(" * 60 + "1" + ")" * 60 + "\"", "--out", "o"],
     ["inputs.throttle", "parentheses nested 60 deep"]),
    # resources
    (["run", "--set", "solver.dt_out=1e-9", "--out", "o"],
     ["4,000,000,000 output rows", "--max-output-rows"]),
    (["run", "--max-output-rows", "100", "--out", "o"], ["2,001 output rows", "100 rows"]),
    (SWEEP + ["--vary", "vehicle.mass=1:2:100000", "--vary", "vehicle.grade=0:1:100000"],
     ["10,000,000,000 runs", "--max-runs"]),
    (SWEEP + ["--vary", "vehicle.mass=1100:1500:11", "--max-runs", "10"],
     ["11 runs", "limit of 10 runs"]),
    (SWEEP + ["--vary", "solver.dt_out=1e-9,1e-3"], ["--vary solver.dt_out", "output rows"]),
    # models: every one is checked before any runs
    (["run", "--model", "lugre", "--out", "o"],
     ["'lugre'", "alternatives = { lugre = {", "friction = { model ="]),
    (["run", "--model", "coulomb-robust", "--model", "nope", "--out", "o"], ["nope"]),
    (["run", "--model", "coulomb-robust", "--model", "coulomb-robust", "--out", "o"],
     ["--model", "listed twice"]),
    # formulas and rig flags
    (RIG + ["--force", "1+"], ["--force", "not a valid formula"]),
    (RIG + ["--force", "__import__('os')"], ["--force", "__import__"]),
    (RIG + ["--force", "1e308*10"], ["--force", "finite"]),
    (RIG + ["--force", "+".join(["1"] * 600)], ["--force", "operators"]),
    (["rig", "--model", "lugre", "--t-end", "-1", "--force", "1"], ["--t-end", "> 0"]),
    (["rig", "--model", "lugre", "--t-end", "nan", "--force", "1"], ["--t-end"]),
    (RIG + ["--force", "1", "--mass", "0"], ["--mass", "> 0"]),
    (["rig", "--model", "lugr", "--t-end", "1", "--force", "1"], ["lugre"]),
    (RIG + ["--force", "1", "--set", "sigma0=-1"], ["sigma0"]),
    # fit flags
    (FIT + ["--window", "5:3"], ["--window", "T0 = 5 s > T1 = 3 s"]),
    (FIT + ["--window", "a:b"], ["--window", "numbers"]),
    (FIT + ["--starts", "0"], ["--starts 0", ">= 1"]),
    (FIT + ["--option", "rtol=-1"], ["rtol = -1.0 must be > 0"]),
    (FIT + ["--option", "rtoll=1e-8"], ["'rtoll'", "did you mean 'rtol'", "options: rtol, atol"]),
    (FIT + ["--option", "rtol"], ["--option 'rtol'", "KEY=VALUE"]),
    # the same --option on every command that simulates
    (["run", "--out", "o", "--option", "rtoll=1e-8"], ["--option", "did you mean 'rtol'"]),
    (["run", "--out", "o", "--option", "rtol=-1"], ["--option", "rtol = -1.0 must be > 0"]),
    (["run", "--out", "o", "--option", "wall_time=soon"], ["'soon' is not a number"]),
    (["judder", "--at", "1", "--option", "max_stepz=10"], ["did you mean 'max_steps'"]),
    (SWEEP + ["--vary", "vehicle.mass=1300", "--option", "atl=1e-9"], ["did you mean 'atol'"]),
    # sweep flags
    (SWEEP + ["--vary", "vehicle.mass=1500:1100:3"], ["LO > HI"]),
    (SWEEP + ["--vary", "vehicle.mass=uniform(1100,1500)"], ["--samples"]),
    (SWEEP + ["--vary", "vehicle.mass=1300", "--connect-timeout", "0"],
     ["--connect-timeout"]),
    # other commands
    (["bench", "drfit"], ["drift"]),
    (["report", "no_such_dir"], ["no_such_dir", "does not exist"]),
    (["report", "notout"], ["notout", "not a clutchsim output"]),
    (["report", "damaged"], ["damaged/summary.json", "is damaged", "re-run"]),
    # output directories: never a file clutchsim did not write, checked before anything runs
    (["run", "--out", "userdir"], ["--out", "userdir", "notes.txt", "never deletes", "--force"]),
    (["run", "--out", "clash", "--force"], ["clash", "summary.json", "never overwrites"]),
    (["run", "--out", "dangling"], ["--out", "dangling", "symbolic link", "not a directory"]),
    (["bench", "drift", "--out", "runout"], ["--out", "runout", "`clutchsim run`", "--force"]),
    (["durability", "missing.toml", "--out", "userdir"], ["userdir", "notes.txt"]),
    (FIT[:-1] + ["userdir"], ["userdir", "notes.txt"]),
    (["judder", "--out", "runout"], ["runout", "`clutchsim run`"]),
    (["demo", "--out", "userdir"], ["userdir", "notes.txt"]),
    (SWEEP[:-1] + ["userdir", "--vary", "vehicle.mass=1300"], ["userdir", "not empty"]),
]


@pytest.fixture
def scratch(tmp_path, monkeypatch):
    _files(tmp_path)
    monkeypatch.chdir(tmp_path)
    return tmp_path


def _listing(d: Path) -> set:
    return {str(p.relative_to(d)) for p in d.rglob("*")}


def test_the_table_is_long_enough():
    assert len(CASES) >= 30


@pytest.mark.parametrize("argv, words", CASES, ids=[" ".join(a)[:60] for a, _ in CASES])
def test_bad_input_is_one_clear_line_and_exit_2(scratch, capsys, argv, words):
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
    assert len(lines[-1]) < 2100          # a 200 KB input is not repeated
    assert "np.float64" not in err and "[1]" not in err
    assert "running " not in err          # nothing was simulated
    assert captured.out == ""
    assert _listing(scratch) == before    # no partial output, no stray file


def test_a_friction_error_names_its_location_once(scratch, capsys):
    assert main(["run", "--model", "lugre", "--out", "o"]) == 2
    err = capsys.readouterr().err
    assert err.count("<default scenario launch.toml>") == 1, err


def test_a_bad_flag_value_is_an_argparse_error(scratch, capsys):
    with pytest.raises(SystemExit) as exc:
        main(RIG + ["--force", "1", "--max-output-rows", "0"])
    assert exc.value.code == 2
    assert "--max-output-rows" in capsys.readouterr().err


# ----------------------------------------------------------------- the help examples
def _examples(text: str) -> list[list[str]]:
    """The command lines of an epilog's ``examples:`` block (continuations joined)."""
    out, block = [], text.split("examples:", 1)[1] if "examples:" in text else ""
    block = block.split("\n\n", 1)[0].replace("\\\n", " ")
    for line in block.splitlines():
        line = line.split("  #", 1)[0].strip()
        if line.startswith("clutchsim "):
            out.append(shlex.split(line)[1:])
    return out


def test_every_subcommand_example_parses():
    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    examples = _examples(EPILOG)
    for p in sub.choices.values():
        examples += _examples(p.epilog or "")
    assert len(examples) > 20
    for argv in examples:
        try:
            parser.parse_args(argv)
        except SystemExit:
            pytest.fail(f"example does not parse: clutchsim {' '.join(argv)}")


# (that each runs as written, with its documented exit status and claims, is
# tests/docs/test_help_examples.py's "clutchsim --help" and "clutchsim CMD --help")


# ----------------------------------------------------------------- property tests
KEYS = ["vehicle.mass", "vehicle.grade", "vehicle.tyre_radius", "engine.kp", "scenario.t_end",
        "solver.dt_out", "solver.max_steps", "solver.method", "inertia[0].J",
        "inertia[1].omega0", "coupling[0].drag", "coupling[1].c", "coupling[0].friction",
        "coupling[0].friction.overrides.T_stat", "coupling[0].friction.parameter_set",
        "inputs.throttle", "scenario.models", "thermal[0].capacity", "nosuch.key",
        "inertia[7].J", "inertia", "scenario"]
VALUES = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.integers(min_value=-10**30, max_value=10**30).map(str),
    st.text(alphabet="0123456789.e+-()[]{}=,\"' abcdefxyz_", max_size=40),
    st.sampled_from(["true", "[]", "{}", "[1, 2]", '"ramp(0, 1, 1)"', '"sine(1,"', "nan",
                     "inf", '{ model = "lugre" }', '"x.csv"', "1e308", "-0.0"]),
)


@settings(max_examples=40, deadline=5000, suppress_health_check=[HealthCheck.too_slow])
@given(edits=st.lists(st.tuples(st.sampled_from(KEYS), VALUES), min_size=1, max_size=3))
def test_random_scenario_edits_raise_only_scenario_errors(edits):
    items = [f"{k}={v}" for k, v in edits]
    t0 = time.perf_counter()
    try:
        sc = load_scenario(None, overrides=items)
        sc.estimate(sc.models[0] if sc.models else None)
    except ScenarioError as exc:
        assert str(exc).startswith("<default scenario launch.toml>")
        assert "np.float64" not in str(exc)
    except ValueError as exc:   # a component's own check: still a ValueError with words
        assert str(exc)
    assert time.perf_counter() - t0 < 5.0


_ATOMS = st.one_of(
    st.floats(allow_nan=False, allow_infinity=False, width=32).map(repr),
    st.sampled_from(["pi", "t", "x", "1e400", "0", "True", "None", "'s'"]),
)


def _formula(children):
    calls = st.tuples(st.sampled_from(["const", "step", "ramp", "sine", "pulse", "exp",
                                       "__import__"]),
                      st.lists(children, max_size=6)).map(
        lambda c: f"{c[0]}({', '.join(c[1])})")
    binops = st.tuples(children, st.sampled_from(["+", "-", "*", "/", "**", "%", "@"]),
                       children).map(lambda b: f"{b[0]} {b[1]} {b[2]}")
    return st.one_of(calls, binops, children.map(lambda c: f"({c})"),
                     children.map(lambda c: f"-{c}"))


FORMULAS = st.one_of(st.recursive(_ATOMS, _formula, max_leaves=30),
                     st.text(alphabet="0123456789.+-*/()pisnect, =_", max_size=80))


@settings(max_examples=150, deadline=2000)
@given(text=FORMULAS)
def test_random_formulas_give_a_signal_or_a_value_error(text):
    t0 = time.perf_counter()
    try:
        parse_signal(text)
    except ValueError as exc:
        msg = str(exc)
        assert msg and len(msg) < 2000 and "np.float64" not in msg
    assert time.perf_counter() - t0 < 2.0
