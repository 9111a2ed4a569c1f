"""The fixed-step real-time kernel (``clutchsim rt``, :mod:`clutchsim.fmu.realtime`).

Checked: the default launch at 1 kHz against the variable-step run (lock-up time within
1 %, peak jerk within 5 %, engine speed within 5 rpm: the targets of the real-time issue),
first-order convergence of the kernel's error as the step halves (events at step ends, inputs
held), bit-identical repeated runs, a step beyond the plant's limit refused (the mode, the
rule, the largest step), an engine stall ending the run as the variable-step run's does, ROS2's
stability function (A- and L-stable: why the limit is one of accuracy), and the library's
C: strict C99, and nothing but arithmetic, libm and memcpy/memset among the step's symbols
(no allocation, no I/O).
"""

from __future__ import annotations

import json
import math
import shutil
import subprocess

import numpy as np
import pytest
from _dl_paths import EXAMPLES

from clutchsim.cli import main
from clutchsim.fmu.realtime import (
    AGREEMENT,
    OMEGA_H_MAX,
    RealtimeError,
    RealtimeKernel,
    export_realtime,
    ros2_damping,
    run_realtime,
)
from clutchsim.scenario import resolve_scenario


@pytest.fixture(scope="module")
def rt_1khz(tmp_path_factory):
    out = tmp_path_factory.mktemp("rt") / "launch_rt"
    return export_realtime(EXAMPLES / "launch.toml", out, step=1e-3)


def test_default_launch_at_1khz_matches_the_variable_step_run(rt_1khz):
    c = rt_1khz.check
    assert c["status"] == "completed" and c["steps"] == 4000
    assert c["warnings"] == []
    assert c["lockup_time_s"]["relative_error"] <= AGREEMENT["lockup_time_s"]
    assert c["jerk_peak_mps3"]["relative_error"] <= AGREEMENT["jerk_peak_mps3"]
    assert c["engine_speed_max_error_rpm"] <= AGREEMENT["engine_speed_max_error_rpm"]
    # measured: 5e-4, 5e-4 and 1.4 rpm; a tenth of the targets at most
    assert c["lockup_time_s"]["relative_error"] < 1e-3
    assert c["engine_speed_max_error_rpm"] < 2.0
    assert rt_1khz.model == "mykhailevych2020"
    assert rt_1khz.step_max > 1e-3


def test_error_falls_as_the_step_halves_and_runs_repeat_bit_for_bit(rt_1khz, tmp_path):
    half = export_realtime(EXAMPLES / "launch.toml", tmp_path / "half", step=5e-4)
    e1 = rt_1khz.check["engine_speed_max_error_rpm"]
    e2 = half.check["engine_speed_max_error_rpm"]
    assert e2 < 0.7 * e1, (e1, e2)          # first order: 1.42 -> 0.71 rpm
    k = RealtimeKernel(rt_1khz.out)
    sc = resolve_scenario(EXAMPLES / "launch.toml", None)
    a, b = run_realtime(k, sc), run_realtime(k, sc)
    for name in ("omega_engine", "T_clutch", "a_vehicle"):
        assert np.array_equal(a[name], b[name])


def test_the_layout_and_sources_are_written(rt_1khz):
    d = rt_1khz.out
    names = sorted(p.name for p in d.iterdir() if not p.name.startswith("."))
    assert {"plant.c", "model.h", "clutchsim_rt.h", "rt_kernel.c", "ros2.c", "rt.json",
            "README.md", "libclutchsim_rt.so"} <= set(names)
    info = json.loads((d / "rt.json").read_text())
    assert info["step_s"] == 1e-3 and info["inputs"] == ["clutch_command", "throttle"]
    assert info["parameters"]["vehicle.mass"] >= 0
    header = (d / "model.h").read_text()
    assert "#define CS_RT_STEP 0.001" in header
    assert "#define CS_RT_U_throttle 1" in header


def test_a_step_beyond_the_limit_is_refused_naming_the_mode(tmp_path):
    with pytest.raises(RealtimeError, match=r"--step 0\.002 s: too long for the mode at "
                                            r"6\d\.\d+ Hz of \w+.*\(after lock-up .*ω·h = "
                                            r".* > 0\.5 .*largest step is 0\.00126"):
        export_realtime(EXAMPLES / "launch.toml", tmp_path / "x", step=2e-3)
    assert not (tmp_path / "x").exists()


@pytest.mark.parametrize("step", [0.0, -1e-3, float("nan"), 1.0])
def test_a_step_that_is_not_a_step_is_refused(tmp_path, step):
    with pytest.raises(RealtimeError, match=r"--step .*: the fixed step must be a number of "
                                            r"seconds in \(0, 0\.1\]"):
        export_realtime(None, tmp_path / "x", step=step)


def test_an_unknown_reset_policy_names_the_option_the_user_typed(tmp_path, capsys):
    code = main(["rt", str(EXAMPLES / "launch.toml"), "--step", "1e-3", "--reset", "bogus",
                 "--out", str(tmp_path / "r")])
    err = capsys.readouterr().err
    assert code == 2 and "Traceback" not in err
    assert "--reset bogus: model (6)'s reset policy is one of clamp, zero" in err
    assert "overrides" not in err and not (tmp_path / "r").exists()


def test_cli_exit_2_for_a_long_step_and_one_json_document(tmp_path, capsys):
    code = main(["rt", str(EXAMPLES / "launch.toml"), "--step", "0.005", "--out",
                 str(tmp_path / "r")])
    cap = capsys.readouterr()
    assert code == 2 and cap.out == "" and "Traceback" not in cap.err
    assert "too long for the mode at" in cap.err
    code = main(["rt", "--step", "1e-3", "--out", str(tmp_path / "ok"), "--json"])
    cap = capsys.readouterr()
    assert code == 0, cap.err
    doc = json.loads(cap.out)
    assert doc["step_s"] == 1e-3 and doc["check"]["warnings"] == []


def test_an_engine_stall_ends_the_run_as_a_failure_event(rt_1khz):
    k = RealtimeKernel(rt_1khz.out)
    t = np.arange(4000) * 1e-3
    dump = np.column_stack([np.clip((t - 0.1) / 0.05, 0.0, 1.0), np.zeros_like(t)])
    rec, status = k.run(dump, record=("omega_engine",))
    assert status == 3                           # the plant's stall event: a failure
    w = rec[:, 0]
    last = np.flatnonzero(~np.isnan(w))[-1]
    assert w[last] * 30 / math.pi < 420.0        # at the stall speed (400 rpm) when it ends
    assert np.all(np.isnan(w[last + 1:]))


def test_ros2_is_a_and_l_stable_and_damps_as_documented():
    for wh in np.geomspace(1e-3, 1e4, 200):
        a, _ = ros2_damping(float(wh))
        assert a <= 1.0 + 1e-15
    assert ros2_damping(1e6)[0] < 1e-5           # L-stable: R(∞) = 0
    assert ros2_damping(OMEGA_H_MAX)[1] == pytest.approx(0.180, abs=1e-3)
    assert ros2_damping(0.2)[1] == pytest.approx(0.0263, abs=1e-4)


@pytest.mark.skipif(shutil.which("nm") is None, reason="nm (binutils) lists the symbols")
def test_the_step_needs_no_allocation_and_no_io(rt_1khz, tmp_path):
    from clutchsim.cgen.compiler import find_compiler
    cc = find_compiler()
    objs = []
    for src in ("rt_kernel.c", "plant.c"):
        obj = tmp_path / (src[:-2] + ".o")
        subprocess.run([cc, "-std=c99", "-pedantic", "-Wall", "-Wextra", "-O2", "-c",
                        f"-I{rt_1khz.out}", "-o", str(obj), str(rt_1khz.out / src)],
                       check=True, capture_output=True, text=True)
        objs.append(obj)
    strict = subprocess.run([cc, "-std=c99", "-pedantic", "-Wall", "-Wextra",
                             "-Wno-unused-parameter", "-Werror", "-fsyntax-only",
                             f"-I{rt_1khz.out}", str(rt_1khz.out / "rt_kernel.c")],
                            capture_output=True, text=True, check=False)
    assert strict.returncode == 0, strict.stderr
    undefined = set()
    for obj in objs:
        out = subprocess.run(["nm", "-u", str(obj)], capture_output=True, text=True,
                             check=True).stdout
        undefined |= {line.split()[-1] for line in out.splitlines() if line.strip()}
    undefined -= {"cs_rhs", "cs_jac", "cs_events", "cs_reset", "cs_outputs"}
    allowed = {"memcpy", "memset", "tanh", "exp", "log", "sqrt", "fabs", "pow", "atan",
               "atan2", "sin", "cos", "tan", "floor", "ceil", "fmin", "fmax", "copysign",
               "cosh", "sinh", "expm1", "log1p", "hypot", "fmod", "asinh", "acosh", "atanh"}
    assert undefined <= allowed, undefined - allowed


def test_the_fixed_step_fmu_takes_the_kernels_steps(rt_1khz):
    """The co-simulation FMU beside the library passes FMPy's checker and, driven by FMPy
    at 1 ms communication steps, follows the kernel's own run (same ROS2 steps, same
    events at the steps' ends, inputs held over a step)."""
    fmpy = pytest.importorskip("fmpy", reason="FMPy (the dev extra) runs the exported FMUs")
    from fmpy.validation import validate_fmu

    from clutchsim.fmu import input_table
    path = rt_1khz.out / "clutchsim_rt.fmu"
    assert validate_fmu(str(path)) == []
    md = fmpy.read_model_description(str(path))
    assert float(md.defaultExperiment.stepSize) == 1e-3
    sc = resolve_scenario(EXAMPLES / "launch.toml", None)
    names = ["omega_engine", "T_clutch"]
    f = fmpy.simulate_fmu(str(path), fmi_type="CoSimulation", output_interval=1e-3,
                          output=names, input=input_table(sc, dt=1e-3,
                                                          names=list(rt_1khz.inputs)))
    rt = run_realtime(RealtimeKernel(rt_1khz.out), sc)
    w = np.interp(rt.t, f["time"], f["omega_engine"])
    assert np.max(np.abs(w - rt["omega_engine"])) * 30 / math.pi < 0.05     # rpm


def test_without_a_c_compiler_the_cli_says_so_before_any_work(tmp_path, capsys, monkeypatch):
    monkeypatch.delenv("CC", raising=False)
    monkeypatch.setenv("PATH", str(tmp_path / "empty"))
    code = main(["rt", str(EXAMPLES / "launch.toml"), "--out", str(tmp_path / "rt")])
    err = capsys.readouterr().err
    assert code == 2, err
    assert "no C compiler found" in err and "Traceback" not in err
    assert not (tmp_path / "rt").exists()
