"""Scenario files: the examples load, the default is the packaged copy, bad input is named."""

from pathlib import Path

import pytest

from clutchsim.scenario import ScenarioError, default_scenario_text, load_scenario
from clutchsim.scenario.schema import reference_markdown

from _dl_paths import EXAMPLES, REPO


def test_packaged_default_equals_example_launch():
    assert default_scenario_text() == (EXAMPLES / "launch.toml").read_text(encoding="utf-8")


def test_reference_doc_is_generated_from_the_schema():
    doc = REPO / "docs" / "scenario-reference.md"
    assert doc.read_text(encoding="utf-8") == reference_markdown() + "\n", \
        "regenerate: python -c 'from clutchsim.scenario import reference_markdown as r; " \
        "print(r())' > docs/scenario-reference.md"


DRIVELINE_EXAMPLES = ("launch", "hill_start", "tip_out", "shift_1_2", "coupled_clutches")


@pytest.mark.parametrize("name", DRIVELINE_EXAMPLES)
def test_examples_load(name):
    sc = load_scenario(EXAMPLES / f"{name}.toml")
    assert sc.t_end > 0 and sc.chain().build().n_states > 0


def _write(tmp_path, text, name="s.toml"):
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return p


def _bad(tmp_path, old, new, count=1):
    text = (EXAMPLES / "launch.toml").read_text(encoding="utf-8")
    assert old in text
    p = _write(tmp_path, text.replace(old, new, count))
    with pytest.raises(ScenarioError) as info:
        load_scenario(p)
    return info.value, p, text.replace(old, new, count)


def _line_of(text, needle):
    return next(i for i, line in enumerate(text.splitlines(), 1) if needle in line)


def test_unknown_key_suggests_closest_with_file_key_and_line(tmp_path):
    err, p, text = _bad(tmp_path, "tyre_radius = 0.3", "tyre_radius = 0.3\ntyre_raduis = 0.3")
    msg = str(err)
    assert str(p) in msg and "vehicle.tyre_raduis" in msg and "did you mean 'tyre_radius'" in msg
    assert err.line == _line_of(text, "tyre_raduis")


def test_missing_required_component(tmp_path):
    p = _write(tmp_path, '[scenario]\nname = "x"\nt_end = 1.0\n')
    with pytest.raises(ScenarioError, match="missing required component"):
        load_scenario(p)


def test_out_of_range_value_and_wrong_units(tmp_path):
    err, _, text = _bad(tmp_path, "mass = 1300.0", "mass = -5.0")
    assert "vehicle.mass" in str(err) and "must be > 0 kg" in str(err)
    assert err.line == _line_of(text, "mass = -5.0")
    err, _, _ = _bad(tmp_path, "idle_speed = 83.78", 'idle_speed = "800 rpm"')
    assert "engine.idle_speed" in str(err) and "rad/s" in str(err)


def test_gear_that_does_not_exist(tmp_path):
    err, _, text = _bad(tmp_path, "gear = 1\n", "gear = 7\n")
    assert "coupling[2].gear" in str(err) and "gear 7 does not exist" in str(err)
    assert err.line == _line_of(text, "gear = 7")


def test_csv_input_with_gap_names_file_key_and_line(tmp_path):
    csv = _write(tmp_path, "time,value\n0,0\n1,0.5\n\n2,1\n", "com.csv")
    err, p, text = _bad(tmp_path, 'clutch_command = "ramp(0.5, 1.2, 1.0)"',
                        'clutch_command = "com.csv"')
    msg = str(err)
    assert str(p) in msg and "inputs.clutch_command" in msg
    assert f"{csv}:4" in msg and "gap" in msg
    assert err.line == _line_of(text, "com.csv")


def test_unknown_model_and_missing_alternative(tmp_path):
    err, _, _ = _bad(tmp_path, 'model = "mykhailevych2020"', 'model = "mykhailevich2020"')
    assert "did you mean 'mykhailevych2020'" in str(err).lower()
    sc = load_scenario(EXAMPLES / "launch.toml")
    with pytest.raises(ScenarioError, match="no parameters for model 'lugre'"):
        sc.chain("lugre")


def test_set_overrides(tmp_path):
    sc = load_scenario(None, overrides=["vehicle.grade=12", "scenario.t_end=1.5"])
    assert sc.data["vehicle"]["grade"] == 12 and sc.t_end == 1.5
    assert Path(sc.file).name.endswith("launch.toml>")
