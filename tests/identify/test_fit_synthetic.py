"""fit() recovers known parameters from synthetic records with noise, deterministically."""

from __future__ import annotations

import numpy as np
import pytest
from _identify_helpers import synthetic_force_record, synthetic_velocity_record

from clutchsim.friction import make_model
from clutchsim.identify import FitOptions, FitProblem, fit

T = np.linspace(0.0, 2.0, 2001)
V = 0.05 * np.sin(2 * np.pi * T) * (1 - np.exp(-T / 0.1))


def _close(result, truth, rel):
    for name, tol in rel.items():
        got, want = result.parameters[name], truth[name]
        assert abs(got - want) <= tol * abs(want), f"{name}: fitted {got:.6g}, true {want:.6g}"


def test_lugre_velocity_drive_recovers_parameters():
    truth = {"F_c": 1.0, "F_s": 1.5, "v_s": 1e-2, "sigma0": 1e4, "sigma1": 50.0, "sigma2": 5.0}
    data = synthetic_velocity_record(make_model("lugre", **truth), T, V, noise=0.01, seed=1)
    start = make_model("lugre", **{**truth, "F_c": 0.7, "F_s": 1.2, "sigma0": 3e3,
                                   "sigma2": 10.0})
    res = fit(start, data, FitProblem(input="v", output="F", plant="rig-velocity",
              params=["F_c", "F_s", "sigma0", "sigma2"]))
    _close(res, truth, {"F_c": 0.02, "F_s": 0.03, "sigma0": 0.1, "sigma2": 0.1})
    assert res.nrmse_fit < 0.02 and res.r2_fit > 0.999
    assert set(res.stderr) == {"F_c", "F_s", "sigma0", "sigma2"}
    assert all(np.isfinite(v) and v > 0 for v in res.stderr.values())
    # the cost history is the running minimum: never increases
    assert np.all(np.diff(res.cost_history) <= 0)


def test_coulomb_viscous_force_drive_recovers_parameters_within_stderr():
    t = np.linspace(0.0, 3.0, 3001)
    f = 1.6 * np.sin(2 * np.pi * 0.5 * t)
    truth = {"F_c": 1.0, "v_t": 1e-3, "sigma2": 0.4}
    data = synthetic_force_record(make_model("tanh", **truth), t, f, noise=1e-5, seed=2)
    res = fit(make_model("tanh", **{**truth, "F_c": 0.6, "sigma2": 1.0}), data,
              FitProblem(input="f", output="x", params=["F_c", "sigma2"], plant="rig-force"))
    _close(res, truth, {"F_c": 0.005, "sigma2": 0.02})
    for name in ("F_c", "sigma2"):
        assert abs(res.parameters[name] - truth[name]) < 6 * res.stderr[name]


def test_model6_velocity_drive_recovers_parameters():
    truth = {"T_stat": 1.5, "k_din": 2 / 3, "phi0": 1.5e-5, "omega0": 1e-2, "k_v": 2.0}
    data = synthetic_velocity_record(make_model("mykhailevych2020", **truth), T, V,
                                     noise=0.01, seed=3)
    start = make_model("mykhailevych2020", **{**truth, "T_stat": 1.2, "k_din": 0.8,
                                              "phi0": 4e-5, "k_v": 4.0})
    res = fit(start, data, FitProblem(input="v", output="F", plant="rig-velocity",
              params=["T_stat", "k_din", "phi0", "k_v"], bounds={"k_din": (0.1, 1.0)}))
    _close(res, truth, {"T_stat": 0.03, "k_din": 0.03, "phi0": 0.15, "k_v": 0.1})


def test_fit_is_deterministic_for_a_seed_and_uses_validation():
    truth = {"F_c": 1.0, "v_t": 1e-2, "sigma2": 3.0}
    model = make_model("tanh", **truth)
    data = synthetic_velocity_record(model, T, V, noise=0.02, seed=4)
    other = synthetic_velocity_record(model, T, 0.5 * V, noise=0.02, seed=5)
    problem = FitProblem(input="v", output="F", plant="rig-velocity",
                         params=["F_c", "sigma2"], t_span=(0.0, 1.0))
    options = FitOptions(starts=3, seed=7)
    a = fit(model.with_(F_c=2.0), data, problem, options, validate=other)
    b = fit(model.with_(F_c=2.0), data, problem, options, validate=other)
    assert dict(a.parameters) == dict(b.parameters)
    assert [s["start"] for s in a.starts] == [s["start"] for s in b.starts]
    assert len(a.starts) == 3 and a.starts[0]["start"]["F_c"] == pytest.approx(2.0)
    # the validation record is twice as long as the fitted window: simulated to its end
    assert a.validation[0].t[-1] == pytest.approx(2.0)
    assert a.nrmse_validation is not None and a.nrmse_validation < 0.05
    doc = a.summary()
    assert set(doc) == {"model", "parameters", "stderr", "nrmse_fit", "nrmse_validation",
                        "nrmse_pooled", "records", "validation", "at_bound", "unidentified",
                        "warnings", "notes"}
    assert doc["at_bound"] == [] and doc["unidentified"] == [] and doc["warnings"] == []


def test_tuple_elements_and_plant_offset_can_be_fitted():
    base = make_model("gms", k=(3e4, 1e4), alpha=(0.5, 0.5), C=100.0, F_c=1.0, F_s=1.2,
                      v_s=1e-2, sigma1=0.0, sigma2=1.0)
    data = synthetic_velocity_record(base, T, V, noise=0.005, seed=6)
    data = data.with_column("F", data["F"] + 0.2)
    res = fit(base.with_(k=(1e4, 1e4)), data, FitProblem(input="v", output="F",
              plant="rig-velocity", params=["k[0]", "offset"], bounds={"offset": (-1.0, 1.0)}))
    assert res.parameters["k[0]"] == pytest.approx(3e4, rel=0.1)
    assert res.parameters["offset"] == pytest.approx(0.2, abs=0.01)
    assert res.model.k[0] == pytest.approx(res.parameters["k[0]"])


@pytest.mark.parametrize("kw, message", [
    ({"params": ["sigma3"]}, (r"lugre has no parameter 'sigma3' \(did you mean 'sigma2'\?\)"
                              r"; model parameters: F_c, F_s")),
    ({"params": ["F_c"], "bounds": {"F_c": (2.0, 1.0)}}, (r"bounds for 'F_c': lo = 2 must "
                                                          r"be < hi = 1")),
    ({"params": ["F_c"], "bounds": {"F_c": (1.0, 1.0)}}, "must be < hi"),
    ({"params": ["F_c"], "bounds": {"F_s": (1.0, 2.0)}}, ("bounds given for 'F_s', which "
                                                          "is not fitted")),
    ({"params": ["F_c"], "fixed": {"F_c": 1.0}}, "both fitted and fixed"),
    ({"params": ["F_c"], "starts": 0}, "starts = 0 must be >= 1"),
    ({"params": []}, "at least one parameter"),
    ({"params": ["F_c"], "plant": "rig-speed"}, r"plant = 'rig-speed' is not known"),
    ({"params": ["F_c"], "input": "vel"}, r"no column 'vel'"),
])
def test_bad_arguments_raise_clear_errors(kw, message):
    data = {"t": T[:50], "v": V[:50], "F": np.sin(T[:50])}
    args = {"input": "v", "output": "F", "plant": "rig-velocity"}
    args.update(kw)
    starts = args.pop("starts", 1)
    with pytest.raises(ValueError, match=message):
        fit(make_model("lugre"), data, FitProblem(**args), FitOptions(starts=starts))


def test_parameter_starting_at_zero_needs_bounds():
    data = {"t": T[:50], "v": V[:50], "F": np.sin(T[:50])}
    with pytest.raises(ValueError, match=r"'sigma2' starts at 0: give its bounds"):
        fit(make_model("tanh", sigma2=0.0), data, FitProblem(input="v", output="F",
            plant="rig-velocity", params=["sigma2"]))


def test_undetermined_parameters_have_no_standard_error():
    from clutchsim.identify.fit import _standard_errors
    from clutchsim.identify.parameters import ParameterSpace

    space = ParameterSpace.build(["a", "b", "c"], {"a": 1.0, "b": 1.0, "c": 1e6}, None, {})
    x = space.to_scaled(np.array([1.0, 1.0, 1e6]))
    rng = np.random.default_rng(0)
    jac = np.column_stack([rng.normal(size=200), np.zeros(200), 1e-3 * rng.normal(size=200)])
    se = _standard_errors(jac, 1.0, 0.01 * rng.normal(size=200), space, x, ["a", "b", "c"])
    assert se["b"] is None
    assert se["a"] > 0 and se["c"] > 0
    # a log-scaled parameter: stderr scales with its value (ln 10 · value · sigma_x)
    assert se["c"] / se["a"] > 1e5


@pytest.mark.parametrize("name, truth, start, params, rel", [
    ("dahl", {"F_c": 1.0, "sigma0": 1e4}, {"F_c": 0.6, "sigma0": 3e3}, ["F_c", "sigma0"],
     {"F_c": 0.02, "sigma0": 0.1}),
    ("elastoplastic",
     {"F_c": 1.0, "F_s": 1.5, "v_s": 1e-2, "sigma0": 1e4, "sigma1": 50.0, "sigma2": 5.0,
      "z_ba": 0.5e-4},
     {"F_c": 0.7, "F_s": 1.2, "sigma0": 3e3, "z_ba": 0.5e-4}, ["F_c", "F_s", "sigma0"],
     {"F_c": 0.02, "F_s": 0.03, "sigma0": 0.1}),
])
def test_presliding_models_recover_parameters(name, truth, start, params, rel):
    """Dahl and elasto-plastic (fitted to the BRFD and micro-tribometer records) are
    identifiable from a noisy imposed-velocity record too."""
    data = synthetic_velocity_record(make_model(name, **truth), T, V, noise=0.01, seed=3)
    res = fit(make_model(name, **{**truth, **start}), data, FitProblem(input="v", output="F",
              plant="rig-velocity", params=params))
    _close(res, truth, rel)
    assert res.nrmse_fit < 0.02


def test_values_at_a_bound_and_unidentifiable_parameters_are_flagged():
    # data without a Stribeck drop (F_s = F_c) and without viscous friction (sigma2 = 0)
    truth = {"F_c": 1.0, "F_s": 1.0, "v_s": 1e-3, "sigma2": 0.0}
    data = synthetic_velocity_record(make_model("stribeck", **truth), T, V, noise=1e-3,
                                     seed=6)
    start = make_model("stribeck", **{**truth, "F_s": 1.3, "v_s": 5e-3, "sigma2": 0.3})
    res = fit(start, data, FitProblem(input="v", output="F", plant="rig-velocity",
              params=["F_c", "F_s", "v_s", "sigma2"], bounds={"sigma2": (0.0, 1.0), "v_s":
              (1e-4, 1e-1)}))
    p = res.parameters
    assert p["F_c"] == pytest.approx(1.0, rel=1e-2)
    assert abs(p["F_s"] - p["F_c"]) <= 1e-3 * p["F_c"]           # no drop found
    assert p["sigma2"] <= 1e-3                                   # pushed onto its bound 0
    assert "sigma2" in res.at_bound and "F_c" not in res.at_bound
    assert "v_s" in res.unidentified and "F_c" not in res.unidentified
    doc = res.summary()
    assert doc["at_bound"] == list(res.at_bound) and doc["unidentified"] == list(res.unidentified)
    assert any(w.startswith("sigma2 = ") and "lower bound" in w for w in doc["warnings"])
    assert any(w.startswith("v_s cannot be identified") for w in doc["warnings"])
