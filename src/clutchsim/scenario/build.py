"""Scenario tables -> driveline components (errors carry the key path and line)."""

from __future__ import annotations

import warnings

from ..driveline.chain import Chain
from ..driveline.components import (Brake, Engine, FrictionElement, Gear, Gearbox, Inertia,
                                    SpringDamper, ThermalNode, Vehicle)
from ..friction import get_model_class, make_model
from ..friction.base import SelfExcitedWarning

__all__ = ["build_chain", "friction_model"]


def friction_model(spec: dict, model: str | None, key: str, fail):
    """The friction model of an element table ``spec`` (optionally another ``model``)."""
    name = spec["model"] if model is None else model
    try:
        get_model_class(name)
    except ValueError as exc:
        fail(str(exc), f"{key}.model")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", SelfExcitedWarning)
            if name == spec["model"]:
                return make_model(name, spec.get("parameter_set"), **spec.get("overrides", {}))
            alts = spec.get("alternatives", {})
            if name not in alts:
                fail(f"no parameters for model {name!r} on this element: add "
                     f"[{key}.alternatives.{name}] (available: "
                     f"{', '.join([spec['model'], *alts]) or 'none'})", f"{key}.alternatives")
            alt = dict(alts[name])
            pset = alt.pop("parameter_set", None)
            if pset is None:
                cls = get_model_class(name)
                return cls(**alt)
            return make_model(name, pset, **alt)
    except (TypeError, ValueError, SelfExcitedWarning) as exc:
        fail(str(exc), f"{key}")
    raise AssertionError  # pragma: no cover


def _replaced(t, model, scenario) -> bool:
    """``--model`` acts on the clutch element and on every element listing it."""
    if model is None:
        return False
    return t["name"] == scenario.clutch or model in t["friction"].get("alternatives", {})


def _pairs(tab, a, b, key, fail):
    if tab is None:
        return None
    if set(tab) != {a, b}:
        fail(f"must be a table {{{a} = [...], {b} = [...]}}, got keys {sorted(tab)}", key)
    return (tab[a], tab[b])


def build_chain(scenario, model: str | None = None) -> Chain:
    """Build the :class:`Chain` of ``scenario`` with ``model`` on its clutch element."""
    data = scenario.data
    fail = scenario.fail
    inputs = scenario.inputs

    def need_input(name, key):
        if name not in inputs:
            fail(f"input signal {name!r} is not defined in [inputs]"
                 f"{'; inputs: ' + ', '.join(inputs) if inputs else ''}", key)

    def guard(fn, key):
        try:
            return fn()
        except (TypeError, ValueError) as exc:
            fail(str(exc), key)

    inertias = []
    for i, t in enumerate(data["inertia"]):
        if t.get("load"):
            need_input(t["load"], f"inertia[{i}].load")
        inertias.append(guard(lambda t=t: Inertia(**t), f"inertia[{i}]"))
    couplings = []
    for i, t in enumerate(data.get("coupling", [])):
        key = f"coupling[{i}]"
        kw = {k: v for k, v in t.items() if k != "type"}
        ctype = t["type"]
        if ctype == "gear":
            couplings.append(guard(lambda kw=kw: Gear(**kw), key))
        elif ctype == "spring_damper":
            couplings.append(guard(lambda kw=kw: SpringDamper(**kw), key))
        elif ctype == "gearbox":
            shifts = tuple((s.get("time"), s.get("gear")) for s in kw.pop("shifts", []))
            if "gear" in kw and isinstance(kw["gear"], int) and \
                    not 1 <= kw["gear"] <= len(kw["ratios"]):
                fail(f"gear {kw['gear']} does not exist: this gearbox has {len(kw['ratios'])} "
                     f"gears (1..{len(kw['ratios'])})", f"{key}.gear")
            couplings.append(guard(lambda kw=kw, s=shifts: Gearbox(shifts=s, **kw), key))
        else:
            need_input(kw["command"], f"{key}.command")
            m = model if _replaced(t, model, scenario) else None
            kw["model"] = friction_model(kw.pop("friction"), m, f"{key}.friction", fail)
            kw["clamp_table"] = _pairs(kw.get("clamp_table"), "position", "force",
                                       f"{key}.clamp_table", fail)
            kw["mu_temperature"] = _pairs(kw.get("mu_temperature"), "theta", "factor",
                                          f"{key}.mu_temperature", fail)
            kw["mu_slip"] = _pairs(kw.get("mu_slip"), "slip", "factor", f"{key}.mu_slip", fail)
            kw["heat"] = tuple((h.get("node"), h.get("share", 1.0)) for h in kw.get("heat", []))
            couplings.append(guard(lambda kw=kw: FrictionElement(**kw), key))
    brakes = []
    for i, t in enumerate(data.get("brake", [])):
        key = f"brake[{i}]"
        kw = dict(t)
        need_input(kw["command"], f"{key}.command")
        m = model if _replaced(t, model, scenario) else None
        kw["model"] = friction_model(kw.pop("friction"), m, f"{key}.friction", fail)
        brakes.append(guard(lambda kw=kw: Brake(**kw), key))
    engine = None
    if "engine" in data:
        e = dict(data["engine"])
        need_input(e["throttle"], "engine.throttle")
        fl = _pairs(e.pop("full_load"), "speed", "torque", "engine.full_load", fail)
        engine = guard(lambda: Engine(speeds=fl[0], torques=fl[1], **e), "engine")
    vehicle = guard(lambda: Vehicle(**data["vehicle"]), "vehicle") if "vehicle" in data else None
    thermal = tuple(guard(lambda t=t: ThermalNode(**t), f"thermal[{i}]")
                    for i, t in enumerate(data.get("thermal", [])))
    return guard(lambda: Chain(inertias, couplings, brakes, engine, vehicle, thermal,
                               name=scenario.name), "coupling")
