"""TOML fit specifications: parsing, path resolution and clear errors."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from clutchsim.identify import load_spec

ROOT = Path(__file__).resolve().parents[2]


def test_shipped_emps_spec_parses():
    spec = load_spec(ROOT / "examples" / "fit_emps.toml")
    assert spec.plant.kind == "emps" and spec.fit["input"] == "q_ref"
    for name in ("tanh", "lugre", "gms", "mykhailevych2020"):
        model, entry = spec.model_entry(name)
        assert model.name == name and entry["params"]
    assert "shared" in str(spec.data["file"]) and "${" not in str(spec.data["file"])


def test_shipped_brfd_loads_spec_parses():
    spec = load_spec(ROOT / "examples" / "fit_brfd_loads.toml")
    assert len(spec.records) == 3 and spec.fit["per_record"] == ["offset"]
    assert spec.weights() == [1.0, 1.0, 1.0] and "s" in spec.data["derived"]
    for name in ("dahl", "lugre", "gms", "mykhailevych2020"):
        model, entry = spec.model_entry(name)
        assert model.name == name and "load_fraction" in entry["params"]


def _spec(tmp_path, text):
    path = tmp_path / "s.toml"
    path.write_text(text)
    return path


def test_spec_reads_relative_data_and_maps_columns(tmp_path):
    t = np.linspace(0, 1, 11)
    np.savez(tmp_path / "d.npz", time=t, pos=t * 1e3, force=-t)
    path = _spec(tmp_path, '[data]\nfile = "d.npz"\ntime = "time"\n'
                           'columns = { x = "pos", F = "force" }\nscale = { x = 1e-3 }\n'
                           '[plant]\nkind = "rig-velocity"\n'
                           '[fit]\nmodel = "lugre"\ninput = "x"\noutput = "F"\n'
                           '[models.lugre]\nparams = ["F_c"]\nstart = { F_c = 2.0, F_s = 3.0 }\n')
    spec = load_spec(path)
    data = spec.read()
    np.testing.assert_allclose(data["x"], t)
    model, entry = spec.model_entry(None)
    assert model.F_c == 2.0 and entry["params"] == ["F_c"]


@pytest.mark.parametrize("text, message", [
    ('[data]\nfile = "d.csv"\n[fit]\ninput = "v"\noutput = "F"\n[plnt]\n', "unknown key 'plnt'"),
    ('[data]\nfile = "d.csv"\n[fit]\ninput = "v"\n', r"\[fit\] needs output"),
    ('[fit]\ninput = "v"\noutput = "F"\n', r"missing table \[data\]"),
    ('[data]\nfile = "d.csv"\n[fit]\ninput = "v"\noutput = "F"\n[plant]\nkind = "rigg"\n',
     "plant = 'rigg' is not known"),
    ('[data\n', "invalid TOML"),
])
def test_bad_specs_raise_clear_errors(tmp_path, text, message):
    with pytest.raises(ValueError, match=message):
        load_spec(_spec(tmp_path, text))


def test_unknown_model_and_entry_keys(tmp_path):
    path = _spec(tmp_path, '[data]\nfile = "d.csv"\n[fit]\ninput = "v"\noutput = "F"\n'
                           '[models.lugre]\nparms = ["F_c"]\n')
    spec = load_spec(path)
    with pytest.raises(ValueError, match="unknown friction model 'lugree'"):
        spec.model_entry("lugree")
    with pytest.raises(ValueError, match=r"\[models.lugre\] unknown key\(s\) parms"):
        spec.model_entry("lugre")


def _damper_files(tmp_path):
    """Two records with actuator forces (normal-load proxy) and one at another rate."""
    t = np.linspace(0.0, 1.0, 101)
    for name, level in (("a", 10.0), ("b", 30.0)):
        np.savez(tmp_path / f"{name}.npz", t=t, x=np.sin(t), F=np.cos(t) * level,
                 F_act1=np.full(t.size, level), F_act2=np.full(t.size, level))
    t2 = np.linspace(0.0, 1.0, 51)
    np.savez(tmp_path / "c.npz", t=t2, x=np.sin(t2), F=np.cos(t2), F_act1=np.ones(t2.size),
             F_act2=np.ones(t2.size))


SPEC = '''[data]
columns = ["x", "F", "F_act1", "F_act2"]
derived = { s = { expr = "(F_act1 + F_act2) / 40.0", unit = "-" } }

[plant]
kind = "rig-velocity"
options = { scale = "s" }

[inputs.F_fix]
to = "force"
gain = 2.0
unit = "N"

[fit]
input = "x"
output = "F"
per_record = ["offset"]

[[records]]
file = "a.npz"
window = [0.0, 0.5]

[[records]]
file = "b.npz"
weight = 2.0

[validate]
initial = [0.0]
warmup = 0.1
'''


def test_spec_records_derived_columns_and_inputs(tmp_path):
    _damper_files(tmp_path)
    np.savez(tmp_path / "a.npz", **{**np.load(tmp_path / "a.npz"), "F_fix": np.zeros(101)})
    spec = load_spec(_spec(tmp_path, SPEC))
    recs = spec.fit_data()
    assert [len(r) for r in recs] == [51, 101]
    np.testing.assert_allclose(recs[0]["s"], 0.5)
    np.testing.assert_allclose(recs[1]["s"], 1.5)
    assert recs[0].units["s"] == "-"
    assert spec.weights() == [1.0, 2.0]
    assert spec.inputs[0].column == "F_fix" and spec.inputs[0].gain == 2.0
    from clutchsim.friction import make_model
    assert spec.validation_initial(make_model("lugre")).tolist() == [0.0]


def test_spec_bad_input_names_file_line_and_key(tmp_path):
    _damper_files(tmp_path)
    from clutchsim.friction import make_model
    # a declared input column that no record has (line of [inputs.F_fix])
    spec = load_spec(_spec(tmp_path, SPEC))
    with pytest.raises(ValueError, match=r"s.toml:9: \[inputs.F_fix\]: declared input column "
                                         r"'F_fix' \(to force\) is in none of the records "
                                         r"\(fitting: .*a.npz, .*b.npz\); columns: F, F_act1"):
        spec.check_inputs(spec.fit_data())
    # an initial state of the wrong size
    with pytest.raises(ValueError, match=r"s.toml:28: \[validate\] initial has 1 entries; "
                                         r"gms has 4 state"):
        spec.validation_initial(make_model("gms"))
    # a derived expression naming an unknown column
    bad = SPEC.replace("(F_act1 + F_act2)", "(F_act1 + F_act3)")
    with pytest.raises(ValueError, match=r"s.toml:3: \[data\] s: derived column .* unknown "
                                         r"column 'F_act3'"):
        load_spec(_spec(tmp_path, bad)).fit_data()
    # records at different sampling rates: refused, the second record's file line named
    mixed = SPEC.replace('file = "b.npz"', 'file = "c.npz"').replace("[inputs.F_fix]\nto = "
                                                                     '"force"\ngain = 2.0\n'
                                                                     'unit = "N"\n', "")
    with pytest.raises(ValueError, match=r"s.toml:20: \[\[records\]\] #2 file: .*c.npz is "
                                         r"sampled every 0.02 s.*refused, not resampled"):
        load_spec(_spec(tmp_path, mixed)).fit_data()
    # an input target the plant does not have
    wrong = SPEC.replace('to = "force"', 'to = "controller"')
    with pytest.raises(ValueError, match=r"s.toml:10: \[inputs.F_fix\] to: to = 'controller' "
                                         r"is not available for plant 'rig-velocity'"):
        load_spec(_spec(tmp_path, wrong))
    # one record in [data] file, the column only in a validation record (the EMPS estimation
    # record and a record with disturbance pulses): fine; in neither: refused
    one = load_spec(_spec(tmp_path, SPEC.split("[[records]]")[0].replace(
        "[data]\n", '[data]\nfile = "b.npz"\n')))
    np.savez(tmp_path / "f.npz", **{**np.load(tmp_path / "a.npz"), "F_fix": np.zeros(101)})
    one.check_inputs(one.fit_data(), [one.read(tmp_path / "f.npz")])
    with pytest.raises(ValueError, match=r"s.toml:10: \[inputs.F_fix\]: .* none of the records "
                                         r"\(fitting: .*b.npz; validation: .*a.npz\)"):
        one.check_inputs(one.fit_data(), [one.read(tmp_path / "a.npz")])
    with pytest.raises(ValueError, match=r"\[\[records\]\] #1 wieght: unknown key 'wieght'"):
        load_spec(_spec(tmp_path, SPEC.replace("window = [0.0, 0.5]", "wieght = 1")))
