"""A model's parameters and phenomena are declared once (``base.parameters``/``expect``), and
every declared rule is enforced on construction: checked over the whole registry."""

from __future__ import annotations

import dataclasses

import pytest

from clutchsim.friction import MODELS, make_model
from clutchsim.friction.base import (
    PHENOMENA,
    SHARED_PARAMETERS,
    Expectation,
    expect,
    parameters,
)
from clutchsim.friction.registry import register


def _element_laws():
    from clutchsim.network.components.dog_clutch import DogLaw
    from clutchsim.network.components.mass_stop import StopLaw
    from clutchsim.network.components.one_way_clutch import OneWayLaw
    from clutchsim.network.components.synchronizer import SyncLaw

    return {"dog-law": DogLaw(w_max=1.0, teeth=4.0, window=0.1),
            "stop-law": StopLaw(F_prop=0.0, F_Coulomb=1.0, F_Stribeck=0.5, fexp=2.0,
                                s_low=0.0, s_high=1.0),
            "one-way-law": OneWayLaw(T_slide=1.0),
            "sync-law": SyncLaw(w_sync=1.0, block_scale=1.0, F_c=1.0, F_s=1.1)}


#: every model of the registry (its default set) and every network element's own law
INSTANCES = {**{name: make_model(name) for name in MODELS}, **_element_laws()}
RULED = [(name, param, rule) for name, model in INSTANCES.items()
         for param, rule in model.parameter_rules.items() if rule]


def _breaking(model, rule: str) -> float:
    """A value that breaks ``rule`` by a clear margin (the rules' own grammar)."""
    if " or " in rule:
        return 1.5
    if rule.startswith("in "):
        high = float(rule[4:-1].split(", ")[1])
        return high + 1.0 if rule.endswith("]") else high
    op, rhs = rule.split(" ")
    limit = getattr(model, rhs) if rhs in model.parameter_info else float(rhs)
    return {">": limit, ">=": limit - 1.0, "<": limit, "<=": limit + 1.0}[op]


@pytest.mark.parametrize(("name", "param", "rule"), RULED,
                         ids=[f"{n}-{p}" for n, p, _ in RULED])
def test_every_declared_rule_is_enforced_with_the_parameter_and_rule_named(name, param, rule):
    model = INSTANCES[name]
    bad = _breaking(model, rule)
    with pytest.raises(ValueError, match=rf"^{type(model).__name__}: {param} = ") as info:
        dataclasses.replace(model, **{param: bad})
    assert f"must be {rule}" in str(info.value)


def test_a_relation_names_the_other_parameter_its_value_and_unit():
    model = make_model("lugre")
    with pytest.raises(ValueError, match=r"^LuGre: F_s = 0.5 N must be >= F_c = 1 N$"):
        dataclasses.replace(model, F_c=1.0, F_s=0.5)


def test_bounds_by_numbers_are_checked_before_relations():
    # F_c < 0 breaks its own bound; F_brk >= F_c holds: the message names F_c
    with pytest.raises(ValueError, match="F_c = -2 N must be >= 0"):
        dataclasses.replace(make_model("rotational-friction"), F_c=-2.0, F_brk=-3.0)


def test_parameters_keeps_field_order_and_the_shared_meanings():
    info, rules = parameters(F_c="> 0", v_t=("velocity", "regularisation velocity", "> 0"),
                             sigma2="")
    assert list(info) == ["F_c", "v_t", "sigma2"]
    assert info["F_c"] == SHARED_PARAMETERS["F_c"]
    assert info["v_t"] == ("velocity", "regularisation velocity")
    assert rules == {"F_c": "> 0", "v_t": "> 0", "sigma2": ""}


@pytest.mark.parametrize(("declared", "message"), [
    ({"F_x": "> 0"}, "'F_x' is not a shared parameter"),
    ({"v_t": ("speed", "x", "> 0")}, "unit kind 'speed'"),
    ({"F_c": "positive"}, "rule 'positive' is not of the forms"),
    ({"F_c": "=> 0"}, "rule '=> 0' is not of the forms"),
])
def test_parameters_refuses_what_it_cannot_check(declared, message):
    with pytest.raises(TypeError, match=message):
        parameters(**declared)


def test_expect_reads_the_opening_word_and_needs_every_phenomenon():
    full = dict.fromkeys(PHENOMENA, "no")
    got = expect(**{**full, "stiction": "yes (frozen)", "lag": "depends: via k_v only"})
    assert got["stiction"] == Expectation("yes", "yes (frozen)")
    assert got["lag"] == Expectation("depends", "via k_v only")
    assert got["stribeck"] == Expectation("no", "no")
    assert list(got) == list(PHENOMENA)
    with pytest.raises(TypeError, match="it takes exactly"):
        expect(**{k: v for k, v in full.items() if k != "lag"})
    with pytest.raises(TypeError, match="must open with yes, no or depends:"):
        expect(**{**full, "lag": "maybe"})


def test_registration_refuses_parameters_out_of_field_order():
    tanh = MODELS["tanh"]

    class Swapped(tanh):
        name, citation, kernels = "swapped", tanh.citation, tanh.kernels
        phenomena, steady_checks = tanh.phenomena, tanh.steady_checks
        default_parameter_set = tanh.default_parameter_set
        parameter_info = dict(reversed(tanh.parameter_info.items()))  # noqa: RUF012
    with pytest.raises(TypeError, match="in that order"):
        register(Swapped)


def _model_page_script():
    import importlib.util
    from pathlib import Path

    path = Path(__file__).resolve().parents[2] / "scripts" / "model_page.py"
    spec = importlib.util.spec_from_file_location("model_page", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_model_pages_show_the_declared_parameters_and_rules():
    script = _model_page_script()
    pages = {p.stem: p.read_text(encoding="utf-8") for p in script.DOCS.glob("*.md")
             if p.stem != "README"}
    assert set(pages) == set(MODELS)
    for name, text in script.refresh_tables(pages).items():
        assert text == pages[name], (f"docs/models/{name}.md's Parameters table differs from "
                                     "the declarations: run scripts/model_page.py --tables")
