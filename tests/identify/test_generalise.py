"""Identification that generalises: several records, load-dependent scaling, declared inputs,
derived columns, initial states for validation (synthetic records)."""

from __future__ import annotations

import numpy as np
import pytest
from _identify_helpers import synthetic_velocity_record

from clutchsim.data import Measurement
from clutchsim.data.column_expr import evaluate_column
from clutchsim.friction import make_model
from clutchsim.identify import FitOptions, FitProblem, InputSpec, evaluate, fit

T = np.linspace(0.0, 2.0, 1001)
V = 0.05 * np.sin(2 * np.pi * T)
TRUTH = {"F_c": 2.0, "v_t": 1e-2, "sigma2": 3.0}
LAMBDA = 0.6            # true load-proportional fraction: F = F_c·(0.4 + 0.6·s)


def _record(s_level, offset=0.0, seed=0):
    cap = (1.0 - LAMBDA) + LAMBDA * s_level
    rec = synthetic_velocity_record(make_model("tanh", **TRUTH), T, V, noise=0.005, seed=seed,
                                    scale=cap)
    return Measurement.from_arrays(T, source=f"load {s_level:g}", v=rec["v"],
                                   F=rec["F"] + offset, s=np.full(T.size, s_level))


def test_joint_fit_separates_constant_and_load_proportional_friction():
    """Records at s = 0.5 and 1.5 identify F_0 = (1-λ)·F_c and μ·N_ref = λ·F_c; per-record
    offsets are fitted once per record; validation at s = 1 is predicted from them."""
    recs = [_record(0.5, offset=0.2, seed=1), _record(1.5, offset=-0.1, seed=2)]
    start = make_model("tanh", **{**TRUTH, "F_c": 1.0, "sigma2": 1.0})
    res = fit(start, recs, FitProblem(input="v", output="F", plant="rig-velocity",
              plant_options={"scale": "s", "load_fraction": 0.9}, params=["F_c", "sigma2",
              "load_fraction"], per_record=["offset"], bounds={"offset": (-1.0, 1.0)}),
              validate=[_record(1.0, offset=0.05, seed=3)])
    p = res.parameters
    assert p["F_c"] == pytest.approx(2.0, rel=0.01)
    assert p["load_fraction"] == pytest.approx(LAMBDA, abs=0.01)
    assert p["offset@1"] == pytest.approx(0.2, abs=0.01)
    assert p["offset@2"] == pytest.approx(-0.1, abs=0.01)
    assert len(res.records) == 2 and [r.source for r in res.records] == ["load 0.5", "load 1.5"]
    assert all(r.nrmse < 0.01 for r in res.records)
    assert res.nrmse_pooled == pytest.approx(np.sqrt(np.mean([r.nrmse ** 2
                                                              for r in res.records])))
    # validation uses the mean of the per-record offsets (0.05): its error stays small
    assert res.validation[0].nrmse < 0.02
    doc = res.summary()
    assert [r["source"] for r in doc["records"]] == ["load 0.5", "load 1.5"]
    assert doc["validation"][0]["source"] == "load 1"


def test_one_record_at_one_load_cannot_separate_the_two_parts():
    """At one constant load only the capacity (1 − λ + λ·1.5)·F is determined: with every
    friction level fitted, λ is flagged unidentified (no standard error)."""
    rec = _record(1.5, seed=4)
    start = make_model("tanh", **{**TRUTH, "F_c": 1.0, "sigma2": 1.0})
    res = fit(start, rec, FitProblem(input="v", output="F", plant="rig-velocity",
              plant_options={"scale": "s", "load_fraction": 0.9}, params=["F_c", "sigma2",
              "load_fraction"], bounds={"F_c": (0.5, 10.0)}))
    p = res.parameters
    cap = 1 - p["load_fraction"] + 1.5 * p["load_fraction"]
    assert p["F_c"] * cap == pytest.approx(2.0 * (0.4 + 0.6 * 1.5), rel=0.01)
    assert p["sigma2"] * cap == pytest.approx(3.0 * (0.4 + 0.6 * 1.5), rel=0.02)
    assert "load_fraction" in res.unidentified and res.stderr["load_fraction"] is None


def test_declared_force_input_and_a_record_that_lacks_it():
    """A measured fixture force (2·Fx) enters the simulated force; a validation record
    without the column takes it as zero and the result says so."""
    rec = synthetic_velocity_record(make_model("tanh", **TRUTH), T, V, noise=0.005, seed=5)
    fx = 0.3 * np.cos(2 * np.pi * 3 * T)
    data = Measurement.from_arrays(T, source="with Fx", v=rec["v"], F=rec["F"] + 2 * fx, Fx=fx)
    other = Measurement.from_arrays(T, source="without Fx", v=rec["v"], F=rec["F"])
    inputs = [InputSpec("Fx", "force", gain=2.0, unit="N")]
    start = make_model("tanh", **{**TRUTH, "F_c": 1.0})
    res = fit(start, data, FitProblem(input="v", output="F", plant="rig-velocity",
              inputs=inputs, params=["F_c", "sigma2"]), validate=[other])
    assert res.parameters["F_c"] == pytest.approx(2.0, rel=0.01)
    assert res.nrmse_fit < 0.01 and res.validation[0].nrmse < 0.01
    assert any("without Fx" in n and "'Fx'" in n and "taken as 0" in n for n in res.notes)
    # without the declared input the same record is fitted much worse
    bare = evaluate(res.model, data, input="v", output="F", plant="rig-velocity")
    assert bare.nrmse > 10 * res.nrmse_fit
    with pytest.raises(ValueError, match=r"inputs: declared input column 'Fy' \(to force\) is "
                                         r"in none of the records \(fitting: with Fx; "
                                         r"validation: without Fx\); columns: F, Fx, v"):
        fit(start, data, FitProblem(input="v", output="F", plant="rig-velocity", params=["F_c"],
            inputs=[InputSpec("Fy", "force")]), validate=[other])
    with pytest.raises(ValueError, match="to = 'controller' is not available for plant "
                                         "'rig-velocity'"):
        evaluate(res.model, data, input="v", output="F", plant="rig-velocity",
                 inputs=[InputSpec("Fx", "controller")])


def test_validation_from_the_fit_end_state_and_warmup():
    """A LuGre record split in the middle of a loaded cycle: the second half simulated from
    rest starts with the wrong bristle state; from the fit's end state (or after a warm-up)
    it does not."""
    t = np.linspace(0.0, 4.0, 4001)
    v = 0.02 * np.sin(2 * np.pi * 0.5 * t)
    truth = make_model("lugre", F_c=1.0, F_s=1.3, v_s=5e-3, sigma0=1e3, sigma1=5.0,
                       sigma2=2.0)
    whole = synthetic_velocity_record(truth, t, v, noise=0.002, seed=6)
    first, second = whole.window(0.0, 1.5), whole.window(1.5, 4.0)
    problem = FitProblem(input="v", output="F", plant="rig-velocity", params=["F_c"])
    kw = {"validate": [second]}
    rest = fit(truth.with_(F_c=0.8), first, problem, **kw)
    end = fit(truth.with_(F_c=0.8), first, problem, validate_initial="fit-end", **kw)
    warm = fit(truth.with_(F_c=0.8), first, problem, validate_warmup=0.5, **kw)
    assert rest.parameters["F_c"] == pytest.approx(1.0, rel=0.01)
    assert end.validation[0].nrmse < 0.02 < rest.validation[0].nrmse
    assert warm.validation[0].nrmse < 0.02
    assert warm.validation[0].t[0] >= 2.0 - 1e-12        # the warm-up is not compared
    assert any("end of" in n for n in end.notes)
    given = fit(truth.with_(F_c=0.8), first, problem, validate_initial=[0.0], **kw)
    assert given.validation[0].nrmse == pytest.approx(rest.validation[0].nrmse, rel=1e-6)
    with pytest.raises(ValueError, match="validate_initial has 2 entries; lugre has 1 state"):
        fit(truth, first, problem, validate_initial=[0.0, 1.0], **kw)


def test_fit_end_continues_the_motion_of_a_force_driven_record():
    """Pure Coulomb friction (1 N) under a sine force of 3 N, split at t = 1.6 s while the
    mass slides back: "fit-end" hands over the whole state (x, v, mode), so the second half is
    predicted to the noise; from rest (v = 0, stuck) it is not.  A given friction state
    leaves the plant at its default start."""
    from _identify_helpers import synthetic_force_record
    t = np.linspace(0.0, 4.0, 4001)
    truth = make_model("coulomb-robust", F_c=1.0, F_s=1.0, sigma2=0.0)
    whole = synthetic_force_record(truth, t, 3.0 * np.sin(np.pi * t), noise=1e-5, seed=8)
    first, second = whole.window(0.0, 1.6), whole.window(1.6, 4.0)
    problem = FitProblem(input="f", output="x", plant="rig-force", params=["F_c"],
                         bounds={"F_c": (0.5, 2.0)})
    kw = {"validate": [second]}
    end = fit(truth.with_(F_c=0.8), first, problem, validate_initial="fit-end", **kw)
    rest = fit(truth.with_(F_c=0.8), first, problem, **kw)
    assert end.parameters["F_c"] == pytest.approx(1.0, rel=1e-3)
    assert end.validation[0].nrmse < 1e-3 and rest.validation[0].nrmse > 0.1
    note = next(n for n in end.notes if "end of" in n)
    assert "x = " in note and "v = -" in note and "mode = -1" in note   # sliding back
    with pytest.raises(ValueError, match=r"y0 has 2 entries; plant 'rig-force' with "
                                         r"coulomb-robust has 3 states \(x, v, mode\)"):
        from clutchsim.identify.plants import PlantSpec, build_setup
        build_setup(PlantSpec("rig-force"), truth, first, input="f", output="x", y0=[0, 1])


def test_joint_fit_refuses_mixed_sampling_rates():
    a = _record(1.0)
    t2 = np.linspace(0.0, 2.0, 401)
    b = Measurement.from_arrays(t2, source="coarse", v=np.interp(t2, T, a["v"]),
                                F=np.interp(t2, T, a["F"]), s=np.ones(t2.size))
    with pytest.raises(ValueError, match="different sampling intervals.*coarse.*resample"):
        fit(make_model("tanh", **TRUTH), [a, b], FitProblem(input="v", output="F",
            plant="rig-velocity", params=["F_c"]))


def test_column_expressions():
    cols = {"a": np.array([1.0, 2.0, 3.0]), "b": np.array([3.0, 2.0, 1.0])}
    np.testing.assert_allclose(evaluate_column("(a + b) / mean(a + b)", cols), 1.0)
    np.testing.assert_allclose(evaluate_column("a / max(a) - 2 ** 2", cols),
                               [1 / 3 - 4, 2 / 3 - 4, -3])
    np.testing.assert_allclose(evaluate_column("sqrt(abs(-a)) * first(b)", cols),
                               3 * np.sqrt([1, 2, 3]))
    with pytest.raises(ValueError, match="unknown column 'c'.*columns: a, b"):
        evaluate_column("a + c", cols)
    with pytest.raises(ValueError, match="unknown function 'exec'"):
        evaluate_column("exec(a)", cols)
    for text in ("a.__class__", "[a]", "a if b else a", "'x'"):
        with pytest.raises(ValueError, match="outside the grammar"):
            evaluate_column(text, cols)
    with pytest.raises(ValueError, match="not finite at row 0"):
        evaluate_column("a / (b - 3)", cols)


def test_solver_options_as_one_object_or_a_mapping_over_the_fit_defaults():
    from clutchsim.core import SolverOptions
    from clutchsim.identify import FIT_SOLVER_DEFAULTS, solver_options
    rec = _record(1.0, seed=7)
    problem = FitProblem(input="v", output="F", plant="rig-velocity", params=["F_c"],
                         plant_options={"scale": "s"})
    start = make_model("tanh", **{**TRUTH, "F_c": 1.0})
    mapping = fit(start, rec, problem, FitOptions(solver_options={"rtol": 1e-8, "atol": 1e-9}))
    one = fit(start, rec, problem,
              FitOptions(solver_options=SolverOptions(**FIT_SOLVER_DEFAULTS, atol=1e-9)))
    assert one.parameters["F_c"] == pytest.approx(mapping.parameters["F_c"], rel=1e-9)
    # the defaults: atol from the output scale unless given; an object is taken as it is
    base, auto = solver_options()
    assert auto and base.rtol == FIT_SOLVER_DEFAULTS["rtol"] == 1e-8
    assert base.wall_time == FIT_SOLVER_DEFAULTS["wall_time"]
    base, auto = solver_options({"rtol": 1e-9, "wall_time": 5})
    assert auto and (base.rtol, base.wall_time) == (1e-9, 5.0)
    assert base.max_steps == FIT_SOLVER_DEFAULTS["max_steps"]
    assert solver_options({"atol": 1e-7})[1] is False
    given = SolverOptions(rtol=1e-5)
    assert solver_options(given) == (given, False)
    with pytest.raises(ValueError, match=r"unknown solver option 'rtoll' \(did you mean "
                       r"'rtol'\?\); options: rtol, atol"):
        fit(start, rec, problem, FitOptions(solver_options={"rtoll": 1e-8}))
    with pytest.raises(TypeError, match="options must be a SolverOptions or a mapping"):
        fit(start, rec, problem, FitOptions(solver_options=1e-8))
    with pytest.raises(TypeError, match="rtol"):
        fit(start, rec, problem, rtol=1e-8)            # the loose tolerances are gone