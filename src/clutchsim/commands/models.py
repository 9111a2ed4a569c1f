"""``clutchsim models``: list the friction models with states, parameters and citations."""

from __future__ import annotations

from ._common import command_parser, emit_json

HELP = """\
examples:
  clutchsim models                 # a table of every model
  clutchsim models --json          # {"models": [{"name", "states", "parameters",
                                   #   "parameter_sets", "citation", ...}]}
  clutchsim models lugre           # one model: default values, its parameter sets
  clutchsim models mykhailevych2020 --domain rotational    # units of a clutch
"""


def register(sub, common):
    p = command_parser(sub, common, "models", help="list the friction models",
                       description="List the friction models: states, parameters (units, "
                       "default values), the parameter sets usable with each (with their "
                       "domain: translational N, m, m/s or rotational N·m, rad, rad/s) and "
                       "the citation.", epilog=HELP)
    p.add_argument("name", nargs="?", help="show one model only")
    p.add_argument("--domain", choices=("translational", "rotational"), default="translational",
                   help="units to show (default: translational)")
    p.add_argument("--json", action="store_true", help="print one JSON document")


def run(args) -> int:
    from ..friction import describe_models, get_model_class, make_model
    from ..friction.params import DOMAIN_UNITS
    models = describe_models(domain=args.domain)
    if args.name:
        cls = get_model_class(args.name)   # unknown names: ValueError with the valid list
        models = [m for m in models if m["name"] == cls.name]
    if args.json:
        emit_json({"domain": args.domain, "models": models})
        return 0
    for m in models:
        print(f"{m['name']}")
        print(f"  states:     {', '.join(m['states']) or '(none)'}")
        caveats = [s for s in m["parameter_sets"] if s.get("caveat")]
        for s in caveats:
            print(f"  NOTE ({s['name']}): {s['caveat']}")
        shown = _defaults_for(m, args.domain)
        if shown["domain"] == args.domain:
            head = f"value in set {shown['name']}" + (
                "" if shown["default"] else f" (the model's default set "
                f"{m['default_parameter_set']} is {m['default_domain']})")
        else:
            head = (f"value in the default set {shown['name']} ({shown['domain']} numbers: "
                    f"{m['name']} has no {args.domain} set)")
        print(f"  parameters [{args.domain} units], {head}:")
        for par in m["parameters"]:
            unit = f"[{par['unit']}]"
            value = getattr(make_model(m["name"], shown["name"]), par["name"])
            print(f"    {par['name']:<10} {unit:<12} {_value(value):>12}  {par['description']}")
        print("  parameter sets:")
        for s in m["parameter_sets"]:
            mark = "default, " if s["default"] else ""
            values = ", ".join(f"{k} = {_value(v)}" for k, v in s["parameters"].items())
            print(f"    {s['name']} ({mark}{s['domain']}: {DOMAIN_UNITS[s['domain']]}): "
                  f"{values}")
        print(f"  citation:   {m['citation']}")
        print()
    return 0


def _defaults_for(m: dict, domain: str) -> dict:
    """The set whose values the table shows: the default set, or in the other domain the
    model's first set of that domain (if it has one)."""
    sets = m["parameter_sets"]
    default = next(s for s in sets if s["default"])
    if default["domain"] == domain:
        return default
    return next((s for s in sets if s["domain"] == domain), default)


def _value(v) -> str:
    if isinstance(v, list):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    if isinstance(v, float):
        return f"{v:g}"
    return str(v)
