"""Read and validate a scenario TOML file into the library's objects."""

from __future__ import annotations

import copy
import tomllib
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

from ..core import Constant, Ramp, Signal, Sine, SolverOptions, Step, Table
from .errors import ScenarioError, find_line
from .schema import COUPLING_TYPES, FRICTION, SECTIONS, check_table, suggest

__all__ = [
    "Scenario",
    "apply_overrides",
    "default_scenario_text",
    "load_scenario",
    "parse_scenario",
]

DEFAULT_NAME = "launch.toml"


def default_scenario_text() -> str:
    """Text of the packaged default scenario (the passenger-car launch)."""
    return (resources.files("clutchsim") / "scenario" / "data" / DEFAULT_NAME).read_text(
        encoding="utf-8")


@dataclass(frozen=True)
class Scenario:
    """A validated scenario: the raw tables plus the objects built from them.

    Attributes
    ----------
    name, description : str
    t_end : float
        End time [s].
    models : tuple of str
        Friction models to run on the element ``clutch`` (first = default).
    clutch : str
        Friction element the models replace and the launch metrics refer to.
    inputs : dict of str to Signal
    solver : str
    options : SolverOptions
    data : dict
        The validated tables (for rebuilding with other overrides).
    file : str
        Where it came from (for messages).
    """

    name: str
    description: str
    t_end: float
    models: tuple
    clutch: str
    inputs: dict
    solver: str
    options: SolverOptions
    data: dict = field(repr=False)
    file: str = "<scenario>"
    text: str = field(default="", repr=False)
    #: built chains per effective model (chains are immutable; a sweep builds each
    #: variant's chain once for validation and would build it again to run it)
    _chains: dict = field(default_factory=dict, repr=False, compare=False)

    def fail(self, problem: str, key: str = "") -> None:
        raise ScenarioError(problem, file=self.file, key=key,
                            line=find_line(self.text, key) if key else None)

    def chain(self, model: str | None = None):
        """The :class:`~clutchsim.driveline.Chain` with ``model`` on the clutch element."""
        from .build import build_chain, effective_model
        key = effective_model(self, model)
        if key not in self._chains:
            self._chains[key] = build_chain(self, key)
        return self._chains[key]


def load_scenario(path: str | Path | None = None, *, overrides=None) -> Scenario:
    """Load a scenario file (``None``: the packaged default launch).

    Parameters
    ----------
    path : str or Path, optional
    overrides : sequence of str, optional
        ``"key.path=value"`` assignments (TOML values) applied before validation.

    Raises
    ------
    ScenarioError
        With file, key path and line.
    """
    if path is None:
        text, file, base = default_scenario_text(), f"<default scenario {DEFAULT_NAME}>", None
    else:
        p = Path(path)
        try:
            text = p.read_text(encoding="utf-8")
        except OSError as exc:
            raise ScenarioError(f"cannot read the scenario file ({exc.strerror})",
                                file=p) from None
        file, base = str(p), p.parent
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        line = getattr(exc, "lineno", None)
        raise ScenarioError(f"not valid TOML: {exc}", file=file, line=line) from None
    if overrides:
        data = apply_overrides(data, overrides, file)
    return parse_scenario(data, text=text, file=file, base_dir=base)


def apply_overrides(data: dict, overrides, file: str = "<scenario>") -> dict:
    """A copy of ``data`` with ``key.path=value`` assignments applied."""
    import re
    out = copy.deepcopy(data)
    for item in overrides:
        if "=" not in item:
            raise ScenarioError(f"--set {item!r}: expected key.path=value", file=file)
        key, raw = item.split("=", 1)
        key = key.strip()
        try:
            value = tomllib.loads(f"v = {raw.strip()}")["v"]
        except tomllib.TOMLDecodeError:
            value = raw.strip()
        parts = re.findall(r"([A-Za-z0-9_\-]+)(?:\[(\d+)\])?", key)
        node: Any = out
        for i, (name, index) in enumerate(parts):
            last = i == len(parts) - 1
            if not isinstance(node, dict):
                raise ScenarioError(f"--set {item!r}: {name!r} is not inside a table", file=file)
            if index:
                seq = node.get(name)
                if not isinstance(seq, list) or int(index) >= len(seq):
                    raise ScenarioError(f"--set {item!r}: {name}[{index}] does not exist",
                                        file=file, key=key)
                if last:
                    seq[int(index)] = value
                node = seq[int(index)]
            elif last:
                node[name] = value
            else:
                node = node.setdefault(name, {})
    return out


def _signal(spec, key: str, base_dir, fail) -> Signal:
    if isinstance(spec, bool):
        fail(f"must be a signal (a number, a formula string, a CSV path or a table), "
             f"got {spec!r}", key)
    if isinstance(spec, (int, float)):
        return Constant(float(spec))
    if isinstance(spec, str):
        text = spec.strip()
        if text.lower().endswith(".csv"):
            path = Path(text) if base_dir is None else Path(base_dir) / text
            try:
                return Table.from_csv(path)
            except ValueError as exc:
                fail(f"bad CSV input: {exc}", key)
        try:
            from ..signal_expr import parse_signal
            return parse_signal(text, base_dir=base_dir)
        except ImportError:   # pragma: no cover - the formula parser ships with clutchsim
            fail("formula signals need clutchsim.signal_expr", key)
        except ValueError as exc:
            fail(f"bad signal {text!r}: {exc}", key)
    if isinstance(spec, dict):
        kind = spec.get("type")
        kinds = {"const": (Constant, {"value"}), "step": (Step, {"time", "height", "offset"}),
                 "ramp": (Ramp, {"start", "duration", "height", "offset"}),
                 "sine": (Sine, {"amplitude", "freq", "phase", "offset", "start"}),
                 "table": (None, {"time", "value"}), "csv": (None, {"path"})}
        if kind not in kinds:
            fail(f"signal type {kind!r} is not known{suggest(str(kind), kinds)} "
                 f"(types: {', '.join(kinds)})", key)
        cls, allowed = kinds[kind]
        for k in spec:
            if k != "type" and k not in allowed:
                fail(f"unknown key {k!r}{suggest(k, allowed)} for a {kind} signal "
                     f"(keys: {', '.join(sorted(allowed))})", f"{key}.{k}")
        args = {k: v for k, v in spec.items() if k != "type"}
        try:
            if kind == "table":
                return Table(np.asarray(args["time"], float), np.asarray(args["value"], float))
            if kind == "csv":
                return _signal(str(args["path"]), key, base_dir, fail)
            return cls(**args)
        except (TypeError, ValueError, KeyError) as exc:
            fail(f"bad {kind} signal: {exc}", key)
    fail(f"must be a signal (a number, a formula string, a CSV path or a table), got {spec!r}",
         key)
    raise AssertionError  # pragma: no cover


def parse_scenario(data: dict, *, text: str = "", file: str = "<scenario>",
                   base_dir=None) -> Scenario:
    """Validate the tables of a scenario and build its signals and options."""

    def fail(problem, key=""):
        raise ScenarioError(problem, file=file, key=key,
                            line=find_line(text, key) if key and text else None)

    for name in data:
        if name not in SECTIONS:
            fail(f"unknown table [{name}]{suggest(name, SECTIONS)} "
                 f"(tables: {', '.join(SECTIONS)})", name)
    for required in ("scenario", "inertia"):
        if required not in data:
            fail(f"missing required table [{required}]" if required == "scenario" else
                 "missing required component: at least one [[inertia]]", "")
    for name, (keys, kind) in SECTIONS.items():
        if name not in data or kind == "map":
            continue
        value = data[name]
        if kind == "tables":
            if not isinstance(value, list):
                fail(f"must be an array of tables [[{name}]]", name)
            for i, tab in enumerate(value):
                path = f"{name}[{i}]"
                if name == "coupling":
                    ctype = tab.get("type")
                    if ctype not in COUPLING_TYPES:
                        fail(f"coupling type {ctype!r} is not known"
                             f"{suggest(str(ctype), COUPLING_TYPES)} (types: "
                             f"{', '.join(COUPLING_TYPES)})", f"{path}.type")
                    check_table(tab, COUPLING_TYPES[ctype], path, fail)
                else:
                    check_table(tab, keys, path, fail)
                if "friction" in tab:
                    check_table(tab["friction"], FRICTION, f"{path}.friction", fail)
        else:
            if not isinstance(value, dict):
                fail(f"must be a table [{name}]", name)
            check_table(value, keys, name, fail)
    n_in, n_cp = len(data["inertia"]), len(data.get("coupling", []))
    if n_cp != n_in - 1:
        fail(f"{n_in} inertias need {n_in - 1} couplings (coupling k joins inertia k and "
             f"k+1), found {n_cp}", "coupling" if n_cp else "inertia")
    sc = data["scenario"]
    inputs = {}
    raw_inputs = data.get("inputs", {})
    if not isinstance(raw_inputs, dict):
        fail("must be a table of name = signal", "inputs")
    for key, spec in raw_inputs.items():
        inputs[key] = _signal(spec, f"inputs.{key}", base_dir, fail)
    solver_tab = dict(data.get("solver", {}))
    method = solver_tab.pop("method", "rodas4")
    from ..core.options import SOLVERS
    if method not in SOLVERS:
        fail(f"solver {method!r} is not known{suggest(method, SOLVERS)} "
             f"(solvers: {', '.join(SOLVERS)})", "solver.method")
    opt_kw = {k: (int(v) if k in ("max_steps", "chatter_events") else float(v))
              for k, v in solver_tab.items()}
    opt_kw.setdefault("dt_out", 0.0)
    try:
        options = SolverOptions(**opt_kw)
    except ValueError as exc:
        fail(str(exc), "solver")
    clutch = sc.get("clutch", "clutch")
    fe_names = [c["name"] for c in data.get("coupling", [])
                if c.get("type") in ("clutch", "one_way_clutch", "lossy_gear")]
    fe_names += [b["name"] for b in data.get("brake", [])]
    if ("models" in sc or "clutch" in sc) and clutch not in fe_names:
        fail(f"friction element {clutch!r} does not exist{suggest(clutch, fe_names)} "
             f"(friction elements: {', '.join(fe_names) or 'none'})", "scenario.clutch")
    models = tuple(sc.get("models", ()))
    scen = Scenario(name=sc["name"], description=sc.get("description", ""),
                    t_end=float(sc["t_end"]), models=models, clutch=clutch, inputs=inputs,
                    solver=method, options=options, data=data, file=file, text=text)
    scen.chain()   # build once: component-level validation errors surface here
    return scen
