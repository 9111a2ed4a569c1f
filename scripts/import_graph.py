#!/usr/bin/env python
"""The import graph of ``src/clutchsim``: upward imports and cycles across packages.

    python scripts/import_graph.py            # summary; exit 1 on an upward import or a cross-package cycle
    python scripts/import_graph.py --list     # also every upward import site, cycle and arrow
    python scripts/import_graph.py --json     # one JSON document on stdout

Every ``import`` and ``from ... import`` statement of every module is an edge, at module
level or lazy (inside a function), and so is ``importlib.import_module(".commands." ...)``
with a literal (or f-string) prefix: a dependency hidden behind importlib is still one.
Imports under ``if TYPE_CHECKING:`` are left out (they never run).  Only edges inside
``clutchsim`` count; a target is resolved to the longest module path that exists
(``from .core import simulate`` is an edge to ``clutchsim.core.simulate`` when that is a
module, else to ``clutchsim.core``).

A *package* is the first name under ``clutchsim`` (``core``, ``durability``, ...); each
package sits on one floor of :data:`FLOORS`, listed bottom up.  An import from a lower
floor to a higher one is *upward*; imports within a floor are allowed (the floor's
members are siblings), and the cycle check below catches siblings leaning on each other.
An *arrow* is a distinct package -> package edge.  A *cycle* is a strongly connected set of
modules (Tarjan); it is *across packages* when its modules lie in more than one package.
Package-level cycles (``a -> b -> a`` through different modules) are reported too.
Stdlib only (``ast``), so it runs without the project installed.
"""

from __future__ import annotations

import argparse
import ast
import json
import sys
from collections import defaultdict
from pathlib import Path

ROOT = "clutchsim"

#: Floors, bottom up.  A package may import from its own floor and the floors below.
#: Where the top-level modules that are not named in the issue go, and why:
#:  - ``_version``, ``progress``, ``_cc`` (the system C compiler): no clutchsim imports;
#:    utilities.
#:  - ``params``: TOML data only (no Python), beside the utilities.
#:  - ``signal_expr`` (the signal expression language over core.signals), ``data``
#:    (measurement files; uses core.system.closest), ``rig`` (the one-DOF test rig built
#:    on core + friction): plain users of core, beside cgen above it.
#:  - ``durability``: a study (it runs scenarios), with the studies.
#:  - ``demo``: runs benchmarks and scenarios and builds a report: with report.
#:  - ``explore``: the launch explorer (a session over scenario runs and a Bokeh app
#:    drawing with plot): with report, below the commands.
#:  - ``__init__`` (lazy public API over every floor) and ``__main__``: with cli.
#:  - ``plot``: the issue puts it beside report, above the studies; but plot draws results
#:    and imports nothing of clutchsim but ``_util``, and the writers of the file bus
#:    (``scenario/outputs``, ``identify/outputs``, ``benchmarks/outputs``, a sweep's figure)
#:    call it.  It sits on the floor above analysis: computing never imports it (core,
#:    network, analysis are below it), and the writers above may draw.
FLOORS: tuple[tuple[str, ...], ...] = (
    ("_util", "_jit", "_cc", "_version", "progress", "params"),
    ("friction",),
    ("core",),
    ("cgen", "signal_expr", "data", "rig"),
    ("network",),
    ("analysis",),
    ("plot",),
    ("scenario",),
    ("studies", "sweeps", "durability", "fmu", "identify", "benchmarks"),
    ("report", "demo", "explore"),
    ("commands",),
    ("cli", "__init__", "__main__"),
)
#: Packages of earlier layouts (moved away since); listed so that an old checkout can be
#: measured with the same script, on the floor they were meant to have.
FORMER: dict[str, float] = {"driveline": 5.5}

FLOOR_OF: dict[str, float] = {p: i for i, floor in enumerate(FLOORS) for p in floor}
FLOOR_OF.update(FORMER)


def modules(src: Path) -> dict[str, Path]:
    """Every module of the package below ``src`` by dotted name (a package by its
    ``__init__``)."""
    out = {}
    for path in sorted((src / ROOT).rglob("*.py")):
        parts = path.relative_to(src).with_suffix("").parts
        if parts[-1] == "__init__" and len(parts) > 1:
            parts = parts[:-1]
        out[".".join(parts)] = path
    return out


def package(module: str) -> str:
    """``clutchsim.core.result`` -> ``core``; the package's own ``__init__`` is ``__init__``."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "__init__"


def _resolve(name: str, known: dict[str, Path]) -> str | None:
    """The longest existing module on ``name``'s path (None outside clutchsim)."""
    parts = name.split(".")
    if parts[0] != ROOT:
        return None
    while parts:
        if ".".join(parts) in known:
            return ".".join(parts)
        parts.pop()
    return None


def _base(module: str, is_package: bool, level: int) -> str:
    """The package a relative import of ``level`` dots in ``module`` starts from."""
    parts = module.split(".")
    if not is_package:
        parts = parts[:-1]
    return ".".join(parts[:len(parts) - (level - 1)] if level > 1 else parts)


def _type_checking_nodes(tree: ast.AST) -> set[int]:
    skip = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            for inner in node.body:
                skip.update(id(n) for n in ast.walk(inner))
    return skip


def _dynamic_prefix(call: ast.Call) -> str | None:
    """The literal start of ``importlib.import_module(<here>, ...)``'s first argument."""
    func = call.func
    name = func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", None)
    if name != "import_module" or not call.args:
        return None
    arg = call.args[0]
    if isinstance(arg, ast.Constant) and isinstance(arg.value, str):
        return arg.value
    if isinstance(arg, ast.JoinedStr) and arg.values and isinstance(arg.values[0], ast.Constant):
        return str(arg.values[0].value)
    return None


def edges_of(module: str, path: Path, known: dict[str, Path]) -> list[dict]:
    """The clutchsim imports of one module: ``{"to", "line", "lazy"}`` each, one per
    statement and target (``from ..cli import A, B`` is one edge)."""
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    skip = _type_checking_nodes(tree)
    is_package = path.name == "__init__.py"
    lazy_ids = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
            lazy_ids.update(id(n) for n in ast.walk(node) if n is not node)
    found = []

    seen = set()

    def add(target: str | None, node: ast.AST) -> None:
        if target is not None and target != module and (target, node.lineno) not in seen:
            seen.add((target, node.lineno))
            found.append({"to": target, "line": node.lineno, "lazy": id(node) in lazy_ids})

    for node in ast.walk(tree):
        if id(node) in skip:
            continue
        if isinstance(node, ast.Import):
            for alias in node.names:
                add(_resolve(alias.name, known), node)
        elif isinstance(node, ast.ImportFrom):
            base = (_base(module, is_package, node.level) if node.level else "")
            stem = ".".join(p for p in (base, node.module or "") if p)
            for alias in node.names:
                add(_resolve(f"{stem}.{alias.name}", known) or _resolve(stem, known), node)
        elif isinstance(node, ast.Call):
            prefix = _dynamic_prefix(node)
            if prefix is None:
                continue
            if prefix.startswith("."):
                level = len(prefix) - len(prefix.lstrip("."))
                rest = prefix[level:].strip(".")
                base = _base(module, is_package, level)
                prefix = ".".join(p for p in (base, rest) if p)
            add(_resolve(prefix.strip("."), known), node)
    return found


def _strongly_connected(graph: dict[str, set[str]]) -> list[list[str]]:
    """Tarjan's strongly connected components with more than one node (iterative)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    on_stack: set[str] = set()
    stack: list[str] = []
    out: list[list[str]] = []
    counter = 0
    for root in sorted(graph):
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = counter
        counter += 1
        stack.append(root)
        on_stack.add(root)
        while work:
            node, children = work[-1]
            for child in children:
                if child not in index:
                    index[child] = low[child] = counter
                    counter += 1
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(graph.get(child, ())))))
                    break
                if child in on_stack:
                    low[node] = min(low[node], index[child])
            else:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[node])
                if low[node] == index[node]:
                    component = []
                    while True:
                        member = stack.pop()
                        on_stack.discard(member)
                        component.append(member)
                        if member == node:
                            break
                    if len(component) > 1:
                        out.append(sorted(component))
    return sorted(out)


def analyse(src: Path) -> dict:
    """The graph's numbers and findings for the tree below ``src`` (a ``src/`` folder)."""
    known = modules(src)
    unplaced = sorted({package(m) for m in known} - set(FLOOR_OF))
    if unplaced:
        raise SystemExit(f"import_graph: package(s) {', '.join(unplaced)} have no floor; "
                         "add them to FLOORS in scripts/import_graph.py")
    graph: dict[str, set[str]] = {m: set() for m in known}
    upward, arrows = [], set()
    n_edges = 0
    for module, path in known.items():
        for edge in edges_of(module, path, known):
            n_edges += 1
            graph[module].add(edge["to"])
            src_pkg, dst_pkg = package(module), package(edge["to"])
            if src_pkg != dst_pkg:
                arrows.add((src_pkg, dst_pkg))
            if FLOOR_OF[src_pkg] < FLOOR_OF[dst_pkg] and src_pkg != "__init__":
                upward.append({"from": module, "line": edge["line"], "to": edge["to"],
                               "lazy": edge["lazy"], "file": str(path.relative_to(src))})
    cycles = _strongly_connected(graph)
    across = [c for c in cycles if len({package(m) for m in c}) > 1]
    package_graph: dict[str, set[str]] = defaultdict(set)
    for a, b in arrows:
        package_graph[a].add(b)
    package_cycles = _strongly_connected(dict(package_graph))
    return {
        "modules": len(known), "packages": len({package(m) for m in known}),
        "import_statements": n_edges, "arrows": len(arrows),
        "upward_imports": len(upward), "upward_package_pairs":
            len({(package(u["from"]), package(u["to"])) for u in upward}),
        "cycles": len(cycles), "cycles_across_packages": len(across),
        "package_cycles": len(package_cycles),
        "upward": upward, "cycle_list": cycles, "package_cycle_list": package_cycles,
        "arrow_list": sorted(f"{a} -> {b}" for a, b in arrows),
    }


def failed(report: dict) -> bool:
    """The rule: no upward import, no module cycle across packages, no package cycle."""
    return bool(report["upward_imports"] or report["cycles_across_packages"]
                or report["package_cycles"])


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--src", type=Path, default=Path(__file__).resolve().parent.parent / "src",
                   help="the src/ folder that holds clutchsim (default: this checkout's)")
    p.add_argument("--list", action="store_true", help="list every finding and arrow")
    p.add_argument("--json", action="store_true", help="print one JSON document")
    args = p.parse_args(argv)
    if not (args.src / ROOT).is_dir():
        print(f"import_graph: --src {args.src}: no {ROOT}/ package there", file=sys.stderr)
        return 2
    report = analyse(args.src)
    if args.json:
        print(json.dumps(report, indent=1))
        return int(failed(report))
    print(f"{report['modules']} modules in {report['packages']} packages, "
          f"{report['import_statements']} import statements, {report['arrows']} arrows; "
          f"upward imports {report['upward_imports']} "
          f"({report['upward_package_pairs']} package pairs); cycles {report['cycles']} "
          f"({report['cycles_across_packages']} across packages); "
          f"package cycles {report['package_cycles']}")
    for u in report["upward"]:
        print(f"  upward: {u['file']}:{u['line']} -> {u['to']}"
              f"{' (lazy)' if u['lazy'] else ''}")
    for c in report["cycle_list"]:
        print(f"  cycle: {' <-> '.join(c)}")
    for c in report["package_cycle_list"]:
        print(f"  package cycle: {' <-> '.join(c)}")
    if args.list:
        for a in report["arrow_list"]:
            print(f"  arrow: {a}")
    return int(failed(report))


if __name__ == "__main__":
    sys.exit(main())
