"""Every value a network's equations read is in its records, with its unit: the
``parameters`` of a run's ``summary.json`` and the Parameters section of its report
(``Network.parameter_values``)."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest
from _fuzz import cases
from hypothesis import HealthCheck, given, settings

from clutchsim.network.components.friction import _FrictionElement
from clutchsim.scenario import load_scenario

EXAMPLES = sorted(p for p in (Path(__file__).parents[2] / "examples").glob("*.toml")
                  if not p.name.startswith("fit_"))

#: the tables a component is built with, by attribute, and the entry that must show them
TABLES = {"speeds": ("full_load", 0), "torques": ("full_load", 1),
          "speed_ratio": ("K", 0), "K": ("K", 1), "torque_ratio": ("torque_ratio", 1)}


def _check(net) -> None:
    pv = net.parameter_values()
    # a plain JSON document: finite numbers, strings, lists
    json.dumps(pv, allow_nan=False)
    assert list(pv) == [c.name for c in net.components]
    for c in net.components:
        rec = pv[c.name]
        for k, r in rec.items():
            assert set(r) >= {"value", "unit", "description"}, (c.name, k)
            assert r["value"] is not None, (c.name, k)        # no nulls in a summary
            assert r["description"], (c.name, k)
        for p in c.params:
            assert rec[p.name]["value"] == c.values[p.name], (c.name, p.name)
            assert rec[p.name]["unit"] == p.unit, (c.name, p.name)
        if isinstance(c, _FrictionElement):
            model = c.model
            assert rec["friction.model"]["value"] == model.name
            for f in dataclasses.fields(model):
                if getattr(model, f.name) is None:
                    assert f"friction.{f.name}" not in rec
                    continue
                r = rec[f"friction.{f.name}"]
                assert r["value"] == getattr(model, f.name), (c.name, f.name)
                if f.name in model.parameter_info:
                    assert r["unit"] == model.unit_of(f.name, c.domain or "rotational")
            for key in ("clamp_table", "mu_temperature", "mu_slip"):
                tab = getattr(c, key)
                assert (key in rec) == (tab is not None), (c.name, key)
                if tab is not None:
                    assert rec[key]["x"] == list(tab[0]) and rec[key]["y"] == list(tab[1])
        for attr, (key, col) in TABLES.items():
            if hasattr(c, attr) and isinstance(getattr(c, attr), tuple):
                assert rec[key]["xy"[col]] == list(getattr(c, attr)), (c.name, attr)
        if hasattr(c, "loss_columns") and not hasattr(c, "ratios"):
            speed, *cols = c.loss_columns
            for name, col in zip(("eta_mf1", "eta_mf2", "tau_bf1", "tau_bf2"), cols):
                r = rec[f"loss_table.{name}"]
                assert r["x"] == list(speed) and r["y"] == list(col)
        for r in rec.values():
            if "x" in r:
                assert len(r["x"]) == len(r["y"]) >= 1 and "→" in r["unit"]


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.stem)
def test_every_example_network_records_every_value_with_its_unit(path):
    sc = load_scenario(path)
    for model in sc.models or [None]:
        _check(sc.network(model))


@settings(max_examples=60, deadline=None, suppress_health_check=list(HealthCheck))
@given(case=cases())
def test_fuzzed_networks_record_every_value_with_its_unit(case):
    _check(case.network())


def test_a_table_entry_reads_as_its_points():
    from clutchsim.network.spec import table_entry
    e = table_entry("full-load curve", [0.0, 100.0], "rad/s", [0.0, 150.0], "N·m")
    assert e["value"] == "2 points: 0 → 0, 100 → 150" and e["unit"] == "rad/s → N·m"
    long = table_entry("t", np.arange(12.0), "s", np.arange(12.0) ** 2, "m")
    assert long["value"] == "12 points: 0 → 0, 1 → 1, 2 → 4, …, 9 → 81, 10 → 100, 11 → 121"
    assert long["x"] == list(np.arange(12.0))


def test_a_compared_run_lists_each_models_clutch_and_the_report_shows_them(tmp_path, capsys):
    """The default launch with two models: one table per shared component, the clutch
    once per model with its friction model's fields and units; ``report.html`` draws them
    in its Parameters section."""
    from clutchsim.cli import main
    from clutchsim.report.gather import gather
    out = tmp_path / "o"
    assert main(["run", "--model", "coulomb-robust", "--model", "mykhailevych2020",
                 "--set", "scenario.t_end=0.2", "-q", "--no-plots", "--out", str(out)]) == 0, \
        capsys.readouterr().err
    params = json.loads((out / "summary.json").read_text())["parameters"]
    assert "clutch" not in params
    assert params["clutch (mykhailevych2020)"]["friction.T_stat"]["unit"] == "N·m"
    assert params["clutch (coulomb-robust)"]["friction.model"]["value"] == "coulomb-robust"
    assert params["vehicle"]["mass"] == {"value": 1300.0, "unit": "kg",
                                         "description": "vehicle mass"}
    assert params["engine_torque"]["full_load"]["unit"] == "rad/s → N·m"
    data = gather(out)
    titles = [t.title for t in data.parameters]
    for name in params:
        assert any(t.endswith(name) for t in titles), (name, titles)
    table = next(t for t in data.parameters if t.title.endswith("clutch (mykhailevych2020)"))
    assert table.columns[:3] == ("value", "unit", "description")
    row = next(r for r in table.rows if r[0] == "friction.k_din")
    assert row[2] == "-"
