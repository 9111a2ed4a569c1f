"""JSON documents -> tables, status, parameters and solver statistics."""

from __future__ import annotations

from clutchsim.report.tables import MISSING, analyse
from clutchsim.report.units import label, split_unit


def test_models_become_rows_and_metrics_columns():
    doc = {"scenario": "launch", "models": {
        "lugre": {"completed": True, "message": "ok", "lockup_time_s": 1.5, "slip_energy_J": 2e4},
        "coulomb": {"completed": False, "message": "chatter", "slip_energy_J": 1e4,
                    "extra_rpm": 800.0}}}
    sec = analyse("summary.json", doc)
    kv, models = sec.tables
    assert kv.rows == (("scenario", "launch"),) and kv.units_from == "rows"
    assert models.title == "summary.json › models" and models.row_label == "model"
    assert models.columns == ("lockup_time_s", "slip_energy_J", "extra_rpm")
    assert models.rows[0] == ("lugre", 1.5, 2e4, MISSING)
    assert models.rows[1][0] == "coulomb" and models.failed == {1}
    assert [(s.where, s.ok, s.message) for s in sec.status] == [
        ("summary.json › models › lugre", True, "ok"),
        ("summary.json › models › coulomb", False, "chatter")]


def test_deeper_nesting_gives_one_table_per_sub_key():
    doc = {"benchmark": "drift", "results": {
        m: {"D1": {"drift_m": 1e-3}, "D2": {"drift_m": 2e-3, "rate_mps": 1e-5}}
        for m in ("lugre", "elastoplastic")}}
    titles = {t.title: t for t in analyse("bench.json", doc).tables}
    d2 = titles["bench.json › results › D2"]
    assert d2.columns == ("drift_m", "rate_mps")
    assert [r[0] for r in d2.rows] == ["lugre", "elastoplastic"]
    assert "bench.json › results › D1" in titles


def test_solver_statistics_warnings_and_meta_are_moved_out():
    doc = {"kind": "fit", "command": "clutchsim fit x.csv", "status": "failed",
           "message": "diverged", "warnings": ["at bound: sigma0"],
           "steps": 10, "rhs_evals": 99, "wall_s": 0.5, "nrmse": 0.1}
    sec = analyse("fit.json", doc)
    assert sec.meta == {"kind": "fit", "command": "clutchsim fit x.csv"}
    assert sec.status[0].ok is False and sec.status[0].message == "diverged"
    assert sec.warnings == [("fit.json", "at bound: sigma0")]
    assert sec.stats == [("fit.json", {"steps": 10, "rhs_evals": 99, "wall_s": 0.5})]
    assert sec.tables[0].rows == (("nrmse", 0.1),)


def test_parameter_tables_join_stderr_and_units():
    doc = {"parameters": {"F_c": 1.0, "F_s": 1.5}, "stderr": {"F_c": 0.1, "F_s": 0.2}}
    sec = analyse("fit.json", doc)
    (p,) = sec.parameters
    assert p.columns == ("value", "stderr")
    assert p.rows == (("F_c", 1.0, 0.1), ("F_s", 1.5, 0.2))
    assert not sec.tables          # stderr is not repeated as a metrics table

    doc = {"parameters": {"engine": {"J_e": {"value": 0.2, "unit": "kg m^2", "source": "S"}},
                          "vehicle": [{"name": "mass_kg", "value": 1500, "source": "cat."}]}}
    tables = {t.title: t for t in analyse("p.json", doc).parameters}
    eng = tables["p.json › parameters › engine"]
    assert eng.columns == ("value", "unit", "source")
    assert eng.rows == (("J_e", 0.2, "kg m^2", "S"),)
    veh = tables["p.json › parameters › vehicle"]
    assert veh.rows == (("mass_kg", 1500, "kg", "cat."),)   # unit from the name suffix


def test_units_from_names():
    assert split_unit("lockup_time_s") == ("lockup_time", "s")
    assert label("peak_heat_node_temp_C") == ("peak heat node temp", "°C")
    assert label("engine_speed_min_rpm") == ("engine speed min", "rpm")
    for symbol in ("F_s", "v_s", "F_c", "sigma0", "energy_balance_rel"):
        assert split_unit(symbol)[1] is None


def test_a_fault_that_never_struck_says_so():
    """summary.json keeps null for a triggered fault that never struck; the report's fault
    table says "not struck" (a null elsewhere stays an empty "—")."""
    doc = {"faults": [{"component": "clutch", "kind": "friction_clutch",
                       "fault": "capacity x 0.5 when the first heat node passes 180 °C",
                       "time_s": None},
                      {"component": "damper", "kind": "spring_damper",
                       "fault": "stiffness x 0.2 at t = 1 s", "time_s": 1.0}],
           "other": [{"name": "a", "time_s": None}, {"name": "b", "time_s": 2.0}]}
    sec = analyse("summary.json", doc)
    faults = next(t for t in sec.tables if t.title == "summary.json › faults")
    col = faults.columns.index("time_s") + 1
    assert [r[col] for r in faults.rows] == ["not struck", 1.0]
    other = next(t for t in sec.tables if t.title == "summary.json › other")
    assert [r[other.columns.index("time_s") + 1] for r in other.rows] == [None, 2.0]
    assert doc["faults"][0]["time_s"] is None
