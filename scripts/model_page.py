#!/usr/bin/env python
"""Write the documentation page of a registered friction model from its declarations.

    python scripts/model_page.py NAME            # write docs/models/NAME.md (a new page)
    python scripts/model_page.py NAME --force    # overwrite an existing page
    python scripts/model_page.py --tables        # every page's Parameters table, again

The page (``docs/models/<name>.md``) gets the model's docstring, its states, events,
parameters with their units in both domains, its parameter sets with their domains and
sources, the citation and a usage example, all read from the class and the parameter
files; the ``## Phenomena`` section is left for ``scripts/phenomena_matrix.py --new``,
which measures the model and fills it in.  Part of the recipe for a new model
(``docs/models/README.md``).  The page is written atomically; an existing page (which may
hold hand-written text) is kept unless ``--force``.
"""

from __future__ import annotations

import argparse
import inspect
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

from clutchsim._util import atomic_write
from clutchsim.benchmarks.phenomena import BEGIN_MARKER, END_MARKER
from clutchsim.friction import get_model_class, list_parameter_sets, load_parameter_set

DOCS = ROOT / "docs" / "models"
CONVENTIONS = ("Conventions (all models): `v` is the slip velocity, `F` the friction force "
               "transmitted in the direction of `v` (the sliding body sees −F), `F_e` the "
               "stick force computed by the plant, and `scale ≥ 0` the capacity multiplier; "
               "the same object works translationally (N, m, m/s) and rotationally (N·m, "
               "rad, rad/s) (see `clutchsim.friction.base`).")
SETS_NOTE = ("Each file in `src/clutchsim/params/friction/` records the source, units and "
             "caveats of its numbers (`clutchsim models NAME` lists the sets).")


def _value(v) -> str:
    return str(v) if isinstance(v, (list, str)) else f"{v:g}"


def parameter_table(cls) -> list[str]:
    """The Markdown table of a model's parameters: units in both domains, the rule its
    construction checks, the description (all from the class's ``parameters(...)``)."""
    lines = ["| parameter | translational | rotational | rule | description |",
             "|---|---|---|---|---|"]
    for p, (_kind, text) in cls.parameter_info.items():
        rule, text = (cls.parameter_rules.get(p, "") or "–",
                      text.replace("|", r"\|"))
        lines.append(f"| `{p}` | {cls.unit_of(p)} | {cls.unit_of(p, 'rotational')} | {rule} | "
                     f"{text} |")
    return lines


def refresh_tables(pages: dict[str, str]) -> dict[str, str]:
    """``pages`` (model name -> page text) with each page's Parameters table rewritten from
    the declarations (pure; the rest of a page, hand-written text included, is kept)."""
    out = {}
    for name, text in pages.items():
        lines = text.split("\n")
        start = lines.index("## Parameters") + 2
        end = start
        while end < len(lines) and lines[end].startswith("|"):
            end += 1
        out[name] = "\n".join(lines[:start] + parameter_table(get_model_class(name))
                              + lines[end:])
    return out


def render_page(name: str) -> str:
    """The Markdown page of model ``name`` (pure: reads only declarations and data)."""
    cls = get_model_class(name)
    model = cls.from_parameters(cls.default_parameter_set)
    doc = inspect.getdoc(cls) or ""
    summary, _, rest = doc.partition("\n\n")
    body = rest.split("\nParameters\n----------")[0].strip()
    equation = ""
    if summary.endswith("::"):          # the docstring's literal block: the equation
        summary = summary[:-2] + "."
        equation, _, body = body.partition("\n\n")
    lines = [f"# `{name}` — {cls.__name__}", "", summary, ""]
    if equation or body:
        lines += ["## Equations", ""]
        lines += ["```", equation.strip(), "```", ""] if equation else []
        lines += [body.replace("``", "`"), ""] if body else []
    lines += [CONVENTIONS, "",
              f"Jacobian: analytic (`{cls.kernels.jacobian.__name__}`).", "",
              "## States", ""]
    states = model.state_names()
    lines += [", ".join(f"`{s}`" for s in states) if states else "None (static map).", ""]
    lines += ["## Events", ""]
    events = model.event_names()
    lines += [", ".join(f"`{e}`" for e in events) if events else "None.", ""]
    lines += ["## Parameters", "", *parameter_table(cls), "", "## Parameter sets", ""]
    for set_name in list_parameter_sets(name):
        pset = load_parameter_set(set_name)
        default = " (default)" if set_name == cls.default_parameter_set else ""
        values = ", ".join(f"{k} = {_value(v)}" for k, v in pset.parameters.items())
        lines.append(f"* `{set_name}`{default}, **{pset.domain}** "
                     f"({pset.describe_domain().split('(')[-1].rstrip(')')}): {values}. "
                     f"Source: {pset.meta.get('source', '')}")
    lines += ["", SETS_NOTE, "",
              "## Phenomena", "", BEGIN_MARKER,
              "Not measured yet: run `scripts/phenomena_matrix.py --new`.", END_MARKER, "",
              "## Reference", "", cls.citation, "",
              "## Usage", "", "```python", "from clutchsim.friction import make_model", "",
              f"model = make_model({name!r})            # default parameter set",
              "F = model.steady_state_force([-0.01, 0.01])", "```", ""]
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("name", nargs="?", help="registry name of the model")
    ap.add_argument("--force", action="store_true", help="overwrite an existing page")
    ap.add_argument("--tables", action="store_true",
                    help="rewrite the Parameters table of every existing page instead")
    args = ap.parse_args(argv)
    if args.tables:
        pages = {p.stem: p.read_text(encoding="utf-8") for p in sorted(DOCS.glob("*.md"))
                 if p.stem != "README"}
        for name, text in refresh_tables(pages).items():
            if text != pages[name]:
                atomic_write(DOCS / f"{name}.md",
                             lambda tmp, t=text: tmp.write_text(t, encoding="utf-8", newline="\n"))
                print(f"wrote {DOCS / f'{name}.md'}", file=sys.stderr)
        return 0
    if not args.name:
        ap.error("give a model NAME (or --tables)")
    try:
        text = render_page(args.name)
    except ValueError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    path = DOCS / f"{args.name}.md"
    if path.exists() and not args.force:
        print(f"error: {path} exists (it may hold hand-written text); --force overwrites it",
              file=sys.stderr)
        return 2
    atomic_write(path, lambda tmp: tmp.write_text(text, encoding="utf-8", newline="\n"))
    print(f"wrote {path}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
