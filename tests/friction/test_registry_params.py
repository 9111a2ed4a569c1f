"""Registry, parameter sets and the meta-test over every registered model."""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest

from clutchsim import friction
from clutchsim.friction import (
    MODELS,
    FrictionModel,
    describe_models,
    get_model_class,
    list_parameter_sets,
    load_parameter_set,
    make_model,
)
from clutchsim.friction.base import UNIT_KINDS

REPO = Path(__file__).resolve().parents[2]

#: the codes the registry gave the models before any later one was appended: compiled
#: plants, their cache keys and exported FMUs were made with them, so they never change (a
#: new model is appended to the registry and takes the next code)
RELEASED_CODES = {
    "coulomb-naive": 1, "coulomb-robust": 2, "karnopp": 3, "tanh": 4, "stribeck": 5,
    "rotational-friction": 6, "dahl": 7, "lugre": 8, "elastoplastic": 9, "gms": 10,
    "mykhailevych2020": 11,
}  # fmt: skip
NAMES = list(MODELS)

EXPECTED_SETS = {
    "lugre_canudas1995", "dahl_d1", "elastoplastic_dupont2002", "gms_illustrative", "coulomb",
    "karnopp", "tanh", "stribeck", "rotational_friction", "mykhailevych2020_translational",
    "mykhailevych2020_clutch",
}  # fmt: skip


def test_codes_follow_the_registry_and_released_codes_never_change():
    assert [cls.code for cls in MODELS.values()] == list(range(1, len(MODELS) + 1))
    for name, code in RELEASED_CODES.items():
        assert MODELS[name].code == code


def test_registration_refuses_incomplete_declarations():
    from clutchsim.friction.registry import register

    class NoKernels(MODELS["tanh"]):
        name = "no-kernels"
        kernels = None
    with pytest.raises(TypeError, match="NoKernels: declares no citation"):
        register(NoKernels)
    NoKernels.steady_checks = MODELS["tanh"].steady_checks
    NoKernels.phenomena = MODELS["tanh"].phenomena
    NoKernels.citation, NoKernels.parameter_info = "x", MODELS["tanh"].parameter_info
    NoKernels.default_parameter_set = "tanh"
    with pytest.raises(TypeError, match="kernels = None must be a FrictionKernels"):
        register(NoKernels)
    with pytest.raises(TypeError, match="name 'tanh' is taken"):
        register(MODELS["tanh"], MODELS["tanh"])


def test_classes_final():
    for cls in MODELS.values():
        assert issubclass(cls, FrictionModel)
        assert cls.__dataclass_params__.frozen  # type: ignore[attr-defined]
        assert not cls.__abstractmethods__


def test_unknown_model_lists_valid_names_and_closest():
    with pytest.raises(ValueError, match=r"unknown friction model 'luger'.*'lugre'") as info:
        get_model_class("luger")
    for name in MODELS:
        assert name in str(info.value)


def test_unknown_parameter_set_lists_valid_names_and_closest():
    with pytest.raises(ValueError, match=r"'lugre_canudas1996'.*'lugre_canudas1995'") as info:
        load_parameter_set("lugre_canudas1996")
    assert "dahl_d1" in str(info.value)


def test_all_expected_sets_present_and_load():
    assert EXPECTED_SETS | _default_sets() <= set(list_parameter_sets())
    for name in list_parameter_sets():
        pset = load_parameter_set(name)
        assert {"source", "notes", "domain"} <= set(pset.meta)
        assert pset.meta["domain"] in ("translational", "rotational")
        for model_name in pset.models:
            model = get_model_class(model_name).from_parameters(name)
            assert set(pset.parameters) <= {f for f in model.parameter_info}


def test_set_for_wrong_model_rejected():
    with pytest.raises(ValueError, match="is for model"):
        get_model_class("lugre").from_parameters("dahl_d1")


def test_list_sets_by_model():
    assert list_parameter_sets("mykhailevych2020") == [
        "mykhailevych2020_clutch",
        "mykhailevych2020_translational",
        "mykhailevych2020_translational_damped",
    ]
    assert "coulomb" in list_parameter_sets("coulomb-naive")
    assert "coulomb" in list_parameter_sets("coulomb-robust")


def test_every_set_has_a_domain_and_sets_list_by_domain():
    rotational = {"rotational_friction", "mykhailevych2020_clutch"}
    for name in list_parameter_sets():
        assert load_parameter_set(name).domain in ("translational", "rotational")
    assert set(list_parameter_sets(domain="rotational")) == rotational
    assert list_parameter_sets("mykhailevych2020", "translational") == [
        "mykhailevych2020_translational", "mykhailevych2020_translational_damped"]
    with pytest.raises(ValueError, match="domain = 'angular'"):
        list_parameter_sets(domain="angular")


def test_rig_refuses_a_set_of_the_other_domain():
    from clutchsim.friction import domain_problem, parameter_source
    from clutchsim.rig import make_rig

    clutch = make_model("mykhailevych2020", "mykhailevych2020_clutch")
    assert parameter_source(clutch).domain == "rotational"
    with pytest.raises(ValueError) as info:
        make_rig(clutch)                      # translational by default
    msg = str(info.value)
    assert "'mykhailevych2020_clutch'" in msg and "rotational (N·m, rad, rad/s)" in msg
    assert "translational units (N, m, m/s)" in msg and "mykhailevych2020_translational" in msg
    assert "T_stat = 240 N·m would be read as 240 N" in msg
    assert make_rig(clutch, domain="rotational").metadata["domain"] == "rotational"
    with pytest.raises(ValueError, match="lugre has no rotational parameter set"):
        make_rig(make_model("lugre"), domain="rotational")
    # every parameter with a unit overridden: nothing of the set's domain is left
    own = make_model("lugre", F_c=20.0, F_s=25.0, v_s=0.1, sigma0=1e4, sigma1=10.0, sigma2=0.0)
    assert parameter_source(own).taken == ()
    assert domain_problem(own, "rotational", "x") is None
    # numbers given directly: their domain is the caller's, nothing to check
    assert parameter_source(clutch.with_(k_v=0.1)) is None
    make_rig(clutch.with_(k_v=0.1))


def _default_sets() -> set[str]:
    return {cls.default_parameter_set for cls in MODELS.values()}


def test_parameter_files_ship_inside_the_package():
    import clutchsim

    pkg = Path(clutchsim.__file__).parent / "params" / "friction"
    assert {p.stem for p in pkg.glob("*.toml")} >= EXPECTED_SETS | _default_sets()


def test_make_model_overrides():
    model = make_model("lugre", sigma2=0.0)
    assert model.sigma2 == 0.0 and model.sigma0 == 1e5
    assert make_model("elastoplastic").z_ba == pytest.approx(0.95 * 1.0 / 1e5)


def test_meta_every_model_complete(model_name):
    """Default set loads, docs page exists, describe_models has units for every parameter."""
    cls = get_model_class(model_name)
    model = make_model(model_name)
    assert isinstance(model, cls)
    assert cls.default_parameter_set in list_parameter_sets(model_name)
    page = REPO / "docs" / "models" / f"{model_name}.md"
    assert page.is_file(), page
    text = page.read_text(encoding="utf-8")
    for param in cls.parameter_info:
        assert f"`{param}`" in text, (model_name, param)
    entry = next(d for d in describe_models() if d["name"] == model_name)
    assert entry["citation"] == cls.citation and len(cls.citation) > 30
    assert entry["states"] == list(model.state_names())
    assert [p["name"] for p in entry["parameters"]] == list(cls.parameter_info)
    for p in entry["parameters"]:
        assert p["unit"] and p["description"]
    for param, (kind, description) in cls.parameter_info.items():
        assert kind in UNIT_KINDS and description
        assert hasattr(model, param)
    assert set(cls.phenomena) == set(friction.PHENOMENA)
    assert {e.expected for e in cls.phenomena.values()} <= {"yes", "no", "depends"}
    # the static capacity is a finite force level, and it holds at least the kinetic level
    # for a model with stiction
    cap = model.static_capacity()
    assert math.isfinite(cap) and cap >= 0.0
    assert isinstance(model.typical_scales(), friction.Scales)
    assert len(model.typical_scales().states) == model.n_states
    # the declared kernels are the ones the dispatchers call, and the events and reset
    # kernels exist exactly where the class can have events
    assert (cls.kernels.events is not None) == (cls.kernels.reset is not None)
    if model.n_events:
        assert cls.kernels.events is not None
    # every dataclass field is documented
    assert {f.name for f in dataclasses.fields(model)} == set(cls.parameter_info)
    # states, units and events are consistent
    assert len(model.state_units("translational")) == model.n_states
    assert len(model.state_units("rotational")) == model.n_states
    assert model.initial_state().shape == (model.n_states,)
    assert model.event_directions().shape == (model.n_events,)
    assert set(model.event_directions().tolist()) <= {-1, 0, 1}
    p = model.pack()
    assert p.dtype == np.float64 and p.ndim == 1 and p.flags.c_contiguous


def test_describe_models_is_json_serialisable():
    data = {"models": describe_models()}
    back = json.loads(json.dumps(data))
    assert [m["name"] for m in back["models"]] == NAMES
    rot = describe_models("rotational")
    lugre = next(d for d in rot if d["name"] == "lugre")
    assert {p["name"]: p["unit"] for p in lugre["parameters"]}["sigma0"] == "N·m/rad"


def test_unit_of_domains():
    cls = get_model_class("lugre")
    assert cls.unit_of("sigma1") == "N·s/m"
    assert cls.unit_of("sigma1", "rotational") == "N·m·s/rad"
    with pytest.raises(ValueError, match="domain"):
        cls.unit_of("sigma1", "angular")
    with pytest.raises(ValueError, match="no parameter 'sigma3'"):
        cls.unit_of("sigma3")


def test_public_api_exports():
    for name in friction.__all__:
        assert hasattr(friction, name)
    assert issubclass(friction.SelfExcitedWarning, UserWarning)


@pytest.mark.parametrize("name", NAMES)
def test_smooth_at_events_flag_matches_the_kernel_and_the_force(name):
    # a model that lets integrators step through its event crossings must have a force
    # that is continuous across them: at its velocity zero crossing, F(0-) = F(0+)
    from clutchsim.friction import friction_force, smooth_at_events
    cls = get_model_class(name)
    assert smooth_at_events(cls.code) == cls.smooth_at_events
    if not cls.smooth_at_events:
        return
    m = make_model(name)
    assert "velocity_zero_crossing" in m.event_names()
    p = m.pack()
    rng = np.random.default_rng(cls.code)
    dz = np.zeros(m.n_states)
    for _ in range(5):
        z = rng.normal(scale=1e-4, size=m.n_states)
        jump = [abs(friction_force(cls.code, p, z, eps, 0.0, 1.0, dz)
                    - friction_force(cls.code, p, z, -eps, 0.0, 1.0, dz))
                for eps in (1e-6, 1e-9, 1e-12)]
        assert jump[0] > jump[1] > jump[2] >= 0.0     # shrinks with the velocity
        assert jump[2] < 1e-9 * m.static_capacity()


@pytest.mark.parametrize("name", NAMES)
def test_stick_force_flag_matches_the_kernel(name):
    # plants skip computing the stick force for models that declare they do not read it;
    # the compiled predicate must agree with the class variable, and a model that says
    # "no" must give the same force and state derivatives for any F_e
    from clutchsim.friction import friction_force, uses_stick_force
    cls = get_model_class(name)
    assert uses_stick_force(cls.code) == cls.uses_stick_force
    if cls.uses_stick_force:
        return
    m = make_model(name)
    p = m.pack()
    rng = np.random.default_rng(cls.code)
    for _ in range(5):
        z = rng.normal(scale=1e-4, size=m.n_states) if m.n_states else np.zeros(0)
        v = float(rng.normal(scale=0.05))
        dz1, dz2 = np.zeros(m.n_states), np.zeros(m.n_states)
        f1 = friction_force(cls.code, p, z, v, 0.0, 1.0, dz1)
        f2 = friction_force(cls.code, p, z, v, float(rng.normal(scale=100.0)), 1.0, dz2)
        assert f1 == f2
        np.testing.assert_array_equal(dz1, dz2)


def test_describe_models_gives_defaults_and_the_sets_with_their_domain():
    m6 = next(d for d in describe_models("rotational") if d["name"] == "mykhailevych2020")
    assert m6["default_parameter_set"] == "mykhailevych2020_translational"
    assert m6["default_domain"] == "translational"
    defaults = {p["name"]: p["default"] for p in m6["parameters"]}
    assert defaults == dataclasses.asdict(make_model("mykhailevych2020"))
    sets = {s["name"]: s for s in m6["parameter_sets"]}
    assert sets["mykhailevych2020_clutch"]["domain"] == "rotational"
    assert sets["mykhailevych2020_clutch"]["parameters"]["T_stat"] == 240.0
    # the benchmark set says up front why it shows no Stribeck drop
    assert "43 N·s/m" in sets["mykhailevych2020_translational"]["caveat"]
    slope = 0.5 * np.sqrt(2 / np.e) / 0.01     # (T_stat - T_din)·sqrt(2/e)/omega0
    assert round(slope) == 43 and make_model("mykhailevych2020").k_v > slope


def test_models_command_shows_defaults_sets_and_domains():
    import subprocess
    import sys
    r = subprocess.run([sys.executable, "-m", "clutchsim", "models", "mykhailevych2020",
                        "--domain", "rotational"], capture_output=True, text=True,
                       timeout=300, check=False)
    assert r.returncode == 0, r.stderr
    out = r.stdout
    # rotational units: the values shown are the rotational set's, in N·m
    line = next(s for s in out.splitlines() if s.strip().startswith("T_stat"))
    assert "[N·m]" in line and "240" in line
    assert "mykhailevych2020_clutch (rotational: N·m, rad, rad/s)" in out
    assert "mykhailevych2020_translational (default, translational: N, m, m/s)" in out
    assert "NOTE (mykhailevych2020_translational)" in out


@pytest.mark.parametrize("model_name", NAMES)
def test_model_docs_list_every_set_with_its_domain(model_name):
    text = (REPO / "docs" / "models" / f"{model_name}.md").read_text(encoding="utf-8")
    section = text.split("## Parameter sets", 1)[1].split("\n## ", 1)[0]
    for name in list_parameter_sets(model_name):
        pset = load_parameter_set(name)
        line = next(s for s in section.splitlines() if s.startswith(f"* `{name}`"))
        assert f"**{pset.domain}**" in line
        for key, value in pset.parameters.items():
            shown = f"{value:g}" if isinstance(value, float) else str(value)
            if not isinstance(value, list):
                assert f"{key} = {shown}" in line


def test_an_unknown_override_names_the_models_parameters_and_the_closest():
    with pytest.raises(TypeError, match=r"lugre has no parameter 'sigma_0' \(did you mean "
                                        r"'sigma0'\?\); its parameters: F_c, F_s"):
        make_model("lugre", sigma_0=1.0)
    with pytest.raises(TypeError, match="its parameters: T_stat, k_din"):
        make_model("mykhailevych2020", F_c=1.0)
