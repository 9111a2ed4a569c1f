"""The house has one direction: scripts/import_graph.py finds no upward import and no cycle
across packages in src/, and it does find them in a tree that has them."""

from __future__ import annotations

import importlib.util
import json
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "scripts" / "import_graph.py"


def _load():
    spec = importlib.util.spec_from_file_location("import_graph", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _tree(tmp_path: Path, files: dict[str, str]) -> Path:
    for name, text in files.items():
        path = tmp_path / "clutchsim" / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    return tmp_path


def test_src_has_no_upward_import_and_no_cycle_across_packages():
    out = subprocess.run([sys.executable, str(SCRIPT), "--json", "--src", str(ROOT / "src")],
                         check=False, capture_output=True, text=True, timeout=120)
    report = json.loads(out.stdout)
    assert report["upward"] == [] and report["upward_imports"] == 0
    assert report["cycles_across_packages"] == 0 and report["package_cycles"] == 0
    # every remaining cycle lies inside one package
    for cycle in report["cycle_list"]:
        assert len({m.split(".")[1] for m in cycle}) == 1, cycle
    assert out.returncode == 0
    assert report["modules"] > 100 and report["arrows"] > 20


def test_an_upward_import_a_lazy_one_and_a_cycle_are_found(tmp_path):
    graph = _load()
    src = _tree(tmp_path, {
        "__init__.py": "",
        "core/__init__.py": "",
        # lazy, inside a function: still an edge (core is below report)
        "core/result.py": "def html(r):\n    from ..report import page\n    return page(r)\n",
        "report/__init__.py": "from .page import page\n",
        "report/page.py": "from ..core import result\n\ndef page(r):\n    return ''\n",
        "_util.py": "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n"
                    "    from .core import result\n",
    })
    report = graph.analyse(src)
    assert [(u["from"], u["to"], u["lazy"]) for u in report["upward"]] == \
        [("clutchsim.core.result", "clutchsim.report.page", True)]
    # core.result -> report -> report.page -> core.result: one cycle over two packages;
    # the TYPE_CHECKING import of _util is not an edge
    assert report["cycles_across_packages"] == 1 and report["package_cycles"] == 1
    assert graph.failed(report)
    assert "clutchsim._util" not in {m for c in report["cycle_list"] for m in c}


def test_a_dynamic_import_is_an_edge_and_an_unplaced_package_is_refused(tmp_path):
    graph = _load()
    src = _tree(tmp_path, {
        "__init__.py": "",
        "cli.py": "import importlib\n\ndef load(n):\n"
                  "    return importlib.import_module(f'.commands.{n}', __package__)\n",
        "commands/__init__.py": "",
        "commands/run.py": "from ..cli import load\n",
    })
    report = graph.analyse(src)
    assert [(u["from"], u["to"]) for u in report["upward"]] == \
        [("clutchsim.commands.run", "clutchsim.cli")]
    assert report["package_cycles"] == 1
    _tree(tmp_path, {"attic/__init__.py": ""})
    try:
        graph.analyse(src)
    except SystemExit as exc:
        assert "attic" in str(exc) and "FLOORS" in str(exc)
    else:
        raise AssertionError("a package without a floor was accepted")
