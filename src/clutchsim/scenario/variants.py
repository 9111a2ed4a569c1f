"""Variants of one scenario as parameter values on its already-built network.

A sweep runs one scenario many times with a few keys changed.  :class:`VariantPlan`
builds the scenario, its network and the compiled :class:`~clutchsim.network.Plan` once,
and maps each varied key onto the component parameter it sets.  A variant then costs a
new parameter vector (the changed components re-packed, the derived block recomputed only
when an inertia or a ratio changed: for an inertia only its inertia part), its initial
state, and the run itself: no TOML re-parse, no copy of the scenario, no chain rebuild, no
new :class:`~clutchsim.core.System` (the base scenario's, with the variant's values:
:meth:`VariantPlan.values`, :meth:`clutchsim.network.plant.Plan.variant_state`).

How a key is mapped: the first time a variant changes it, the scenario is built once with
that value the ordinary way (overrides, validation, chain, network) and compared with the
base network.  The key is *direct* when exactly one value of one component changed, to
the value given, and nothing else did (topology, solver settings, end time, the metrics'
inputs).  A key of a friction table (``coupling[0].friction.overrides.phi0``) whose
element alone changed, in its friction model only, is direct too: per variant that model
is built again from the element's friction table by the scenario builder
(:func:`clutchsim.scenario.build.friction_model`), which checks it.  Every other key (a
gear or a gearbox selection that enters a ratio, a table, the solver's or the scenario's
settings, a lining radius) is a *rebuild* key: a variant that changes one is built from
the scenario text as before.  A
scenario that does not run on the network plant (a lossy gear, a shifting gearbox, a
one-way clutch) rebuilds every variant.

Bad values: a direct key's value is checked against the scenario schema and the
component's own rules (its constructor); a value that fails either is run through the
rebuild, so its error is the one the scenario loader gives (file, key, rule, ``--set``).
"""

from __future__ import annotations

import functools
import inspect
import re
import threading
from dataclasses import dataclass

import numpy as np

from .errors import ScenarioError

__all__ = ["VariantPlan", "value_at"]

_PART = re.compile(r"([A-Za-z0-9_\-]+)(?:\[(\d+)\])?")
#: sections whose keys never act on a component value alone
_REBUILD_SECTIONS = ("scenario", "solver", "inputs", "network")
#: a probe that changed nothing (a key left out of the file, given its default): ask again
_UNSEEN = object()


@dataclass(frozen=True)
class _Direct:
    """A key that sets ``param`` of component ``index`` (rebuilt by ``cls(name, **kw)``)."""

    index: int
    param: str
    kwargs: dict
    schema: object      # the scenario schema Key of the key (or None)


@dataclass(frozen=True)
class _Friction:
    """A key inside the friction table of element ``index`` (``table`` its key path,
    ``path`` the keys inside its ``friction`` table): the element's friction model is
    built again from that table, as the scenario builder does, with ``model`` acting on it
    (``--model``; None: its own)."""

    index: int
    table: str
    path: tuple
    model: str | None
    kwargs: dict


class VariantPlan:
    """One scenario with ``model`` on its clutch element, built once; variants are
    parameter values on it (see the module docstring).

    Thread-safe: a sweep's worker threads share one plan.
    """

    def __init__(self, scenario, model: str | None = None):
        from ..network import compile_network
        self.scenario = scenario
        self.model = model
        net = scenario.network(model)
        self.net = net
        self._direct: dict = {}
        self._base_values: dict = {}
        self._inputs0 = scenario.inputs0()
        self._lock = threading.Lock()
        self._base = None
        self.plan = compile_network(net)
        self.params = self.plan.values_vector(net.components)
        self.base = _observed(scenario, net)

    # ------------------------------------------------------------------ mapping
    def direct(self, key: str, value: float) -> _Direct | None:
        """How ``key`` maps onto a component (``_Direct``: a value; ``_Friction``: a friction
        model parameter; None: a rebuild key).  The first call for a
        key builds the scenario once with ``key = value`` (a value other than the base
        one); a value that the scenario rejects raises its :class:`ScenarioError`, and the
        key stays unmapped."""
        if key in self._direct:
            return self._direct[key]
        with self._lock:
            if key not in self._direct:
                found = self._map(key, value)
                if found is _UNSEEN:
                    return None
                self._direct[key] = found
        return self._direct[key]

    def _map(self, key: str, value: float) -> _Direct | None:
        if key.split(".")[0].split("[")[0] in _REBUILD_SECTIONS:
            return None
        base = value_at(self.scenario.data, key)
        if base is not None and not _is_number(base):
            return None         # a table, a string: not a value of one component
        probe = self._rebuilt_scenario(((key, value),))
        from ..network.plant import structure_key
        net = probe.network(self.model)
        if structure_key(net) != structure_key(self.net) or \
                _observed(probe, net) != self.base:
            return None
        changed = []
        for i, (c0, c1) in enumerate(zip(self.net.components, net.components)):
            if not _same_pack(c0, c1):
                changed += [(i, k) for k in c0.values if c0.values[k] != c1.values[k]] \
                    or [(i, None)]
        if not changed and base is None:
            return _UNSEEN      # the value a key left out has already: nothing to learn
        if len(changed) == 1 and changed[0][1] is None and ".friction." in key:
            return self._map_friction(key, value, changed[0][0], net)
        if len(changed) != 1 or changed[0][1] is None:
            return None
        i, param = changed[0]
        comp = self.net.components[i]
        if net.components[i].values[param] != float(value):
            return None         # the key enters the parameter through a formula
        kwargs = _ctor_kwargs(comp)
        if kwargs is None:
            return None
        try:
            again = type(comp)(comp.name, **kwargs, **comp.values)
        except (TypeError, ValueError):
            return None
        if again.structure() != comp.structure() or not _same_pack(again, comp):
            return None         # the component cannot be rebuilt from what it keeps
        from .schema import key_spec
        spec = key_spec(self.scenario.data, key)
        return _Direct(i, param, kwargs, spec)

    def _map_friction(self, key: str, value: float, i: int, probe_net) -> _Friction | None:
        """A key of a friction table whose element ``i`` alone changed, in its model only:
        direct when building that model again reproduces the probe's element."""
        from .build import _replaced, effective_model
        table, _, rest = key.partition(".friction.")
        comp = self.net.components[i]
        elem = value_at(self.scenario.data, table)
        if not isinstance(elem, dict) or not isinstance(elem.get("friction"), dict) or \
                elem.get("name") != comp.name or "[" in rest:
            return None
        kwargs = _ctor_kwargs(comp)
        if kwargs is None or "model" not in kwargs:
            return None
        eff = effective_model(self.scenario, self.model)
        d = _Friction(i, table, tuple(rest.split(".")), eff if _replaced(elem, eff,
                                                                         self.scenario)
                      else None, kwargs)
        new = self._friction_component(comp, ((d, value),))
        if new is None or new.structure() != comp.structure() or \
                not _same_pack(new, probe_net.components[i]):
            return None
        return d

    def _friction_component(self, comp, items):
        """``comp`` with its friction model built again from its table with ``items`` =
        ``((_Friction, value), ...)`` set in it (None if the builder refuses it)."""
        from .build import friction_model
        d0 = items[0][0]
        elem = value_at(self.scenario.data, d0.table)
        spec = elem["friction"]
        for d, value in items:
            spec = _with(spec, d.path, float(value))

        def fail(problem, key=""):
            raise ScenarioError(problem)
        try:
            model = friction_model(spec, d0.model, f"{d0.table}.friction", fail, comp.name)
            kw = {k: comp.__dict__.get(k, v) for k, v in d0.kwargs.items()}
            return type(comp)(comp.name, **{**kw, "model": model}, **comp.values)
        except (TypeError, ValueError):
            return None

    # ------------------------------------------------------------------ variants
    def system(self, changes):
        """The :class:`~clutchsim.core.System` of the variant ``changes`` = ``((key,
        value), ...)``, or None when it must be rebuilt (:meth:`rebuilt`): a rebuild key,
        or a value that its checks refuse."""
        found = self.values(changes)
        if found is None:
            return None
        p, y0, names = found
        return self._base_system()[0].with_values(p, y0, names)

    def values(self, changes):
        """``(params, y0, event_names)`` of the variant ``changes`` (``event_names`` None:
        the base system's), or None when it must be rebuilt (see :meth:`system`, which is
        the base system with these)."""
        comps = list(self.net.components)
        friction: dict = {}
        values: dict = {}       # component index -> (its _Direct, {param: value})
        for key, value in changes:
            base = self._base_values.get(key, _UNSEEN)
            if base is _UNSEEN:     # a key's base value, read from the scenario once
                base = self._base_values[key] = value_at(self.scenario.data, key)
            if _is_number(base) and float(base) == float(value):
                continue            # the base value: nothing changes
            d = self.direct(key, value)
            if d is None:
                return None
            if isinstance(d, _Friction):
                friction.setdefault(d.index, []).append((d, value))
                continue
            if d.schema is not None and not _schema_ok(d.schema, value):
                return None
            values.setdefault(d.index, (d, {}))[1][d.param] = value
        touched = []
        for i, (d, params) in values.items():     # each component built once
            comp = comps[i]
            kw = {k: comp.__dict__.get(k, v) for k, v in d.kwargs.items()}
            try:
                new = type(comp)(comp.name, **kw, **{**comp.values, **params})
            except (TypeError, ValueError):
                return None
            if new.structure() != comp.structure():
                return None
            comps[i] = new
            touched.append(i)
        for i, items in friction.items():
            new = self._friction_component(comps[i], tuple(items))
            if new is None or new.structure() != comps[i].structure():
                return None
            comps[i] = new
            touched.append(i)
        p = self.plan.updated_vector(self.params, self.net.components, comps, touched)
        _base, produced0, start = self._base_system()
        try:
            y0, names = self.plan.variant_state(comps, p, self._inputs0,
                                                {comps[i].name for i in touched}, produced0,
                                                start)
        except ValueError:
            return None     # e.g. initial speeds that violate a gear: the rebuild says so
        return p, y0, names

    @functools.cached_property
    def batch_reason(self) -> str:
        """Why its variants cannot run as one compiled batch ("" when they can:
        :func:`clutchsim.scenario.run.batch_reason`)."""
        from .run import batch_reason
        return batch_reason(self.scenario, self.base_system())

    def base_system(self):
        """The base scenario's :class:`~clutchsim.core.System` (a variant is this system
        with its own :meth:`values`)."""
        return self._base_system()[0]

    def _base_system(self):
        """(the base scenario's system, its produced signals at the start, (the base
        components, their initial state with those signals)), built once: a variant is
        this system with its own values, its initial state computed from that one
        (:meth:`Plan.variant_state`)."""
        if self._base is None:
            with self._lock:
                if self._base is None:
                    net = self.net
                    base = self.plan.system(net.components, inputs0=self._inputs0,
                                            name=net.name, metadata=dict(net.metadata),
                                            params=self.params)
                    produced0 = self.plan.produced0(base, self._inputs0)
                    start = self.plan.initial_state(self.net.components,
                                                    {**self._inputs0, **produced0})
                    self._base = (base, produced0, (tuple(self.net.components), start))
        return self._base

    def rebuilt(self, changes):
        """``(scenario, system)`` of the variant built from the scenario text (the
        overrides applied, validated, the network built): the way every variant was built
        before, and the way for rebuild keys.  Raises the scenario's errors."""
        sc = self._rebuilt_scenario(changes)
        return sc, sc.network(self.model).build(sc.inputs0())

    def _rebuilt_scenario(self, changes):
        from .loader import apply_overrides, parse_scenario, toml_value
        sc = self.scenario
        data = apply_overrides(sc.data, [f"{k}={toml_value(v)}" for k, v in changes], sc.file)
        return parse_scenario(data, text=sc.text, file=sc.file)


def _observed(scenario, net) -> tuple:
    """What else a run reads from the scenario besides the network's values (its solver
    options come from ``[solver]`` alone, a rebuild section, and may be replaced by the
    sweep's ``--option``: they are not compared)."""
    from .run import expects_lockup, lining_geometry
    return (scenario.t_end, scenario.solver, scenario.clutch, scenario.models,
            tuple(scenario.inputs), lining_geometry(scenario),
            expects_lockup(scenario, {c.name: c.kind for c in net.components}),
            net.connections, net.name)


def _same_pack(a, b) -> bool:
    pa, pb = a.pack(), b.pack()
    return pa.keys() == pb.keys() and all(
        np.array_equal(np.asarray(pa[k], dtype=float), np.asarray(pb[k], dtype=float))
        for k in pa)


def _ctor_kwargs(comp) -> dict | None:
    """The constructor arguments of ``comp`` besides its name and parameter values, read
    back from the attributes of the same names (None if one is missing)."""
    out = {}
    params = list(inspect.signature(type(comp).__init__).parameters.values())[2:]
    for p in params:
        if p.kind in (p.VAR_KEYWORD, p.VAR_POSITIONAL):
            continue
        if p.name in comp.__dict__:
            out[p.name] = comp.__dict__[p.name]
        elif p.default is not p.empty:
            out[p.name] = p.default
        else:
            return None
    return out


def value_at(data: dict, key: str):
    """The value at the key path ``key`` (``coupling[0].friction.model``) of the scenario
    tables ``data``, or None where the path leads nowhere."""
    node = data
    for name, index in _PART.findall(key):
        if not isinstance(node, dict) or name not in node:
            return None
        node = node[name]
        if index:
            if not isinstance(node, list) or int(index) >= len(node):
                return None
            node = node[int(index)]
    return node


def _with(table: dict, path: tuple, value) -> dict:
    """A copy of the nested ``table`` with ``value`` at ``path`` (tables copied along it)."""
    out = dict(table)
    inner = out.get(path[0])
    out[path[0]] = value if len(path) == 1 else \
        _with(inner if isinstance(inner, dict) else {}, path[1:], value)
    return out


def _is_number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _schema_ok(spec, value) -> bool:
    from .schema import check_table

    def fail(problem, key=""):
        raise ScenarioError(problem)
    try:
        check_table({spec.name: value}, (spec,), "", fail)
    except ScenarioError:
        return False
    return True
