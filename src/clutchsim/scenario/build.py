"""Scenario tables -> a network of components (errors carry the key path and line)."""

from __future__ import annotations

import math
import re
import warnings

from ..friction import domain_problem, get_model_class, make_model
from ..friction.base import SelfExcitedWarning
from . import chain_format, composites
from .schema import FRICTION_TYPES, LINING_KEYS, suggest

__all__ = ["build_network", "effective_model", "friction_model"]


def friction_model(spec: dict, model: str | None, key: str, fail, element: str = "",
                   domain: str = "rotational"):
    """The friction model of an element table ``spec`` (optionally another ``model``).

    The model's own entry (``model``, ``parameter_set``, ``overrides``) and an entry of
    ``alternatives`` (``{parameter_set = ..., key = value, ...}``) are read alike: the
    parameters not given come from the set (default: the model's own).  Every element of
    a scenario is rotational: a set of the other domain whose numbers would be read as
    N·m and rad/s is refused (:func:`clutchsim.friction.domain_problem`).
    """
    name = spec["model"] if model is None else model
    try:
        get_model_class(name)
    except ValueError as exc:
        fail(str(exc), f"{key}.model")
    if name == spec["model"]:
        entry = {k: v for k, v in spec.get("overrides", {}).items()}
        pset, where = spec.get("parameter_set"), key
        how = (f"{key}.parameter_set = \"NAME\"", f"{key}.overrides")
    else:
        alts = spec.get("alternatives", {})
        if name not in alts:
            fail(f"no parameters for model {name!r} on this element (available: "
                 f"{', '.join([spec['model'], *alts]) or 'none'}): add them to its "
                 f"friction table, e.g. friction = {{ model = \"{spec['model']}\", ..., "
                 f"alternatives = {{ {name} = {{ parameter_set = \"...\" }} }} }}",
                 f"{key}.alternatives")
        entry = dict(alts[name])
        pset, where = entry.pop("parameter_set", None), f"{key}.alternatives.{name}"
        how = (f"{where}.parameter_set = \"NAME\"", where)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", SelfExcitedWarning)
            built = make_model(name, pset, **entry)
    except (TypeError, ValueError, SelfExcitedWarning) as exc:
        fail(_in_domain(str(exc), name, domain), where)
    label = f"friction element {element!r}" if element else "this friction element"
    problem = domain_problem(built, domain, label, choose_set=how[0], give_params=how[1])
    if problem:
        fail(problem, where)
    return built


def _in_domain(message: str, model: str, domain: str) -> str:
    """A friction model's message with its ``<param> = <value> <unit>`` parts in the units
    of ``domain``: the models keep translational units (N, m/s), and on a clutch or brake
    the same parameters are N·m and rad/s (``F_s = 330 N`` reads ``F_s = 330 N·m``)."""
    if domain == "translational":
        return message
    cls = get_model_class(model)
    for param in cls.parameter_info:
        old, new = cls.unit_of(param), cls.unit_of(param, domain)
        if old != new:
            message = re.sub(rf"\b({re.escape(param)} = \S+) {re.escape(old)}(?![\w·/])",
                             rf"\1 {new}", message)
    return message


def _replaced(t, model, scenario) -> bool:
    """``--model`` acts on the clutch element and on every element listing it."""
    if model is None:
        return False
    return t["name"] == scenario.clutch or model in t["friction"].get("alternatives", {})


def effective_model(scenario, model: str | None) -> str | None:
    """``model``, or ``None`` when it changes nothing: every element it would act on
    already uses it as its own model (then the chain is the scenario's own)."""
    if model is None:
        return None
    for t in (*scenario.data.get("coupling", []), *scenario.data.get("brake", []),
              *(c for c in scenario.data.get("component", [])
                if c.get("type") in FRICTION_TYPES)):
        if "friction" not in t:
            if t.get("name") == scenario.clutch:
                return model        # a fixed switching law: building says it cannot
            continue
        if _replaced(t, model, scenario) and t["friction"].get("model") != model:
            return model
    return None


def _pairs(tab, a, b, key, fail):
    if tab is None:
        return None
    if set(tab) != {a, b}:
        fail(f"must be a table {{{a} = [...], {b} = [...]}}, got keys {sorted(tab)}", key)
    return (tab[a], tab[b])


def _runout(tab, key, fail):
    """``(amplitude, order)`` of a ``runout = {amplitude, order}`` table, or None."""
    if tab is None:
        return None
    if not isinstance(tab, dict) or set(tab) != {"amplitude", "order"}:
        got = sorted(tab) if isinstance(tab, dict) else repr(tab)
        fail(f"must be a table {{amplitude = ..., order = ...}}, got {got}", key)
    for k in ("amplitude", "order"):
        v = tab[k]
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            fail(f"= {v!r} must be a finite number", f"{key}.{k}")
    return (float(tab["amplitude"]), float(tab["order"]))


def _number_list(value, key, fail):
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        value = [value]
    if not isinstance(value, list) or not value or not all(
            isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)
            for x in value):
        fail(f"must be a non-empty list of finite numbers, got {value!r}", key)
    return [float(x) for x in value]


def loss_table(tab, key: str, fail) -> tuple:
    """Rows (speed, eta_mf1, eta_mf2, tau_bf1, tau_bf2) of a lossy-gear ``loss_table``
    table, checked column by column (errors name the entry, its value and the rule)."""
    from ..network.components.lossy_gear import LOSS_COLUMNS
    if tab is None:
        return ((0.0, 1.0, 1.0, 0.0, 0.0),)
    if not isinstance(tab, dict) or set(tab) != set(LOSS_COLUMNS):
        got = sorted(tab) if isinstance(tab, dict) else repr(tab)
        fail("must be a table {" + ", ".join(f"{c} = [...]" for c in LOSS_COLUMNS)
             + f"}}, got {got}", key)
    cols = {c: _number_list(tab[c], f"{key}.{c}", fail) for c in LOSS_COLUMNS}
    n = len(cols["speed"])
    for c in LOSS_COLUMNS[1:]:
        if len(cols[c]) != n:
            fail(f"has {len(cols[c])} entries, but speed has {n} (one value per speed)",
                 f"{key}.{c}")
    speed = cols["speed"]
    for i, w in enumerate(speed):
        if i == 0 and w < 0.0:
            fail(f"= {w:g} rad/s is out of range: must be >= 0 (the table is read at "
                 "|omega_a|)", f"{key}.speed[0]")
        if i > 0 and w <= speed[i - 1]:
            fail(f"= {w:g} rad/s must be greater than speed[{i - 1}] = {speed[i - 1]:g} rad/s "
                 "(strictly increasing)", f"{key}.speed[{i}]")
    for c in ("eta_mf1", "eta_mf2"):
        for i, v in enumerate(cols[c]):
            if not 0.0 < v <= 1.0:
                fail(f"= {v:g} is out of range: an efficiency must be in (0, 1] (0 cannot "
                     "transmit power)", f"{key}.{c}[{i}]")
    for c in ("tau_bf1", "tau_bf2"):
        for i, v in enumerate(cols[c]):
            if v < 0.0:
                fail(f"= {v:g} N·m is out of range: a bearing friction torque must be >= 0 "
                     "N·m", f"{key}.{c}[{i}]")
    return tuple(zip(*(cols[c] for c in LOSS_COLUMNS)))


def angle_states(scenario) -> bool:
    """``[outputs] angles``: angle (position) states of every inertia (mass)."""
    return bool(scenario.data.get("outputs", {}).get("angles", False))


def _check_signals(scenario, fail, comps, needs, where) -> None:
    """Every signal a component reads is an [inputs] entry or another component's signal
    (``<component>.<signal>``), and no signal is both."""
    from ..network.plant import produced_signals
    produced = produced_signals(comps)
    for name, (comp, _unit) in produced.items():
        if name in scenario.inputs:
            fail(f"signal {name!r} is produced by {comp.label} ({where[comp.name]}) "
                          "and also given here: a signal has one source (remove one)",
                          f"inputs.{name}")
    for name, key in needs:
        if name in produced or name in scenario.inputs:
            continue
        known = [*scenario.inputs, *produced]
        fail(f"signal {name!r} is neither defined in [inputs] nor produced by a "
                      f"component{suggest(name, known)}"
                      f"{'; signals: ' + ', '.join(known) if known else ''}", key)


def network_document(data: dict, fail):
    """The network tables of a scenario document: a chain file read as a network
    (:mod:`.chain_format`), composite tables expanded (:mod:`.composites`); with the
    ``fail(problem, key)`` that names the key the user wrote for a key of those tables, and
    the input signals the composites generate (name -> formula text)."""
    if chain_format.is_chain(data):
        chain = chain_format.rewrite(data)
        data = chain.data
        user_fail = fail

        def fail(problem, key=""):
            user_fail(problem, chain.chain_key(key))
    expansion = composites.expand(data, fail)
    if expansion.data is data:
        return data, fail, {}
    network_fail = fail

    def expanded_fail(problem, key=""):
        network_fail(problem, expansion.source_key(key))
    return expansion.data, expanded_fail, expansion.inputs


def build_network(scenario, model: str | None = None):
    """Build the :class:`~clutchsim.network.Network` of a scenario with ``model`` on its
    clutch element: its ``[[component]]`` tables and ``[network] connect``, or the tables
    of a chain file read as those (:mod:`clutchsim.scenario.chain_format`).  Errors name
    the table the user wrote (the chain's, through the rewrite's key map), its key and
    line."""
    from ..network import COMPONENTS, Network, NetworkError
    data, fail, _inputs = network_document(scenario.data, scenario.fail)
    if model is not None:
        for t in data.get("component", []):
            if t.get("name") == scenario.clutch and t.get("type") in ("one_way_clutch",
                                                                       "lossy_gear"):
                fail(f"model {model!r} cannot replace {t['name']!r}: a {t['type']} has a fixed "
                     "switching law, not a friction model (run it without --model)",
                     "scenario.clutch")

    comps = []
    where = {}
    needs = []              # (signal, key): checked once every component's signals are known
    for i, t in enumerate(data.get("component", [])):
        key = f"component[{i}]"
        kw = {k: v for k, v in t.items() if k not in ("type", "name")
              and not (t["type"] == "clutch" and k in LINING_KEYS)}
        cls = COMPONENTS[t["type"]]
        needs += [(kw[k], f"{key}.{k}") for k in getattr(cls, "signal_keys", ())
                  if isinstance(kw.get(k), str)]
        # friction elements with a friction model (a lossy gear's `friction` is a
        # property; a one-way clutch has its own law, below)
        if getattr(cls, "friction", False) is True and t["type"] not in (
                "one_way_clutch", "mass_with_stop_and_friction") and not getattr(
                cls, "own_law", False):
            if cls.commanded:
                needs.append((kw["command"], f"{key}.command"))
            m = model if _replaced(t, model, scenario) else None
            kw["model"] = friction_model(kw.pop("friction"), m, f"{key}.friction", fail,
                                         t["name"], cls.domain)
            for k, (a, b) in (("clamp_table", ("position", "force")),
                              ("mu_temperature", ("theta", "factor")),
                              ("mu_slip", ("slip", "factor"))):
                if k in kw:
                    kw[k] = _pairs(kw[k], a, b, f"{key}.{k}", fail)
            kw["heat"] = tuple((h.get("node"), h.get("share", 1.0)) for h in kw.get("heat", []))
            if "runout" in kw:
                kw["runout"] = _runout(kw["runout"], f"{key}.runout", fail)
            if "wear" in kw:
                from ..network.wear import WearLaw
                kw["wear"] = WearLaw.from_table(kw["wear"], fail, f"{key}.wear")
        elif getattr(cls, "own_law", False):     # a band brake's capstan law, a dog clutch
            needs.append((kw["command"], f"{key}.command"))
            if "heat" in kw:
                kw["heat"] = tuple((h.get("node"), h.get("share", 1.0)) for h in kw["heat"])
        elif t["type"] == "engine":
            needs.append((kw["throttle"], f"{key}.throttle"))
            fl = _pairs(kw.pop("full_load"), "speed", "torque", f"{key}.full_load", fail)
            kw["speeds"], kw["torques"] = fl
        elif t["type"] in ("torque", "force"):
            needs.append((kw["input"], f"{key}.input"))
        elif t["type"] == "torque_pulsation" and "amplitude_table" in kw:
            kw["amplitude_table"] = _pairs(kw["amplitude_table"], "speed", "amplitude",
                                           f"{key}.amplitude_table", fail)
        elif t["type"] in ("lossy_gear", "lossy_gear_with_lash"):
            kw["loss_table"] = loss_table(kw.get("loss_table"), f"{key}.loss_table", fail)
        elif t["type"] == "gearbox":
            kw["shifts"] = tuple((s.get("time"), s.get("gear")) for s in kw.get("shifts", []))
            n = len(kw["ratios"]) if isinstance(kw.get("ratios"), list) else None
            if n == 0:
                fail("= [] lists no gear: give at least one ratio [-] (gear 1 first), e.g. "
                     "ratios = [3.6, 2.1, 1.4, 1.0, 0.8]", f"{key}.ratios")
            if n and isinstance(kw.get("gear"), int) and not 1 <= kw["gear"] <= n:
                fail(f"gear {kw['gear']} does not exist: this gearbox has {n} gears (1..{n})",
                     f"{key}.gear")
        elif t["type"] == "one_way_clutch":
            needs.append((kw["command"], f"{key}.command"))
            kw["mu_temperature"] = _pairs(kw.get("mu_temperature"), "theta", "factor",
                                          f"{key}.mu_temperature", fail)
            kw["heat"] = tuple((h.get("node"), h.get("share", 1.0)) for h in kw.get("heat", []))
        elif t["type"] == "release_system":
            from ..network.components.release_system import monotone_spring
            for k, x in (("cushion", "compression"), ("spring", "deflection")):
                if k in kw:
                    kw[k] = _pairs(kw[k], x, "force", f"{key}.{k}", fail)
                    try:
                        monotone_spring(f"release system {t['name']!r}", k, *kw[k], x)
                    except ValueError as exc:
                        fail(str(exc), f"{key}.{k}")
        try:
            comps.append(cls(t["name"], **kw))
        except (TypeError, ValueError) as exc:
            # a component's error may name the key of its table it concerns (exc.key)
            sub = getattr(exc, "key", None)
            fail(str(exc), f"{key}.{sub}" if isinstance(sub, str) and sub in t else key)
        where[t["name"]] = key
        c = comps[-1]
        if getattr(c, "has_fault", False) and not c.values["fault_time"] < scenario.t_end:
            fail(f"= {c.values['fault_time']:g} s is outside the run: a fault strikes in "
                 f"[0, t_end) = [0, {scenario.t_end:g}) s", f"{key}.fault_time")
    _check_signals(scenario, fail, comps, needs, where)
    try:
        net = Network(comps, data["network"]["connect"], name=scenario.name,
                      angles=angle_states(scenario))
        net.compile().values_vector(net.components)     # and the values' checks
    except NetworkError as exc:
        comp, _, rest = exc.where.partition(".")
        table = next((t for t in data["component"] if t.get("name") == comp), {})
        fail(str(exc), where[comp] + (f".{rest}" if rest in table else "")
             if comp in where else "network.connect")
    except ValueError as exc:
        fail(str(exc), "network.connect")
    return net
