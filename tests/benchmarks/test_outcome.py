"""Benchmark metrics carry the machine-readable outcome of their runs (real runs)."""

from __future__ import annotations

import dataclasses

from clutchsim.benchmarks._base import STIFF_OPTIONS
from clutchsim.benchmarks.phenomena import FAILED, _failed_or_none
from clutchsim.benchmarks.presliding import run_presliding


def test_presliding_metrics_carry_outcome_and_a_budget_failure_is_named():
    ok = run_presliding(["lugre"])
    m = ok.metrics_json()["results"]["lugre"]
    assert m["outcome"] == "completed" and m["warnings"] == []
    assert m["loop_closes"] is True and _failed_or_none(m) is None
    # a step budget far too small: the run ends on its budget, not with a metric
    tight = dataclasses.replace(STIFF_OPTIONS, max_steps=50)
    bad = run_presliding(["lugre"], options=tight)
    m = bad.metrics_json()["results"]["lugre"]
    assert bad.runs["lugre"]["presliding"].outcome == "budget"
    assert m["outcome"] == "budget" and m["status"] == "failed" and "loop_closes" not in m
    assert _failed_or_none(m).status == FAILED
    # the decision does not read the message: a misleading message changes nothing
    assert _failed_or_none({**m, "message": "completed fine"}).status == FAILED
    assert _failed_or_none({"outcome": "completed", "message": "failed"}) is None
