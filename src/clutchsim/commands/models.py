"""``clutchsim models``: list the friction models with states, parameters and citations."""

from __future__ import annotations

import argparse

from ..cli import emit_json

HELP = """\
examples:
  clutchsim models                 # a table of every model
  clutchsim models --json          # {"models": [{"name", "states", "parameters", "citation"}]}
  clutchsim models lugre           # one model in detail
"""


def register(sub, common):
    p = sub.add_parser("models", parents=[common], help="list the friction models",
                       description="List the friction models: states, parameters (units) "
                       "and citation.", epilog=HELP,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("name", nargs="?", help="show one model only")
    p.add_argument("--domain", choices=("translational", "rotational"), default="translational",
                   help="units to show (default: translational)")
    p.add_argument("--json", action="store_true", help="print one JSON document")


def run(args) -> int:
    from ..friction import describe_models, get_model_class
    models = describe_models()
    if args.name:
        cls = get_model_class(args.name)   # unknown names: ValueError with the valid list
        models = [m for m in models if m["name"] == cls.name]
    if args.domain == "rotational":
        rot = {m["name"]: m for m in describe_models(domain="rotational")} \
            if _accepts_domain(describe_models) else {}
        models = [rot.get(m["name"], m) for m in models]
    if args.json:
        emit_json({"models": models})
        return 0
    for m in models:
        print(f"{m['name']}")
        print(f"  states:     {', '.join(_fmt_state(s) for s in m['states']) or '(none)'}")
        for par in m["parameters"]:
            print(f"  {par['name']:<10} [{par['unit']}]  {par['description']}")
        print(f"  citation:   {m['citation']}")
        print()
    return 0


def _fmt_state(s):
    if isinstance(s, dict):
        return f"{s.get('name')} [{s.get('unit', '')}]"
    return str(s)


def _accepts_domain(fn):
    import inspect
    return "domain" in inspect.signature(fn).parameters
