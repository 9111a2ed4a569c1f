"""A run's warnings reach summary.json and the report, visibly (a real ringing run)."""

from __future__ import annotations

import json
from pathlib import Path

from clutchsim.report import build_report
from clutchsim.report.tables import analyse
from clutchsim.scenario import load_scenario
from clutchsim.scenario.outputs import write_runs

LAUNCH = Path(__file__).resolve().parents[2] / "examples" / "launch.toml"
F = "coupling[0].friction.overrides."


def test_warnings_of_every_run_are_in_the_summary_and_the_report(tmp_path):
    sc = load_scenario(LAUNCH, overrides=[F + "T_stat=360", F + "k_din=0.8",
                                          F + "omega0=1.0"])
    write_runs(sc, ["mykhailevych2020", "coulomb-robust"], tmp_path, plots=False)
    summary = json.loads((tmp_path / "summary.json").read_text())
    judder, robust = summary["models"]["mykhailevych2020"], summary["models"]["coulomb-robust"]
    assert judder["outcome"] == "completed" and len(judder["warnings"]) == 3
    assert robust["warnings"] == []
    sections = analyse("summary.json", summary)
    entry = next(s for s in sections.status if s.where.endswith("mykhailevych2020"))
    assert entry.ok is True and entry.warnings == 3
    html = build_report(tmp_path).read_text(encoding="utf-8")
    assert "banner warn" in html and "1 with warnings" in html
    assert "completed · 3 warnings" in html
    for w in judder["warnings"]:
        assert w.split(":")[0].replace("'", "&#x27;") in html


def test_outcome_decides_the_status_not_the_message():
    doc = {"models": {"a": {"completed": True, "outcome": "completed", "message": "failed?"},
                      "b": {"outcome": "chatter", "message": "all fine"},
                      "c": {"outcome": "stalled", "message": ""}}}
    ok = {s.where.split(" › ")[1]: s.ok for s in analyse("x.json", doc).status}
    assert ok == {"a": True, "b": False, "c": False}
