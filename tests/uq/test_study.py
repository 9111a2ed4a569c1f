"""The study engine through a stub runner: Sobol' indices against analytic ones (Ishigami,
a linear model), Morris on a linear model, probabilities against counting, interval
coverage, and the checks that refuse a study before anything runs."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy import stats

from clutchsim.studies.uq import UQInputError, clopper_pearson, study

PI = math.pi
UNIFORM_PI = f"uniform({-PI!r},{PI!r})"


def stub(f):
    """An evaluate() of the study: ``f(x)`` on the design (runs x inputs); a run whose
    value is NaN is ``stalled``, the others ``completed``."""
    calls = []

    def evaluate(design):
        calls.append(design.n)
        x = np.column_stack([design.columns[k] for k in design.keys])
        y = f(x)
        codes = np.where(np.isfinite(y), 0, 1).astype(np.int32)
        return {"outcome": (codes, ["completed", "stalled"]), "y": y}, {}
    evaluate.calls = calls
    return evaluate


def ishigami(x, a=7.0, b=0.1):
    return np.sin(x[:, 0]) + a * np.sin(x[:, 1]) ** 2 + b * x[:, 2] ** 4 * np.sin(x[:, 0])


def ishigami_indices(a=7.0, b=0.1):
    v1 = 0.5 * (1 + b * PI**4 / 5) ** 2
    v2 = a**2 / 8
    v13 = b**2 * PI**8 * (1 / 18 - 1 / 50)
    v = v1 + v2 + v13
    return (v1 / v, v2 / v, 0.0), ((v1 + v13) / v, v2 / v, v13 / v)


def test_sobol_indices_of_the_ishigami_function():
    ev = stub(ishigami)
    r, _ = study({k: UNIFORM_PI for k in ("x1", "x2", "x3")}, ev, method="sobol",
                 samples=2048, seed=3)
    assert ev.calls == [2048 * 5] and r.samples == 2048 * 5
    s1, st = ishigami_indices()
    for i, k in enumerate(("x1", "x2", "x3")):
        got = r.sobol["y"][k]
        assert got["S1"] == pytest.approx(s1[i], abs=0.03)
        assert got["ST"] == pytest.approx(st[i], abs=0.03)
        # the bootstrap intervals hold the exact values (95 % each; 6 of them)
        lo, hi = got["ST_ci95"]
        assert lo - 0.01 <= st[i] <= hi + 0.01
        lo, hi = got["S1_ci95"]
        assert lo - 0.01 <= s1[i] <= hi + 0.01
    # the convergence of each index ends at the reported value
    c = r.convergence["ST(y; x1)"]
    assert c["n"][-1] == r.samples and c["value"][-1] == r.sobol["y"]["x1"]["ST"]


def test_sobol_indices_of_a_linear_model_with_normal_and_uniform_inputs():
    a = np.array([1.0, 2.0, 0.5, 0.0])
    inputs = {"n1": "normal(0,1)", "n2": "normal(3,0.5)", "u": "uniform(0,6)",
              "dead": "uniform(0,1)"}
    var = a**2 * np.array([1.0, 0.25, 3.0, 1 / 12])
    r, _ = study(inputs, stub(lambda x: x @ a), method="sobol", samples=4096, seed=1)
    for k, expect in zip(inputs, var / var.sum()):
        assert r.sobol["y"][k]["S1"] == pytest.approx(expect, abs=0.02)
        assert r.sobol["y"][k]["ST"] == pytest.approx(expect, abs=0.02)


def test_morris_of_a_linear_model_is_exact():
    a = np.array([2.0, -3.0, 0.0])
    r, _ = study({"p": "uniform(0,4)", "q": "uniform(10,12)", "z": "uniform(0,1)"},
                 stub(lambda x: x @ a), method="morris", samples=10, seed=2)
    assert r.samples == 10 * 4
    # a step of one level of 4 is a quarter of the range; SALib's unit is 1/(4 - 1)
    for k, ai, width in (("p", 2.0, 4.0), ("q", -3.0, 2.0), ("z", 0.0, 1.0)):
        got = r.morris["y"][k]
        assert got["mu_star"] == pytest.approx(abs(ai) * width * 3 / 4, abs=1e-9)
        assert got["mu"] == pytest.approx(ai * width * 3 / 4, abs=1e-9)
        assert got["sigma"] == pytest.approx(0.0, abs=1e-9)


def test_probabilities_and_quantiles_are_plain_counting_of_the_same_runs():
    # stalls where x0 + x1 > 1.4 (NaN), a threshold event on y
    def f(x):
        return np.where(x[:, 0] + x[:, 1] > 1.4, np.nan, x[:, 0] * 10)
    seen = {}

    def evaluate(design):
        cols, info = stub(f)(design)
        seen.update(cols=cols)
        return cols, info
    r, _ = study({"a": "uniform(0,1)", "b": "triangular(0,0.5,1)"}, evaluate,
                    method="lhs", samples=777, seed=5)
    y = seen["cols"]["y"]
    stalled = int(np.isnan(y).sum())
    assert r.probabilities["stalled"]["count"] == stalled
    assert r.probabilities["stalled"]["p"] == stalled / 777
    assert r.probabilities["completed"]["p"] == 1 - stalled / 777
    assert r.probabilities["chatter"] == {"p": 0.0, "ci95": (0.0, pytest.approx(
        1 - 0.025 ** (1 / 777))), "count": 0}
    ok = y[np.isfinite(y)]
    q = r.quantiles["y"]
    assert (q["p05"], q["p50"], q["p95"]) == tuple(np.quantile(ok, [0.05, 0.5, 0.95]))
    assert q["n"] == ok.size
    lo, hi = r.probabilities["stalled"]["ci95"]
    ref = stats.binomtest(stalled, 777).proportion_ci(0.95, method="exact")
    assert (lo, hi) == (pytest.approx(ref.low), pytest.approx(ref.high))
    conv = r.convergence["P(stalled)"]
    assert conv["n"][-1] == 777 and conv["value"][-1] == stalled / 777


def test_clopper_pearson_covers_a_known_bernoulli_probability():
    rng = np.random.default_rng(0)
    for p, n in ((0.3, 40), (0.02, 200), (0.5, 15)):
        k = rng.binomial(n, p, size=4000)
        lo, hi = clopper_pearson(k, n)
        coverage = np.mean((lo <= p) & (p <= hi))
        # exact intervals: at least 95 % for every p (conservative, so below ~99 %)
        assert 0.945 <= coverage <= 0.995, (p, n, coverage)


def test_the_result_is_immutable():
    r, _ = study({"a": "uniform(0,1)"}, stub(lambda x: x[:, 0]), samples=20, seed=0)
    with pytest.raises(dataclasses.FrozenInstanceError):
        r.samples = 3
    with pytest.raises(TypeError):
        r.probabilities["stalled"] = {}
    assert r.to_dict()["probabilities"]["completed"]["ci95"][1] == 1.0


@pytest.mark.parametrize("kw, words", [
    ({"samples": 100, "method": "sobol"}, "power of 2 >= 8 (the base samples"),
    ({"samples": 64, "method": "sobol", "correlation": ["a,b=0.3"]}, "independent inputs"),
    ({"samples": 10, "method": "grid"}, "--method 'grid': not one of"),
    ({"samples": 0}, "--samples 0: must be an integer >= 1"),
    ({"samples": 10_000, "max_runs": 9_999}, "10,000 runs is above the limit of 9,999"),
    ({"samples": 2048, "method": "sobol", "max_runs": 8000},
     "8,192 runs is above the limit of 8,000"),
])
def test_bad_studies_are_refused_before_anything_runs(kw, words):
    ev = stub(lambda x: x[:, 0])
    with pytest.raises(ValueError) as e:
        study({"a": "uniform(0,1)", "b": "normal(0,1)"}, ev, seed=1, **kw)
    assert words in str(e.value)
    assert ev.calls == []
    assert isinstance(e.value, UQInputError) or "--max-runs" in str(e.value)
