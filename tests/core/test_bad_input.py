"""Bad arguments raise errors that name the argument, its value and the rule."""

import numpy as np
import pytest

from clutchsim.core import SolverOptions, simulate
from clutchsim.core.reference_problems import oscillator


def test_non_finite_initial_state_is_named():
    with pytest.raises(ValueError, match=r"initial state v = nan must be finite"):
        simulate(oscillator(), (0, 1), {"F": 0.0}, y0=[0.0, np.nan])


def test_wrong_initial_state_length():
    with pytest.raises(ValueError, match=r"y0 has 3 entries.*2 states \(x, v\)"):
        simulate(oscillator(), (0, 1), {"F": 0.0}, y0=[0.0, 0.0, 1.0])


@pytest.mark.parametrize("span", [(1.0, 1.0), (2.0, 1.0)])
def test_t_end_must_be_after_t_start(span):
    with pytest.raises(ValueError, match=r"t_end = .* must be > t_start"):
        simulate(oscillator(), span, {"F": 0.0})


def test_non_finite_span():
    with pytest.raises(ValueError, match="must be finite"):
        simulate(oscillator(), (0.0, np.inf), {"F": 0.0})


@pytest.mark.parametrize("field, value, rule", [("rtol", -1e-6, "must be > 0"),
                                                ("atol", 0.0, "must be > 0"),
                                                ("h_max", -1.0, "must be >= 0"),
                                                ("rtol", float("nan"), "finite")])
def test_bad_tolerances_name_the_option(field, value, rule):
    with pytest.raises(ValueError, match=f"{field} = .*{rule}"):
        SolverOptions(**{field: value})


def test_unknown_solver_lists_valid_ones_and_the_closest():
    with pytest.raises(ValueError) as info:
        simulate(oscillator(), (0, 1), {"F": 0.0}, solver="rodas")
    msg = str(info.value)
    assert "did you mean 'rodas4'" in msg and "dopri5" in msg and "scipy-radau" in msg


def test_unknown_and_missing_inputs():
    with pytest.raises(ValueError, match=r"unknown input 'Force' \(did you mean 'F'\?\)"):
        simulate(oscillator(), (0, 1), {"Force": 0.0})
    with pytest.raises(ValueError, match="no signal given for input"):
        simulate(oscillator(), (0, 1), {})


def test_non_finite_parameters_are_rejected():
    sysm = oscillator().with_params(np.array([2.0, np.nan]))
    with pytest.raises(ValueError, match="parameter vector entry 1 = nan must be finite"):
        simulate(sysm, (0, 1), {"F": 0.0})


def test_unknown_option_keyword_is_a_type_error():
    with pytest.raises(TypeError):
        SolverOptions(tolerance=1e-3)


def test_solver_options_from_a_mapping_name_the_bad_key():
    from clutchsim.core.controllers import StepController
    opts = SolverOptions.from_mapping({"rtol": 1e-7, "max_steps": 10, "controller": "pid"},
                                      dt_out=0.01)
    assert opts.rtol == 1e-7 and opts.max_steps == 10 and opts.dt_out == 0.01
    assert opts.controller == StepController(kind="pid")
    with pytest.raises(ValueError, match="unknown solver option 'rtl'.*did you mean 'rtol'"):
        SolverOptions.from_mapping({"rtl": 1e-6})
    with pytest.raises(ValueError, match="max_steps = 2.5 must be an integer"):
        SolverOptions.from_mapping({"max_steps": 2.5})
    with pytest.raises(ValueError, match="atol = 'x' must be a number"):
        SolverOptions.from_mapping({"atol": "x"})
    with pytest.raises(ValueError, match="kind = 'PID' is not known"):
        SolverOptions.from_mapping({"controller": "PID"})
