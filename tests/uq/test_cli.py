"""``clutchsim uq`` end to end on the default launch: the JSON document, the files, the
counts against the results table, resume, Sobol' through the sweep, and bad input (exit 2
before anything runs)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from clutchsim.cli import main
from clutchsim.studies.sweeps import read_results

GRADE = "vehicle.grade=uniform(0,8)"     # about half the launches stall the engine
MASS = "vehicle.mass=tol(±60,cpk=1)"     # normal about the scenario's 1300 kg, sigma 20


def test_monte_carlo_study_of_stalls_with_json_and_resume(tmp_path, capsys):
    out = tmp_path / "mc"
    argv = ["uq", "--vary", GRADE, "--vary", MASS, "--samples", "120", "--seed", "4",
            "--out", str(out), "--json", "-q"]
    assert main(argv) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["samples"] == 120 and doc["method"] == "mc"
    assert doc["inputs"] == {"vehicle.grade": "uniform(0,8)",
                             "vehicle.mass": "tol(±60,cpk=1)"}
    t = read_results(out)
    assert len(t) == 120
    assert t["vehicle.mass"].mean() == pytest.approx(1300, abs=8)
    assert t["vehicle.mass"].std() == pytest.approx(20, rel=0.25)
    # probabilities are the counts of the table's outcomes, with exact intervals
    for name in ("completed", "stalled", "chatter", "invariant_violated"):
        k = int((t["outcome"] == name).sum())
        p = doc["probabilities"][name]
        assert p["count"] == k and p["p"] == k / 120
        assert p["ci95"][0] <= k / 120 <= p["ci95"][1]
    assert 0.2 < doc["probabilities"]["stalled"]["p"] < 0.8
    # a stalled launch is on a steeper grade than a completed one, on average
    assert t["vehicle.grade"][t["outcome"] == "stalled"].min() > \
        t["vehicle.grade"][t["outcome"] == "completed"].min()
    no_lock = int(t["lockup_time_s"].isna().sum())
    assert doc["probabilities"]["no_lockup"]["count"] == no_lock
    lock = t["lockup_time_s"].dropna().to_numpy()
    q = doc["quantiles"]["lockup_time_s"]
    assert [q["p05"], q["p50"], q["p95"]] == pytest.approx(
        np.quantile(lock, [0.05, 0.5, 0.95]).tolist())
    assert set(doc) >= {"samples", "probabilities", "quantiles"} and "sobol" not in doc
    files = {p.name for p in out.iterdir()}
    assert {"uq.json", "probabilities.csv", "quantiles.csv", "uq_probabilities.png",
            "uq_distributions.png", "uq_convergence.png", "command.txt", "report.html"} <= files
    assert "clutchsim uq report: mc, 120 runs" in (out / "report.html").read_text()
    # the same command resumes: nothing runs again, the same answers
    assert main([*argv, "--no-plots"]) == 0
    again = json.loads(capsys.readouterr().out)
    assert again["chunks_resumed"] > 0 and again["probabilities"] == doc["probabilities"]


def test_sobol_study_through_the_cli(tmp_path, capsys):
    out = tmp_path / "sobol"
    assert main(["uq", "--method", "sobol", "--vary", "vehicle.grade=uniform(0,1.5)",
                 "--vary", "vehicle.mass=uniform(1100,1500)", "--samples", "32", "--seed",
                 "1", "--out", str(out), "--json", "-q", "--no-plots"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["samples"] == 32 * 4 and doc["probabilities"]["completed"]["p"] == 1.0
    s = doc["sobol"]["lockup_time_s"]
    assert set(s) == {"vehicle.grade", "vehicle.mass"}
    for v in s.values():
        assert set(v) == {"S1", "S1_ci95", "ST", "ST_ci95"}
        assert v["ST_ci95"][0] <= v["ST"] <= v["ST_ci95"][1]
    # both inputs load the launch: each explains part of the lock-up time
    assert s["vehicle.mass"]["ST"] > 0.05 and s["vehicle.grade"]["ST"] > 0.05
    assert (out / "sensitivity.csv").exists()


@pytest.mark.parametrize("args, words", [
    (["--vary", "vehicle.mas=normal(1400,50)"], "did you mean 'mass'"),
    (["--vary", "vehicle.mass=normal(1400,0)"],
     "--vary vehicle.mass=normal(1400,0): needs SIGMA > 0 (got 0)"),
    (["--vary", "vehicle.grade=uniform(8,0)"], "needs A < B (got A = 8, B = 0)"),
    (["--vary", "vehicle.mass=normal(1400,50)", "--vary", "vehicle.grade=uniform(0,8)",
      "--vary", "inertia[0].J=uniform(0.1,0.2)", "--corr", "vehicle.mass,vehicle.grade=0.9",
      "--corr", "vehicle.grade,inertia[0].J=0.9", "--corr",
      "vehicle.mass,inertia[0].J=-0.9"], "is not positive definite"),
    (["--vary", "vehicle.mass=normal(1400,50)", "--max-runs", "99"],
     "1,000 runs is above the limit of 99"),
    (["--vary", "vehicle.mass=tol(±5,cpk=1.33)", "--vary", "nothing.here=tol(±1,cpk=1)"],
     "no value at 'nothing.here'"),
])
def test_bad_input_exits_2_before_anything_runs(tmp_path, capsys, args, words):
    out = tmp_path / "bad"
    assert main(["uq", *args, "--out", str(out), "-q"]) == 2
    err = capsys.readouterr().err
    assert words in err and err.count("\n") == 1 and "Traceback" not in err
    assert not (out / "chunks").exists()
