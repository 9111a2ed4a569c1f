"""Uncertain inputs: the DIST syntax, the moments of each distribution, tolerances,
correlations through the Gaussian copula, and the errors for bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import stats

from clutchsim.studies.uq import (
    UQInputError,
    correlation_matrix,
    make_samples,
    parse_correlation,
    parse_dist,
    parse_inputs,
)


@pytest.mark.parametrize("text, mean, std", [
    ("uniform(2,6)", 4.0, 4 / math.sqrt(12)),
    ("normal(1500, 50)", 1500.0, 50.0),
    ("lognormal(1e-3,0.1)", 1e-3 * math.exp(0.005), 1e-3 * math.sqrt((math.exp(0.01) - 1)
                                                                   * math.exp(0.01))),
    ("triangular(0,1,4)", 5 / 3, math.sqrt((0 + 1 + 16 - 0 - 0 - 4) / 18)),
    ("discrete(1,2,3,4)", 2.5, math.sqrt(1.25)),
    ("discrete(1:1,3:3)", 2.5, math.sqrt(0.75)),
    ("tol(10±0.3,cpk=1)", 10.0, 0.1),
    ("tol(10+-0.4,cpk=1.33)", 10.0, 0.4 / 3.99),
])
def test_moments_of_each_distribution_analytic_and_sampled(text, mean, std):
    d = parse_dist(text, "x")
    assert d.mean() == pytest.approx(mean, rel=1e-9)
    assert d.std() == pytest.approx(std, rel=1e-9)
    u = make_samples("lhs", 8000, 3, 1)[:, 0]
    v = d.ppf(u)
    assert v.mean() == pytest.approx(mean, rel=2e-3, abs=1e-3 * std)
    assert v.std() == pytest.approx(std, rel=2e-2)


def test_truncated_normal_stays_inside_and_matches_scipy():
    d = parse_dist("tnormal(0,1,-0.5,2)", "x")
    v = d.ppf(make_samples("mc", 5000, 1, 1)[:, 0])
    assert v.min() >= -0.5 and v.max() <= 2.0
    assert d.mean() == pytest.approx(stats.truncnorm(-0.5, 2).mean())


def test_tolerance_takes_the_nominal_from_the_scenario():
    d = parse_dist("tol(±20,cpk=1.33)", "vehicle.mass", nominal=lambda key: 1400.0)
    assert d.params == (1400.0, pytest.approx(20 / 3.99))
    # Cpk = 1.33, centred: ~66 ppm outside the limits
    out = 2 * stats.norm.sf(3 * 1.33)
    assert out == pytest.approx(6.6e-5, rel=0.05)


def test_discrete_draws_each_value_with_its_weight():
    d = parse_dist("discrete(5:0.2, 1:0.5, 3:0.3)", "x")
    v = d.ppf(make_samples("mc", 20000, 7, 1)[:, 0])
    for value, w in ((1, 0.5), (3, 0.3), (5, 0.2)):
        assert np.mean(v == value) == pytest.approx(w, abs=0.015)


@pytest.mark.parametrize("text, words", [
    ("normal(1500,0)", "SIGMA > 0 (got 0)"),
    ("normal(1500,-5)", "SIGMA > 0 (got -5)"),
    ("uniform(3,1)", "A < B (got A = 3, B = 1)"),
    ("tnormal(0,1,2,1)", "LO < HI"),
    ("triangular(0,5,4)", "LO <= MODE <= HI"),
    ("lognormal(-1,0.1)", "MEDIAN > 0"),
    ("normel(1,2)", "did you mean 'normal'"),
    ("normal(1)", "takes 2 numbers"),
    ("normal(1,__import__('os'))", "is not a number"),
    ("uniform(0,inf)", "is not a number"),
    ("discrete(1:0.5,2)", "weight to every value"),
    ("discrete(1:0,2:1)", "weights > 0"),
    ("tol(±0.2)", "cpk=C"),
    ("tol(±-0.2,cpk=1)", "T > 0 (got -0.2)"),
    ("tol(±x,cpk=1)", "is not ±T"),
    ("tol(±0.2,cpk=0)", "cpk > 0"),
    ("1500", "expected NAME(ARGS)"),
])
def test_bad_distributions_name_key_value_and_rule(text, words):
    with pytest.raises(UQInputError) as e:
        parse_dist(text, "vehicle.mass")
    assert f"--vary vehicle.mass={text}" in str(e.value) and words in str(e.value)


def test_a_key_given_twice_is_refused():
    with pytest.raises(UQInputError, match="given twice"):
        parse_inputs(["a=normal(0,1)", "a=normal(0,2)"])


@settings(max_examples=10, deadline=None)
@given(rho=st.floats(-0.9, 0.9))
def test_the_copula_gives_the_rank_correlation_asked_for(rho):
    c = correlation_matrix(["a", "b"], parse_correlation([f"a,b={rho!r}"]))
    u = make_samples("mc", 4000, 11, 2, c)
    r = stats.spearmanr(u[:, 0], u[:, 1]).statistic
    assert r == pytest.approx(rho, abs=0.05)
    # the marginals stay uniform (the copula only couples them)
    assert stats.kstest(u[:, 0], "uniform").pvalue > 1e-3


def test_a_correlation_matrix_that_is_not_positive_definite_is_refused():
    pairs = parse_correlation(["a,b=0.9", "b,c=0.9", "a,c=-0.9"])
    with pytest.raises(UQInputError, match="not positive definite") as e:
        correlation_matrix(["a", "b", "c"], pairs)
    assert "a,c=-0.9" in str(e.value) and "smallest eigenvalue" in str(e.value)
    with pytest.raises(UQInputError, match="'d' is not a varied key"):
        correlation_matrix(["a", "b"], parse_correlation(["a,d=0.1"]))
    with pytest.raises(UQInputError, match=r"-1 <= RHO <= 1 \(got 1.5\)"):
        parse_correlation(["a,b=1.5"])


def test_latin_hypercube_puts_one_point_in_each_stratum():
    u = make_samples("lhs", 50, 4, 3)
    for j in range(3):
        assert sorted(np.floor(u[:, j] * 50).astype(int)) == list(range(50))


def test_the_same_seed_gives_the_same_samples():
    for method, n in (("mc", 30), ("lhs", 30), ("sobol", 16), ("morris", 4)):
        a, b = make_samples(method, n, 9, 3), make_samples(method, n, 9, 3)
        assert np.array_equal(a, b) and 0 < a.min() and a.max() < 1
        assert not np.array_equal(a, make_samples(method, n, 10, 3))
