"""A launch explorer session: one scenario, parameters changed by key path, re-run.

:class:`Session` holds a :class:`~clutchsim.scenario.Scenario` and a friction model, takes
new values for its parameters (:meth:`Session.set`: checked at once, by the same rules and
with the same messages as ``clutchsim run --set``), and re-runs the launch
(:meth:`Session.run`), returning the traces and launch metrics (:class:`ExplorerRun`).  The
network is built and compiled once per model: a change of a component value or a friction
parameter is a new parameter vector on it (:class:`clutchsim.scenario.variants.VariantPlan`),
so a re-run costs the simulation itself (a few ms); a change of an input signal or a table
rebuilds the scenario from its tables (validated as a file is), still without compiling.

The parameters offered (:attr:`Session.parameters`) are the ones of the scenario that
shape a launch, where it has them: the clutch's friction parameters (its capacity first),
the touch point of a release system, the engagement time of the clutch command's ramp,
the engine's full-load torque (a factor on its table), the vehicle mass and road grade,
and the stiffness of the torsional damper.  Any other numeric key path of the scenario
can be set too.

>>> from clutchsim.explore import Session
>>> s = Session()                                   # the packaged launch
>>> s.set("vehicle.mass", 1600.0)                   # doctest: +SKIP
>>> s.run().metrics["lockup_time_s"]                # doctest: +SKIP
"""

from __future__ import annotations

import json
import math
import re
import time
from dataclasses import dataclass, field

import numpy as np

from ..scenario import Scenario, ScenarioError, resolve_scenario
from ..scenario.variants import value_at
from ..studies.sweeps.runner import METRICS as RUN_METRICS

__all__ = ["ENGAGEMENT", "METRICS", "TORQUE_FACTOR", "ExplorerRun", "Parameter", "Session",
           "launch_parameters"]

#: derived parameter: the duration [s] of the ramp of the clutch command's input signal
ENGAGEMENT = "engagement_time"
#: derived parameter: a factor [-] on the engine's full-load torque table
TORQUE_FACTOR = "engine_torque_factor"
#: the launch metrics the explorer shows: key -> (label, unit), the units those of a sweep's
#: columns
METRICS = {key: (label, RUN_METRICS[key][0]) for key, label in {
    "lockup_time_s": "lock-up time",
    "slip_energy_J": "slip energy",
    "peak_heat_node_temp_C": "peak temperature",
    "engine_speed_min_rpm": "minimum engine speed",
    "engine_dip_rpm": "engine dip",
    "judder_amplitude_Nm": "judder amplitude",
    "jerk_peak_mps3": "peak jerk",
    "lockup_shock_mps2": "lock-up shock",
    "energy_balance_rel": "energy balance error",
}.items()}
_RAMP = re.compile(r"ramp\(\s*([^,()]+?)\s*,\s*([^,()]+?)\s*,\s*([^,()]+?)\s*\)")


@dataclass(frozen=True)
class Parameter:
    """A parameter the explorer offers: ``key`` (a key path of the scenario, or
    :data:`ENGAGEMENT` / :data:`TORQUE_FACTOR`), its label and unit, the scenario's value
    and a slider range ``[low, high]`` with ``step`` (any value the rules accept may be set,
    outside the range too)."""

    key: str
    label: str
    unit: str
    value: float
    low: float
    high: float
    step: float
    doc: str = ""


@dataclass(frozen=True)
class ExplorerRun:
    """One run of a session: ``traces`` (series name -> array, ``"t"`` the time [s]) with
    their ``units``, the launch ``metrics`` (:func:`clutchsim.analysis.launch_metrics.analyse_run`),
    the status of the run and its message, and the time it took [ms]."""

    model: str
    status: str
    completed: bool
    message: str
    metrics: dict
    traces: dict = field(repr=False)
    units: dict = field(repr=False)
    run_ms: float = 0.0


def _number(key: str, value) -> float:
    """``value`` as a finite float, or ValueError naming the key, the value and the rule."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        try:
            out = float(str(value).strip())
        except ValueError:
            raise ValueError(f"{key} = {value!r}: must be a number") from None
    else:
        out = float(value)
    if not math.isfinite(out):
        raise ValueError(f"{key} = {value!r}: must be a finite number")
    return out


def _literal(value) -> str:
    """A TOML literal of a value: a number, a string or a list of numbers."""
    if isinstance(value, str):
        return json.dumps(value)     # a TOML basic string (JSON's escapes are TOML's)
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(repr(float(v)) for v in value) + "]"
    return repr(float(value))


def _element(data: dict, name: str, kinds=None):
    """``(key path, table)`` of the first element named ``name`` (``kinds``: of these
    ``type``\\ s instead), in ``[[coupling]]`` and ``[[component]]``, or (None, None)."""
    for section in ("coupling", "component"):
        for i, t in enumerate(data.get(section, [])):
            if not isinstance(t, dict):
                continue
            if (kinds is None and t.get("name") == name) or (kinds and t.get("type") in kinds
                                                            and name in t.get("name", "")):
                return f"{section}[{i}]", t
    return None, None


def _span(value: float, unit: str) -> tuple[float, float, float]:
    low, high = 0.5 * value, 1.5 * value
    if unit == "-" and value <= 1.0:
        high = min(high, 1.0)
    return low, high, (high - low) / 100.0


def _friction_parameters(scenario: Scenario, model: str | None) -> list[Parameter]:
    from ..friction import get_model_class, make_model
    path, elem = _element(scenario.data, scenario.clutch)
    spec = elem.get("friction") if elem else None
    if not isinstance(spec, dict) or "model" not in spec:
        return []
    name = model or spec["model"]
    if name == spec["model"]:
        entry, prefix = dict(spec.get("overrides", {})), f"{path}.friction.overrides"
        pset = spec.get("parameter_set")
    elif name in spec.get("alternatives", {}):
        entry = dict(spec["alternatives"][name])
        pset, prefix = entry.pop("parameter_set", None), f"{path}.friction.alternatives.{name}"
    else:
        return []
    cls = get_model_class(name)
    built = make_model(name, pset, **entry)
    out = []
    for p, (_kind, doc) in cls.parameter_info.items():
        v = getattr(built, p, None)
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not v > 0:
            continue
        unit = cls.unit_of(p, "rotational")
        if unit == "-" and float(v).is_integer():
            continue    # an exponent or a policy's factor: not a slider (the key field)
        out.append(Parameter(f"{prefix}.{p}", f"clutch friction {p}", unit, float(v),
                             *_span(float(v), unit), doc))
    # the capacity first: the static or Coulomb level, in N·m
    out.sort(key=lambda q: (q.unit != "N·m", -q.value if q.unit == "N·m" else 0.0))
    return out


def engagement_input(scenario: Scenario) -> tuple[str, str] | None:
    """``(input name, formula)`` of the input that engages the clutch (the clutch's command,
    or an actuator's) when its formula holds exactly one ``ramp(start, duration, height)``
    with a plain number as duration; None otherwise."""
    data = scenario.data
    inputs = data.get("inputs", {})
    _, elem = _element(data, scenario.clutch)
    names = [elem.get("command")] if elem else []
    names += [c.get("command") for c in data.get("component", []) if isinstance(c, dict)]
    for n in names:
        text = inputs.get(n) if isinstance(n, str) else None
        if isinstance(text, str) and len(_RAMP.findall(text)) == 1:
            try:
                float(_RAMP.search(text).group(2))
            except ValueError:
                continue
            return n, text
    return None


def _tables(data: dict, section: str, kind: str):
    """``(key path, table)`` of ``[section]`` and of each ``[[component]]`` of ``kind``."""
    if isinstance(data.get(section), dict):
        yield section, data[section]
    for i, c in enumerate(data.get("component", [])):
        if isinstance(c, dict) and c.get("type") == kind:
            yield f"component[{i}]", c


def launch_parameters(scenario: Scenario, model: str | None = None) -> tuple[Parameter, ...]:
    """The parameters of ``scenario`` that shape a launch (see the module docstring), with
    ``model`` on its clutch (None: the scenario's first model)."""
    data = scenario.data
    out = _friction_parameters(scenario, model)
    for path, t in _tables(data, "release", "release_system"):
        if isinstance(t.get("touch_point"), (int, float)):
            v = float(t["touch_point"])
            out.append(Parameter(f"{path}.touch_point", "touch point", "m", v, *_span(v, "m"),
                                 "release travel where the clamp load starts"))
    found = engagement_input(scenario)
    if found:
        v = float(_RAMP.search(found[1]).group(2))
        out.append(Parameter(ENGAGEMENT, "engagement time", "s", v, 0.2 * v, 3.0 * v,
                             v / 50.0, f"duration of the ramp of inputs.{found[0]}"))
    for path, t in _tables(data, "engine", "engine"):
        if isinstance(t.get("full_load"), dict):
            out.append(Parameter(TORQUE_FACTOR, "engine full-load torque factor", "-", 1.0,
                                 0.5, 1.5, 0.01, f"factor on {path}.full_load.torque"))
            break
    for path, t in _tables(data, "vehicle", "vehicle"):
        if isinstance(t.get("mass"), (int, float)):
            v = float(t["mass"])
            out.append(Parameter(f"{path}.mass", "vehicle mass", "kg", v, *_span(v, "kg"),
                                 "vehicle mass"))
            g = float(t.get("grade", 0.0))
            out.append(Parameter(f"{path}.grade", "road grade", "%", g, -10.0, 25.0, 0.5,
                                 "road grade, positive uphill"))
        break
    path, t = _element(data, "damper", kinds=("spring_damper",))
    if t is not None and isinstance(t.get("c"), (int, float)):
        v = float(t["c"])
        out.append(Parameter(f"{path}.c", "damper stiffness", "N·m/rad", v, *_span(v, "-"),
                             "torsional damper stiffness (first stage)"))
    return tuple(out)


class Session:
    """One scenario explored with one friction model at a time (see the module docstring).

    Parameters
    ----------
    scenario : Scenario, str, Path or None
        A loaded scenario or a path (None: the packaged launch).
    model : str, optional
        Friction model on the clutch (default: the scenario's first).
    """

    def __init__(self, scenario=None, model: str | None = None):
        self.scenario = resolve_scenario(scenario)
        models = list(self.scenario.models)
        self.model = model or (models[0] if models else None)
        if self.model is not None:
            from ..friction import get_model_class
            get_model_class(self.model)          # an unknown model: its error now
        self.values: dict = {}
        self._plans: dict = {}
        self._built = None
        self.parameters = launch_parameters(self.scenario, self.model)

    # ------------------------------------------------------------------ parameters
    @property
    def models(self) -> tuple:
        """The friction models the scenario compares (its ``models``)."""
        return tuple(self.scenario.models) or ((self.model,) if self.model else ())

    def parameter(self, key: str) -> Parameter | None:
        return next((p for p in self.parameters if p.key == key), None)

    def value(self, key: str) -> float:
        """The current value of ``key`` (set, else the scenario's)."""
        if key in self.values:
            return self.values[key]
        p = self.parameter(key)
        if p is not None:
            return p.value
        base = value_at(self.scenario.data, key)
        return float(base) if isinstance(base, (int, float)) else float("nan")

    def set(self, key: str, value) -> None:
        """Set ``key`` (a key path of the scenario or a :attr:`parameters` key) to
        ``value``.  The value is checked at once (ValueError / ScenarioError naming the
        key, the value and the rule, as ``clutchsim run --set`` does); a refused value
        leaves the session as it was."""
        v = _number(key, value)
        if key == ENGAGEMENT and not v > 0:
            raise ValueError(f"{key} = {v!r} s: must be > 0 s (the clutch command's ramp "
                             "needs a duration)")
        if key == TORQUE_FACTOR and not v >= 0:
            raise ValueError(f"{key} = {v!r}: must be >= 0 (a factor on the full-load torque)")
        if self.parameter(key) is None:
            base = value_at(self.scenario.data, key)
            if isinstance(base, (dict, list, str, bool)):
                raise ValueError(f"{key} = {v!r}: {key} is not a number in the scenario "
                                 "(only numeric keys can be explored)")
        values = {**self.values, key: v}
        built = self._build(values)            # raises, leaving the session as it was
        self.values, self._built = values, built

    def reset(self) -> None:
        """Back to the scenario's values."""
        self.values, self._built = {}, None

    def set_model(self, model: str) -> None:
        """Run ``model`` on the clutch from now on (the values set so far are kept where
        the other model has the same keys; its friction parameters are its own)."""
        if model == self.model:
            return
        from ..scenario.build import effective_model
        effective_model(self.scenario, model)
        self.scenario.system(model)             # the scenario's error for a model it lacks
        old = {p.key for p in self.parameters}
        self.model = model
        self.parameters = launch_parameters(self.scenario, model)
        keep = {k: v for k, v in self.values.items() if ".friction." not in k or k not in old}
        self.values, self._built = {}, None
        for k, v in keep.items():
            self.set(k, v)

    # ------------------------------------------------------------------ changes
    def changes(self, values=None) -> tuple:
        """``((key path, value), ...)`` of the values set: the derived parameters as the
        key paths they change (a formula, a table)."""
        values = self.values if values is None else values
        out = []
        data = self.scenario.data
        for key, v in values.items():
            if key == ENGAGEMENT:
                name, text = engagement_input(self.scenario)
                m = _RAMP.search(text)
                new = f"{text[:m.start(2)]}{v!r}{text[m.end(2):]}"
                out.append((f"inputs.{name}", new))
            elif key == TORQUE_FACTOR:
                path, t = next(_tables(data, "engine", "engine"))
                out.append((f"{path}.full_load.torque",
                            [float(x) * v for x in t["full_load"]["torque"]]))
            else:
                out.append((key, v))
        return tuple(out)

    def _plan(self):
        from ..scenario.variants import VariantPlan
        plan = self._plans.get(self.model)
        if plan is None:
            plan = self._plans[self.model] = VariantPlan(self.scenario, self.model)
        return plan

    def _build(self, values):
        """``(scenario, system)`` with ``values``: the compiled network with new parameter
        values where it can, else the scenario rebuilt from its tables."""
        changes = self.changes(values)
        plan = self._plan()
        if all(isinstance(v, float) for _, v in changes):
            system = plan.system(changes)
            if system is not None:
                return plan.scenario, system
        sc = self.scenario
        items = [f"{k}={_literal(v)}" for k, v in changes]
        from ..scenario.loader import apply_overrides, parse_scenario
        data = apply_overrides(sc.data, items, sc.file)
        rebuilt = parse_scenario(data, text=sc.text, file=sc.file,
                                 set_by={k: i for (k, _), i in zip(changes, items)})
        return rebuilt, rebuilt.system(self.model)

    # ------------------------------------------------------------------ running
    def run(self) -> ExplorerRun:
        """Simulate the launch with the current values: its traces and metrics.  A run
        that does not complete is an :class:`ExplorerRun` with its status and message."""
        from ..scenario.run import run_system
        if self._built is None:
            self._built = self._build(self.values)
        sc, system = self._built
        t0 = time.perf_counter()
        lr = run_system(sc, system, self.model)
        ms = 1e3 * (time.perf_counter() - t0)
        res = lr.result
        traces = {"t": np.asarray(res.t)}
        units = {"t": "s"}
        for name in res.signals:
            traces[name] = np.asarray(res[name])
            units[name] = res.units.get(name, "")
        m = lr.metrics
        return ExplorerRun(lr.model or (self.model or ""), res.status, bool(m.get("completed")),
                       str(m.get("message", res.message)), m, traces, units, ms)

    def overrides(self) -> list[str]:
        """The values set as ``--set`` items (``clutchsim run SCENARIO --set ...``)."""
        return [f"{k}={_literal(v)}" for k, v in self.changes()]

    def scenario_toml(self) -> str:
        """The scenario with the values set, as the text of a scenario file (its tables;
        the comments of the original are not kept, a header names it and the changes).
        Relative paths in it (CSV signal tables) are relative to the original's folder."""
        from ..scenario.loader import apply_overrides
        items = self.overrides()
        data = apply_overrides(self.scenario.data, items, self.scenario.file)
        head = [f"# saved by clutchsim explore from {self.scenario.file}",
                f"# model on the clutch: {self.model or 'its own'}"]
        head += [f"# --set {i}" for i in items] or ["# no values changed"]
        return "\n".join(head) + "\n" + _toml_tables(data)


def _toml_key(k: str) -> str:
    return k if re.fullmatch(r"[A-Za-z0-9_\-]+", k) else _literal(str(k))


def _toml_inline(v) -> str:
    """A TOML value: numbers, booleans, strings, arrays and inline tables."""
    from ..scenario.loader import toml_value
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{_toml_key(k)} = {_toml_inline(x)}" for k, x in v.items()) \
            + " }"
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_inline(x) for x in v) + "]"
    if isinstance(v, str):
        return _literal(v)
    return toml_value(v)


def _toml_tables(data: dict) -> str:
    """The scenario tables as TOML: ``[section]`` per table, ``[[section]]`` per entry of
    an array of tables, nested tables inline."""
    lines = []
    for name, value in data.items():
        if isinstance(value, dict):
            lines += ["", f"[{_toml_key(name)}]"]
            lines += [f"{_toml_key(k)} = {_toml_inline(v)}" for k, v in value.items()]
        elif isinstance(value, list) and value and all(isinstance(t, dict) for t in value):
            for t in value:
                lines += ["", f"[[{_toml_key(name)}]]"]
                lines += [f"{_toml_key(k)} = {_toml_inline(v)}" for k, v in t.items()]
        else:
            lines.insert(0, f"{_toml_key(name)} = {_toml_inline(value)}")
    return "\n".join(lines).lstrip("\n") + "\n"


def check_error(exc: BaseException) -> str:
    """The one-line message of a refused value (as the command line prints it)."""
    if isinstance(exc, (ScenarioError, ValueError)):
        return str(exc)
    return f"{type(exc).__name__}: {exc}"
