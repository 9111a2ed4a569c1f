"""The EMPS closed-loop plant: synthetic recovery and the benchmark record."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from _identify_helpers import shared_file

from clutchsim.core import SolverOptions, Table, simulate
from clutchsim.data import Measurement, read_measurements
from clutchsim.friction import make_model
from clutchsim.identify import FitOptions, FitProblem, evaluate, fit, load_spec, make_emps

ROOT = Path(__file__).resolve().parents[2]
GAINS = {"gtau": 35.15, "kp": 160.18, "kv": 243.45}


def test_emps_synthetic_coulomb_viscous_recovery():
    t = np.linspace(0.0, 3.0, 3001)
    q_ref = 0.05 * (1 - np.cos(2 * np.pi * 0.5 * t)) + 0.01 * np.sin(2 * np.pi * 1.3 * t)
    truth = make_model("tanh", F_c=20.0, v_t=1e-3, sigma2=200.0)
    system = make_emps(truth, M=95.0, offset=-3.0, tau_v=0.0015, **GAINS)
    res = simulate(system, (0.0, 3.0), {"q_ref": Table(t, q_ref, hit_knots=False), "u_d": 0.0,
                                        "F_d": 0.0},
                   solver="dopri5", options=SolverOptions(rtol=1e-10, atol=1e-13,
                                                          dt_out=1e-3))
    assert res.status == "completed", res.message
    q = np.interp(t, res.t, res["q"])
    q = np.round(q / 5e-8) * 5e-8                      # the encoder quantum of the benchmark
    data = Measurement.from_arrays(t, q=q, q_ref=q_ref)
    start = truth.with_(F_c=12.0, sigma2=300.0)
    out = fit(start, data, FitProblem(input="q_ref", output="q", plant="emps",
              plant_options={**GAINS, "M": 95.0, "offset": 0.0, "tau_v": 0.0015}, params=["F_c",
              "sigma2", "offset"], bounds={"F_c": (1.0, 100.0), "sigma2": (10.0, 1000.0)}),
              FitOptions(solver="dopri5", tol=1e-6))
    p = out.parameters
    assert p["F_c"] == pytest.approx(20.0, rel=0.01)
    assert p["sigma2"] == pytest.approx(200.0, rel=0.01)
    assert p["offset"] == pytest.approx(-3.0, abs=0.1)
    assert out.fit_trace.metrics["position_error_pct"] < 1e-3


def test_emps_plant_rejects_bad_options():
    with pytest.raises(ValueError, match=r"EMPS plant: M = -1.0 must be finite and > 0"):
        make_emps(make_model("tanh"), M=-1.0)
    with pytest.raises(ValueError, match=r"tau_v = -0.1 s must be finite and >= 0"):
        make_emps(make_model("tanh"), tau_v=-0.1)


@pytest.fixture(scope="module")
def emps_data():
    shared_file("data", "emps", "DATA_EMPS.mat")
    return load_spec(ROOT / "examples" / "fit_emps.toml").read()


def test_published_values_reproduce_the_benchmark_record(emps_data):
    """The authors' IDIM values in our loop: position error well under their 0.014 %."""
    tr = evaluate(make_model("tanh", F_c=20.39, v_t=1e-3, sigma2=203.5), emps_data,
                  input="q_ref", output="q", plant="emps", solver="dopri5",
                  plant_options={"M": 95.11, "offset": -3.165, "voltage": "vir"})
    assert tr.metrics["position_error_pct"] < 0.003
    assert 5.0 < tr.metrics["force_error_pct"] < 7.5          # 6.3 % measured, 5.8 % published


def test_coulomb_viscous_fit_on_the_benchmark_record(emps_data):
    """C+V fit on the first 8 s, plant held at the spec's values: close to the IDIM values."""
    spec = load_spec(ROOT / "examples" / "fit_emps.toml")
    res = fit(make_model("tanh", F_c=15.0, v_t=1e-3, sigma2=150.0), emps_data.window(0, 8),
              FitProblem(input="q_ref", output="q", plant="emps",
              plant_options=dict(spec.plant.options), params=["F_c", "sigma2"], bounds={"F_c":
              (1.0, 100.0), "sigma2": (10.0, 1000.0)}), FitOptions(solver="dopri5", tol=1e-6))
    assert res.parameters["F_c"] == pytest.approx(20.4, rel=0.1)
    assert res.parameters["sigma2"] == pytest.approx(203.0, rel=0.1)
    assert res.nrmse_fit < 0.0045                   # whole record, 5 parameters: 0.0030


def test_read_the_mat_file_with_gains(emps_data):
    assert emps_data.scalars["gtau"] == pytest.approx(35.1507, rel=1e-5)
    assert len(emps_data) == 24841 and emps_data.units["q"] == "m"
    with pytest.raises(ValueError, match=r"missing column\(s\) 'qx'.*'qm'"):
        read_measurements(shared_file("data", "emps", "DATA_EMPS.mat"), columns={"q": "qx"})


def test_emps_controller_and_force_disturbances_are_inputs():
    """Pulses added to the controller output (u_d [V]) and a disturbance force (F_d [N]):
    a declared input reproduces the record; without it the same parameters do not."""
    from clutchsim.identify import InputSpec
    t = np.linspace(0.0, 2.0, 2001)
    q_ref = 0.05 * (1 - np.cos(2 * np.pi * 0.5 * t))
    pulse = np.where((t % 0.5) < 0.05, 0.3, 0.0)           # V
    push = 5.0 * np.sin(2 * np.pi * 2 * t)                   # N
    truth = make_model("tanh", F_c=20.0, v_t=1e-3, sigma2=200.0)
    system = make_emps(truth, M=95.0, **GAINS)
    res = simulate(system, (0.0, 2.0), {"q_ref": Table(t, q_ref, hit_knots=False),
                                        "u_d": Table(t, pulse, hit_knots=False),
                                        "F_d": Table(t, push, hit_knots=False)},
                   solver="dopri5", options=SolverOptions(rtol=1e-10, atol=1e-13,
                                                          dt_out=1e-3))
    assert res.status == "completed", res.message
    data = Measurement.from_arrays(t, q=np.interp(t, res.t, res["q"]), q_ref=q_ref,
                                   pulse=pulse, push=push)
    kw = {"input": "q_ref", "output": "q", "plant": "emps", "solver": "dopri5",
          "plant_options": {**GAINS, "M": 95.0}}
    inputs = [InputSpec("pulse", "controller", unit="V"), InputSpec("push", "force", unit="N")]
    with_inputs = evaluate(truth, data, inputs=inputs, **kw)
    without = evaluate(truth, data, **kw)
    assert with_inputs.nrmse < 1e-3
    assert without.nrmse > 100 * with_inputs.nrmse
