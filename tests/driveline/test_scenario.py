"""Scenario files: the examples load, the default is the packaged copy, bad input is named."""

from pathlib import Path

import pytest
from _dl_paths import EXAMPLES, REPO

from clutchsim.scenario import ScenarioError, default_scenario_text, load_scenario
from clutchsim.scenario.schema import reference_markdown


def test_packaged_default_equals_example_launch():
    assert default_scenario_text() == (EXAMPLES / "launch.toml").read_text(encoding="utf-8")


def test_reference_doc_is_generated_from_the_schema():
    doc = REPO / "docs" / "scenario-reference.md"
    assert doc.read_text(encoding="utf-8") == reference_markdown() + "\n", \
        "regenerate: python -c 'from clutchsim.scenario import reference_markdown as r; " \
        "print(r())' > docs/scenario-reference.md"


DRIVELINE_EXAMPLES = sorted(p.stem for p in EXAMPLES.glob("*.toml") if not p.stem.startswith("fit_"))


@pytest.mark.parametrize("name", DRIVELINE_EXAMPLES)
def test_examples_load(name):
    sc = load_scenario(EXAMPLES / f"{name}.toml")
    assert sc.t_end > 0 and sc.network().build().n_states > 0


def _write(tmp_path, text, name="s.toml"):
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return p


def _bad(tmp_path, old, new, count=1, src="launch"):
    text = (EXAMPLES / f"{src}.toml").read_text(encoding="utf-8")
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
        sc.network("lugre")


def test_set_overrides(tmp_path):
    sc = load_scenario(None, overrides=["vehicle.grade=12", "scenario.t_end=1.5"])
    assert sc.data["vehicle"]["grade"] == 12 and sc.t_end == 1.5
    assert Path(sc.file).name.endswith("launch.toml>")


def _assert_names(err, path, key, value, rule, text, needle):
    """The message names the file, the key path, the value and the rule; the line is
    the line of the bad entry."""
    msg = str(err)
    assert str(path) in msg and key in msg, msg
    assert value in msg and rule in msg, msg
    assert err.key == key
    assert err.line == _line_of(text, needle)


@pytest.mark.parametrize("old,new,key,value,rule", [
    ("peak = 25.0", "peak = 0.5", "coupling[0].peak", "0.5", "must be >= 1"),
    ("T_slide = 1.5 ", "T_slide = -1.5 ", "coupling[0].T_slide", "-1.5", "must be >= 0 N·m"),
])
def test_bad_one_way_clutch_parameters(tmp_path, old, new, key, value, rule):
    err, p, text = _bad(tmp_path, old, new, src="one_way_clutch")
    _assert_names(err, p, key, value, rule, text, new.strip())


LOSS = ("loss_table = { speed = [0.0], eta_mf1 = [0.5], eta_mf2 = [0.5], tau_bf1 = [0.0], "
        "tau_bf2 = [0.0] }")


@pytest.mark.parametrize("new,key,value,rule", [
    (LOSS.replace("eta_mf1 = [0.5]", "eta_mf1 = [0.0]"), "coupling[0].loss_table.eta_mf1[0]",
     "= 0 ", "an efficiency must be in (0, 1]"),
    (LOSS.replace("eta_mf2 = [0.5]", "eta_mf2 = [1.2]"), "coupling[0].loss_table.eta_mf2[0]",
     "= 1.2", "an efficiency must be in (0, 1]"),
    (LOSS.replace("tau_bf1 = [0.0]", "tau_bf1 = [-0.1]"), "coupling[0].loss_table.tau_bf1[0]",
     "= -0.1 N·m", "must be >= 0 N·m"),
    (LOSS.replace("speed = [0.0], eta_mf1 = [0.5], eta_mf2 = [0.5], tau_bf1 = [0.0], "
                  "tau_bf2 = [0.0]",
                  "speed = [0.0, 2.0, 1.0], eta_mf1 = [0.5, 0.5, 0.5], eta_mf2 = [0.5, 0.5, 0.5], "
                  "tau_bf1 = [0.0, 0.0, 0.0], tau_bf2 = [0.0, 0.0, 0.0]"),
     "coupling[0].loss_table.speed[2]", "= 1 rad/s", "must be greater than speed[1]"),
    (LOSS.replace("eta_mf2 = [0.5]", "eta_mf2 = [0.5, 0.6]"), "coupling[0].loss_table.eta_mf2",
     "has 2 entries", "one value per speed"),
    (LOSS.replace("tau_bf2", "tau_bf3"), "coupling[0].loss_table", "tau_bf3",
     "must be a table {speed = [...]"),
])
def test_bad_lossy_gear_table(tmp_path, new, key, value, rule):
    err, p, text = _bad(tmp_path, LOSS, new, src="lossy_gear_demo1")
    _assert_names(err, p, key, value, rule, text, "loss_table = {")


def test_bad_lossy_gear_ratio_and_count(tmp_path):
    err, p, text = _bad(tmp_path, "ratio = 2.0", "ratio = 0.0", src="lossy_gear_demo1")
    _assert_names(err, p, "coupling[0].ratio", "= 0", "must be non-zero", text, "ratio = 0.0")
    second = ('[[inertia]]\nname = "Inertia3"\nJ = 1.0\n\n[[coupling]]\nname = "gear2"\n'
              'type = "lossy_gear"\nratio = 1.0\n' + LOSS + "\n")
    err, p, text = _bad(tmp_path, "[[coupling]]", second + "\n[[coupling]]",
                        src="lossy_gear_demo1")
    assert "at most one" in str(err) and err.key == "coupling[1]"


def test_bad_thermal_link(tmp_path):
    err, p, text = _bad(tmp_path, 'link = "pressure_plate"', 'link = "pressure_plat"',
                        src="ten_launches")
    _assert_names(err, p, "thermal[0].link", "'pressure_plat'", "is not a thermal node", text,
                  'link = "pressure_plat"')
    assert "did you mean 'pressure_plate'" in str(err)
    err, p, _ = _bad(tmp_path, "link_conductance = 120.0   #", "link_conductance = 0.0   #",
                     src="ten_launches")
    assert "thermal[0]" in str(err) and "needs link_conductance > 0 W/K" in str(err)


def test_model_cannot_replace_a_fixed_switching_law():
    sc = load_scenario(EXAMPLES / "one_way_clutch.toml")
    with pytest.raises(ScenarioError, match="'lugre' cannot replace 'oneWayClutch'"):
        sc.network("lugre")
    assert sc.network(None).build().metadata["models"]["oneWayClutch"] == "one-way-clutch"


@pytest.mark.parametrize("old,new,key,value,rule", [
    ("efficiency = 0.95 ", "efficiency = 1.2 ", "coupling[2].efficiency", "= 1.2",
     "must be <= 1"),
    ("efficiency_reverse = 0.93", "efficiency_reverse = 0.0", "coupling[2].efficiency_reverse",
     "= 0", "must be > 0"),
    ("efficiency = 0.95 ", "efficiency = -0.5 ", "coupling[2].efficiency", "= -0.5",
     "must be > 0"),
])
def test_bad_gearbox_efficiency(tmp_path, old, new, key, value, rule):
    err, p, text = _bad(tmp_path, old, new, src="tip_out")
    _assert_names(err, p, key, value, rule, text, new.strip())


def test_gearbox_with_losses_counts_as_the_one_lossy_gear(tmp_path):
    # a lossy final drive behind a gearbox with an efficiency: refused, with the key
    text = (EXAMPLES / "tip_out.toml").read_text(encoding="utf-8")
    old = '[[coupling]]\nname = "driveshaft"'
    assert old in text
    new = text.replace(old, '[[coupling]]\nname = "final"\ntype = "lossy_gear"\nratio = 1.0\n'
                       'loss_table = { speed = [0.0], eta_mf1 = [0.9], eta_mf2 = [0.9], '
                       'tau_bf1 = [0.0], tau_bf2 = [0.0] }\n\n' + old)
    new += '\n[[inertia]]\nname = "hub"\nJ = 0.1\n'     # one more node for the extra gear
    p = _write(tmp_path, new)
    with pytest.raises(ScenarioError) as info:
        load_scenario(p)
    assert "a second gear with losses (gearbox 'gearbox' is the first" in str(info.value)
    assert info.value.key == "coupling[3]"


def test_network_is_built_once_per_effective_model():
    # the default launch's clutch already uses model (6): asking for it by name is the
    # same network; another model is another network, each built once
    sc = load_scenario(None)
    own = sc.network()
    assert sc.network("mykhailevych2020") is own
    robust = sc.network("coulomb-robust")
    assert robust is not own and sc.network("coulomb-robust") is robust
    names = {c.name: type(c.model).__name__ for c in robust.components
             if getattr(c, "friction", False)}
    assert names["clutch"] == "CoulombRobust"


def test_a_scenario_parsed_again_reads_its_relative_paths_from_its_folder(tmp_path,
                                                                           monkeypatch):
    """Overrides on a loaded scenario (a sweep's key checks and variants) parse it again:
    its ``[scenario] compare`` and signal tables stay relative to its file, not to the
    working directory."""
    from clutchsim.scenario.loader import resolve_scenario
    sc = load_scenario(EXAMPLES / "launch_closed_loop.toml")
    assert sc.compare
    monkeypatch.chdir(tmp_path)
    again = resolve_scenario(sc, ["scenario.t_end=1.0"])
    assert again.t_end == 1.0 and again.compare == sc.compare


def test_a_chain_file_is_the_network_its_reader_writes():
    """The chain reader's document, parsed as a network scenario, is the same network
    (components, connections, parameter vector) as the chain file."""
    import tomllib

    from clutchsim.scenario import chain_format
    from clutchsim.scenario.loader import parse_scenario
    text = (EXAMPLES / "launch.toml").read_text(encoding="utf-8")
    data = tomllib.loads(text)
    assert chain_format.is_chain(data)
    doc = chain_format.rewrite(data).data
    assert not chain_format.is_chain(doc)
    chain, net = load_scenario(EXAMPLES / "launch.toml").network(), parse_scenario(doc).network()
    assert [(type(c), c.name) for c in net.components] == \
        [(type(c), c.name) for c in chain.components]
    assert net.connections == chain.connections
    assert list(net.compile().values_vector(net.components)) == \
        list(chain.compile().values_vector(chain.components))


def test_chain_errors_name_the_chain_key_and_its_line(tmp_path):
    text = (EXAMPLES / "launch.toml").read_text(encoding="utf-8")
    # a load (a torque component the reader adds) reading no input: the inertia's `load`
    disc = next(s for s in text.splitlines() if s.startswith('name = "disc"'))
    err, _p, text2 = _bad(tmp_path, disc + "\n", disc + '\nload = "nosuch"\n')
    assert "inertia[1].load" in str(err) and "'nosuch'" in str(err)
    assert err.line == next(i for i, s in enumerate(text2.splitlines(), 1)
                            if s == 'load = "nosuch"')
    # the engine's node names no inertia
    old = next(s for s in text.splitlines() if s.startswith("node = "))
    err, _p, _ = _bad(tmp_path, old + "\n", 'node = "engin"\n')
    assert "engine.node" in str(err) and "did you mean 'engine'" in str(err)
