"""build_report writes atomically; the CLI's exit codes."""

from __future__ import annotations

import json

import pytest

from clutchsim.cli import main
from clutchsim.report import build_report, gather


def test_atomic_write_leaves_no_temporary(run_dir, monkeypatch):
    path = build_report(run_dir)
    assert path == run_dir / "report.html"
    assert not [p for p in run_dir.iterdir() if p.name.endswith(".tmp")]
    before = path.read_text(encoding="utf-8")

    def boom(data):
        raise RuntimeError("renderer failed")
    monkeypatch.setattr("clutchsim.report.build.render", boom)
    with pytest.raises(RuntimeError):
        build_report(run_dir)
    assert path.read_text(encoding="utf-8") == before     # old report untouched
    assert not [p for p in run_dir.iterdir() if p.name.endswith(".tmp")]


def test_kind_and_title(tmp_path):
    for name, kind in (("summary.json", "run"), ("bench.json", "bench"), ("fit.json", "fit")):
        d = tmp_path / kind
        d.mkdir()
        (d / name).write_text(json.dumps({"x_s": 1.0}))
        data = gather(d)
        assert data.kind == kind and data.title == f"clutchsim {kind} report: {kind}"
    (tmp_path / "run" / "other.json").write_text(json.dumps({"kind": "sweep"}))
    assert gather(tmp_path / "run").kind == "sweep"
    assert gather(tmp_path / "run", title="T").title == "T"


def test_cli(run_dir, tmp_path, capsys):
    assert main(["report", str(run_dir)]) == 0
    assert capsys.readouterr().out.strip() == str(run_dir / "report.html")
    assert main(["report", str(run_dir), "--json", "--title", "Mine"]) == 0
    assert json.loads(capsys.readouterr().out) == {"report": str(run_dir / "report.html")}
    assert "<title>Mine</title>" in (run_dir / "report.html").read_text(encoding="utf-8")

    empty = tmp_path / "empty"
    empty.mkdir()
    (empty / "report.html").write_text("old")          # a report alone is still empty
    mine = tmp_path / "mine"                            # a folder clutchsim did not write
    mine.mkdir()
    (mine / "notes.json").write_text("{}")
    for bad, words in ((tmp_path / "missing", "does not exist"), (empty, "is empty"),
                       (run_dir / "summary.json", "is a file"),
                       (mine, "is not a clutchsim output directory")):
        assert main(["report", str(bad)]) == 2
        err = capsys.readouterr().err
        assert words in err and len(err.strip().splitlines()) == 1
