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
