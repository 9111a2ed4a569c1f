"""Bad parameters are rejected with messages naming the parameter, value and rule."""

from __future__ import annotations

import dataclasses
import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from clutchsim.friction import (
    GMS,
    MODELS,
    ElastoPlastic,
    LuGre,
    Mykhailevych2020,
    make_model,
)

LUGRE = {"F_c": 1.0, "F_s": 1.5, "v_s": 1e-3, "sigma0": 1e5, "sigma1": 316.0, "sigma2": 0.4}


def test_lugre_fs_below_fc_message():
    with pytest.raises(ValueError, match=r"^LuGre: F_s = 0.5 N must be >= F_c = 1 N$"):
        LuGre(**{**LUGRE, "F_s": 0.5})


@pytest.mark.parametrize("value", (0.0, -1.0))
def test_sigma0_must_be_positive(value):
    with pytest.raises(ValueError, match=rf"LuGre: sigma0 = {value:g} N/m must be > 0"):
        LuGre(**{**LUGRE, "sigma0": value})


@pytest.mark.parametrize(("param", "value"), [("phi0", 0.0), ("omega0", -1e-3)])
def test_model6_scales_must_be_positive(param, value):
    kwargs = {"T_stat": 1.5, "k_din": 2 / 3, "phi0": 1.5e-5, "omega0": 1e-2, "k_v": 316.0}
    with pytest.raises(ValueError, match=rf"Mykhailevych2020: {param} = {value:g} .* must be > 0"):
        Mykhailevych2020(**{**kwargs, param: value})


def test_model6_p_must_be_1_or_2():
    with pytest.raises(ValueError, match="p = 3 must be 1 or 2"):
        make_model("mykhailevych2020", p=3)


def test_gms_weights_must_sum_to_one():
    with pytest.raises(
        ValueError, match=r"GMS: alpha = \(0.1, 0.2, 0.3, 0.3\) must be summing to 1"
    ):
        make_model("gms", alpha=(0.1, 0.2, 0.3, 0.3))
    make_model("gms", alpha=(0.1, 0.2, 0.3, 0.4 + 5e-10))  # within 1e-9: accepted
    with pytest.raises(ValueError, match="same length as k"):
        make_model("gms", alpha=(0.5, 0.5))


def test_elastoplastic_zba_rule():
    with pytest.raises(ValueError, match=r"z_ba = 2e-05 m must be < F_c/sigma0 = 1e-05 m"):
        make_model("elastoplastic", z_ba=2e-5)


@pytest.mark.parametrize("bad", (math.nan, math.inf, -math.inf))
def test_nan_and_inf_rejected_everywhere(model_name, bad):
    model = make_model(model_name)
    for f in dataclasses.fields(model):
        value = getattr(model, f.name)
        if isinstance(value, str):
            continue
        new = tuple(bad for _ in value) if isinstance(value, tuple) else bad
        with pytest.raises(ValueError, match=rf"{f.name} = .* must be finite"):
            model.with_(**{f.name: new})


def test_unknown_keyword_is_type_error(model_name):
    with pytest.raises(TypeError):
        make_model(model_name, not_a_parameter=1.0)


def test_models_are_frozen(default_model):
    with pytest.raises(dataclasses.FrozenInstanceError):
        default_model.F_c = 2.0  # type: ignore[misc]


def test_non_numeric_rejected():
    with pytest.raises(ValueError, match="F_c = 'abc' must be a real number"):
        LuGre(**{**LUGRE, "F_c": "abc"})


def test_ints_are_coerced_to_float():
    model = LuGre(**{**LUGRE, "F_c": 1, "F_s": 2})
    assert isinstance(model.F_c, float) and model.F_s == 2.0


@settings(max_examples=60, deadline=None)
@given(
    F_c=st.floats(0.01, 10.0),
    ratio=st.floats(0.0, 0.999),
    sigma0=st.floats(-1e6, 0.0),
)
def test_invalid_lugre_family_rejected(F_c, ratio, sigma0):
    """F_s < F_c or sigma0 <= 0 always raise, naming the parameter."""
    with pytest.raises(ValueError, match="F_s = .* must be >= F_c"):
        LuGre(**{**LUGRE, "F_c": F_c, "F_s": ratio * F_c})
    with pytest.raises(ValueError, match="sigma0 = .* must be > 0"):
        ElastoPlastic(**{**LUGRE, "sigma0": sigma0, "z_ba": 1e-6})


@settings(max_examples=40, deadline=None)
@given(weights=st.lists(st.floats(0.01, 1.0), min_size=1, max_size=6))
def test_gms_weight_sum_rule(weights):
    total = sum(weights)
    k = tuple(1e4 for _ in weights)
    kwargs = {"C": 100.0, "F_c": 1.0, "F_s": 1.5, "v_s": 1e-3, "sigma1": 0.0, "sigma2": 0.0}
    if abs(total - 1.0) > 1e-9:
        with pytest.raises(ValueError, match="alpha"):
            GMS(k=k, alpha=tuple(weights), **kwargs)
    normalised = tuple(w / total for w in weights)
    assert GMS(k=k, alpha=normalised, **kwargs).n_states == len(weights)


def test_every_model_has_validation_messages_with_class_name():
    for name, cls in MODELS.items():
        model = make_model(name)
        first = next(f.name for f in dataclasses.fields(model) if f.name in cls.parameter_info)
        with pytest.raises(ValueError, match=rf"^{cls.__name__}: "):
            model.with_(**{first: math.nan})
