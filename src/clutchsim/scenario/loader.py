"""Read and validate a scenario TOML file into the library's objects."""

from __future__ import annotations

import copy
import math
import sys
import tomllib
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

from .._util import quote, toml_line
from ..core import Constant, Ramp, Signal, Sine, SolverOptions, Step, Table
from . import chain_format, composites
from .errors import ScenarioError
from .schema import (
    FRICTION,
    FRICTION_TYPES,
    SECTIONS,
    chain_keys,
    check_lining,
    check_table,
    suggest,
)

__all__ = [
    "Scenario",
    "apply_overrides",
    "default_scenario_text",
    "load_scenario",
    "parse_scenario",
    "resolve_scenario",
    "toml_value",
    "with_solver_options",
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
    #: another scenario file this launch is compared with on the quality metrics
    #: (``[scenario] compare``, resolved against this file's folder), or ""
    compare: str = ""
    #: built networks per effective model (a sweep builds each variant's network once for
    #: validation and would build it again to run it)
    _networks: dict = field(default_factory=dict, repr=False, compare=False)
    #: built systems per effective model (:meth:`system`)
    _systems: dict = field(default_factory=dict, repr=False, compare=False)
    #: key path -> the ``--set`` item that gave it (errors name the item, not a file line)
    set_by: dict = field(default_factory=dict, repr=False, compare=False)

    def fail(self, problem: str, key: str = "") -> None:
        _fail(problem, key, file=self.file, text=self.text, set_by=self.set_by)

    def inputs0(self) -> dict:
        """The input values at t = 0 (what a system is built with)."""
        return {name: float(np.asarray(sig(0.0)).ravel()[0])
                for name, sig in self.inputs.items()}

    def estimate(self, model: str | None = None):
        """What one run with ``model`` will produce: a :class:`clutchsim._util.RunEstimate`
        (output rows, signals, the least number of steps), before running it."""
        from .._util import estimate_run
        system = self.system(model)
        n = len(system.state_names) + len(system.input_names) + len(system.output_names)
        return estimate_run(self.t_end, self.options, n)

    def system(self, model: str | None = None):
        """The :class:`~clutchsim.core.System` of :meth:`network` with ``model``, built
        with the inputs at t = 0 once per effective model and shared by every run of this
        scenario (:func:`~clutchsim.scenario.run_scenario`): read it, do not modify its
        arrays (``simulate`` copies the parameter vector it integrates; build your own
        with ``network(model).build(inputs0())`` to change one)."""
        from .build import effective_model
        key = effective_model(self, model)
        system = self._systems.get(key)
        if system is None:
            system = self._systems[key] = self.network(model).build(self.inputs0())
        return system

    def network(self, model: str | None = None):
        """The :class:`~clutchsim.network.Network` with ``model`` on the clutch element
        (a chain file read as one, :mod:`clutchsim.scenario.chain_format`)."""
        from .build import build_network, effective_model
        key = effective_model(self, model)
        if key not in self._networks:
            self._networks[key] = build_network(self, key)
        return self._networks[key]


def _fail(problem: str, key: str, *, file: str, text: str, set_by: dict) -> None:
    """Raise the :class:`ScenarioError` for ``key``.

    An error raised while another one is being handled (a builder that catches
    ``ValueError`` and calls ``fail`` again) is the one already located: it is raised as it
    is, so the message never repeats its location prefix.
    """
    current = sys.exception()
    if isinstance(current, ScenarioError) and problem == str(current):
        raise current
    origin = _set_origin(key, set_by) if key else None
    line = toml_line(text, key) if key and text and origin is None else None
    raise ScenarioError(problem, file=file, key=key, line=line, origin=origin)


def _set_origin(key: str, set_by: dict) -> str | None:
    """The ``--set`` item that set ``key``, a table above it or a key inside it."""
    for path, item in set_by.items():
        if key == path or key.startswith((path + ".", path + "[")) or \
                path.startswith((key + ".", key + "[")):
            return item
    return None


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
        if p.is_dir():
            raise ScenarioError("is a directory, not a scenario file (give a .toml file)",
                                file=p)
        try:
            raw = p.read_bytes()
        except OSError as exc:
            raise ScenarioError(f"cannot read the scenario file ({exc.strerror})",
                                file=p) from None
        if len(raw) > MAX_FILE_BYTES:
            raise ScenarioError(f"{len(raw):,} bytes is not a scenario file (at most "
                                f"{MAX_FILE_BYTES:,}; long input signals belong in CSV "
                                "tables)", file=p)
        try:
            text = raw.decode("utf-8")
        except UnicodeDecodeError as exc:
            raise ScenarioError(f"not a text file: byte {exc.start} is not UTF-8 (a binary "
                                "file? a scenario is TOML text)", file=p) from None
        if "\x00" in text:
            raise ScenarioError("not a text file: it holds NUL bytes (a binary file? a "
                                "scenario is TOML text)", file=p)
        file, base = str(p), p.parent
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        line = getattr(exc, "lineno", None)
        raise ScenarioError(f"not valid TOML: {exc}", file=file, line=line) from None
    except (RecursionError, MemoryError):
        raise ScenarioError("not a usable TOML file: its arrays or tables are nested too "
                            "deeply to read", file=file) from None
    set_by: dict = {}
    if overrides:
        data, set_by = _overridden(data, overrides, file)
    return parse_scenario(data, text=text, file=file, base_dir=base, set_by=set_by)


#: largest scenario file [bytes]
MAX_FILE_BYTES = 10_000_000


def resolve_scenario(scenario, overrides=None) -> Scenario:
    """A :class:`Scenario` from a loaded one, a path or None (the packaged default), with
    ``overrides`` (``key=value`` strings) applied: the one place that does "apply the
    overrides, then parse" for the functions that accept any of the three."""
    if not isinstance(scenario, Scenario):
        return load_scenario(scenario, overrides=overrides)
    if overrides:
        data = apply_overrides(scenario.data, overrides, scenario.file)
        return parse_scenario(data, text=scenario.text, file=scenario.file)
    return scenario


def with_solver_options(scenario: Scenario, items) -> Scenario:
    """``scenario`` with the solver options ``items`` (a mapping of
    :attr:`SolverOptions.MAPPING_KEYS`, e.g. the ``--option KEY=VALUE`` items of the command
    line) over its ``[solver]`` table: both are read together by
    :meth:`SolverOptions.from_mapping`, as the table alone is.  ValueError names a bad key."""
    if not items:
        return scenario
    from dataclasses import replace
    table = {k: v for k, v in scenario.data.get("solver", {}).items() if k != "method"}
    options = SolverOptions.from_mapping({**table, **dict(items)}, dt_out=0.0)
    from ..analysis.launch_metrics import grid_problem
    if grid_problem(options.dt_out):
        raise ValueError(grid_problem(options.dt_out))
    return replace(scenario, options=options)


def toml_value(v) -> str:
    """A TOML literal for an override's value (``key=<literal>``)."""
    if isinstance(v, (bool, np.bool_)):
        return "true" if v else "false"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    f = float(v)
    if math.isnan(f):
        return "nan"
    if math.isinf(f):
        return "inf" if f > 0 else "-inf"
    return repr(f)


def apply_overrides(data: dict, overrides, file: str = "<scenario>") -> dict:
    """A copy of ``data`` with ``key.path=value`` assignments applied."""
    return _overridden(data, overrides, file)[0]


def _overridden(data: dict, overrides, file: str) -> tuple[dict, dict]:
    """``(data with the overrides, {key path: the --set item})``."""
    import re
    out = copy.deepcopy(data)
    set_by = {}
    if isinstance(overrides, str):
        overrides = [overrides]
    for item in overrides:
        if not isinstance(item, str) or "=" not in item:
            raise ScenarioError(f"--set {quote(item)}: expected key.path=value, e.g. "
                                "vehicle.mass=1400", file=file)
        key, raw = item.split("=", 1)
        key = key.strip()
        shown = quote(item)
        parts = re.findall(r"([A-Za-z0-9_\-]+)(?:\[(\d+)\])?", key)
        if not parts or "".join(f"{n}[{i}]" if i else n for n, i in parts) != \
                key.replace(".", ""):
            raise ScenarioError(f"--set {shown}: {quote(key)} is not a key path (names "
                                "joined by '.', with [N] for an entry of an array of tables, "
                                "e.g. coupling[0].drag)", file=file)
        try:
            value = tomllib.loads(f"v = {raw.strip()}")["v"]
        except tomllib.TOMLDecodeError:
            value = raw.strip()
        except (RecursionError, MemoryError):
            raise ScenarioError(f"--set {shown}: the value is nested too deeply to read",
                                file=file) from None
        node: Any = out
        for i, (name, index) in enumerate(parts):
            last = i == len(parts) - 1
            if not isinstance(node, dict):
                raise ScenarioError(f"--set {shown}: {name!r} is not inside a table",
                                    file=file)
            if index:
                seq = node.get(name)
                if not isinstance(seq, list) or int(index) >= len(seq):
                    n = len(seq) if isinstance(seq, list) else 0
                    raise ScenarioError(f"--set {shown}: {name}[{index}] does not exist "
                                        f"({name} has {n} entries)", file=file)
                if last:
                    seq[int(index)] = value
                node = seq[int(index)]
            elif last:
                node[name] = value
            else:
                node = node.setdefault(name, {})
        set_by[key] = item if len(item) <= 80 else shown
    return out, set_by


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
        except ValueError as exc:   # the message quotes the formula (shortened)
            fail(str(exc), key)
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
                   base_dir=None, set_by: dict | None = None) -> Scenario:
    """Validate the tables of a scenario and build its signals and options.

    ``set_by`` maps key paths to the ``--set`` items that gave them: their errors name the
    item instead of a line of the file.  ``base_dir``: the folder that relative paths in
    the scenario (signal tables, ``[scenario] compare``) are read from; default the folder
    of ``file`` when it is a file, else the working directory.
    """
    set_by = dict(set_by or {})
    if base_dir is None and file and Path(file).is_file():
        base_dir = Path(file).parent    # a scenario parsed again (overrides, sweep variants)

    def fail(problem, key=""):
        _fail(problem, key, file=file, text=text, set_by=set_by)

    for name in data:
        if name not in SECTIONS:
            fail(f"unknown table [{name}]{suggest(name, SECTIONS)} "
                 f"(tables: {', '.join(SECTIONS)})", name)
    network = "component" in data or "network" in data
    for required in ("scenario", "component" if network else "inertia"):
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
                if not isinstance(tab, dict):
                    fail(f"must be a table [[{name}]], got {quote(tab)}", path)
                if name == "component":
                    from .schema import component_types
                    types = component_types()
                    ctype = tab.get("type")
                    if ctype not in types:
                        fail(f"component type {ctype!r} is not known"
                             f"{suggest(str(ctype), types)} (types: {', '.join(types)})",
                             f"{path}.type")
                    check_table(tab, types[ctype], path, fail)
                    if ctype == "clutch":
                        check_lining(tab, path, fail)
                elif name == "coupling":
                    ctype = tab.get("type")
                    types = chain_format.COUPLING_TYPES
                    if ctype not in types:
                        fail(f"coupling type {ctype!r} is not known"
                             f"{suggest(str(ctype), types)} (types: "
                             f"{', '.join(types)})", f"{path}.type")
                    check_table(tab, chain_keys(name, ctype), path, fail)
                    if ctype == "clutch":
                        check_lining(tab, path, fail)
                else:
                    check_table(tab, chain_keys(name) if keys is None else keys, path, fail)
                if "friction" in tab:
                    check_table(tab["friction"], FRICTION, f"{path}.friction", fail)
        else:
            if not isinstance(value, dict):
                fail(f"must be a table [{name}]", name)
            check_table(value, chain_keys(name) if keys is None else keys, name, fail)
    if network:
        for other in ("inertia", "coupling", "brake", "engine", "vehicle", "thermal"):
            if other in data:
                fail(f"a network scenario lists its parts as [[component]] tables; "
                     f"[{other}] belongs to the chain format", other)
        if "network" not in data:
            fail("missing required table [network] (with connect = [[...], ...])", "")
    n_in, n_cp = len(data.get("inertia", [])), len(data.get("coupling", []))
    if not network and n_cp != n_in - 1:
        fail(f"{n_in} inertias need {n_in - 1} couplings (coupling k joins inertia k and "
             f"k+1), found {n_cp}", "coupling" if n_cp else "inertia")
    inertias = [t.get("name") for t in data.get("inertia", [])]
    for key, node in chain_format.nodes(data) if not network else ():
        if node not in inertias:
            fail(f"= {node!r} is not an inertia{suggest(str(node), inertias)} (inertias: "
                 f"{', '.join(map(str, inertias))})", key)
    sc = data["scenario"]
    inputs = {}
    raw_inputs = data.get("inputs", {})
    if not isinstance(raw_inputs, dict):
        fail("must be a table of name = signal", "inputs")
    for key, spec in raw_inputs.items():
        inputs[key] = _signal(spec, f"inputs.{key}", base_dir, fail)
    if composites.has_composites(data):      # the signals a composite generates
        from .build import network_document
        for key, formula in network_document(data, fail)[2].items():
            inputs[key] = _signal(formula, f"inputs.{key}", base_dir, fail)
    solver_tab = dict(data.get("solver", {}))
    from ..core.options import DEFAULT_METHOD, SOLVERS
    method = solver_tab.pop("method", DEFAULT_METHOD)
    if method not in SOLVERS:
        fail(f"solver {method!r} is not known{suggest(method, SOLVERS)} "
             f"(solvers: {', '.join(SOLVERS)})", "solver.method")
    try:
        options = SolverOptions.from_mapping(solver_tab, dt_out=0.0)
    except ValueError as exc:
        fail(str(exc), "solver")
    from ..analysis.launch_metrics import grid_problem
    if grid_problem(options.dt_out):
        fail(grid_problem(options.dt_out), "solver.dt_out")
    clutch = sc.get("clutch", "clutch")
    fe_names = [c["name"] for c in data.get("coupling", [])
                if c.get("type") in ("clutch", "one_way_clutch", "lossy_gear")]
    fe_names += [b["name"] for b in data.get("brake", [])]
    fe_names += [c["name"] for c in data.get("component", [])
                 if c.get("type") in FRICTION_TYPES]
    if ("models" in sc or "clutch" in sc) and clutch not in fe_names:
        fail(f"friction element {clutch!r} does not exist{suggest(clutch, fe_names)} "
             f"(friction elements: {', '.join(fe_names) or 'none'})", "scenario.clutch")
    models = tuple(sc.get("models", ()))
    if "models" in sc and not models:
        fail("= [] names no friction model: list at least one (`clutchsim models`), or "
             "leave the key out to run the element's own model", "scenario.models")
    compare = ""
    if "compare" in sc:
        path = Path(sc["compare"]) if base_dir is None else Path(base_dir) / sc["compare"]
        if not path.is_file():
            fail(f"= {sc['compare']!r}: no such scenario file ({path}); the launch to compare "
                 "with is a path relative to this file", "scenario.compare")
        if file and Path(file).exists() and path.resolve() == Path(file).resolve():
            fail(f"= {sc['compare']!r} is this scenario itself; compare with another launch",
                 "scenario.compare")
        compare = str(path)
    scen = Scenario(name=sc["name"], description=sc.get("description", ""),
                    t_end=float(sc["t_end"]), models=models, clutch=clutch, inputs=inputs,
                    solver=method, options=options, data=data, file=file, text=text,
                    set_by=set_by, compare=compare)
    net = scen.network()   # build once: component-level validation errors surface here
    _check_input_ranges(scen, net)
    if "shaft" in sc:
        _check_shaft(scen, net, sc["shaft"], fail)
    return scen


def _check_shaft(scen: Scenario, net, shaft: str, fail) -> None:
    """``[scenario] shaft``: a compliant coupling geared to the clutch's output."""
    names = [c.name for c in net.components if getattr(c, "twist_flanges", None)]
    if shaft not in names:
        fail(f"= {shaft!r} is not a compliant coupling of the network{suggest(shaft, names)} "
             f"(the peak torque is read from one: {', '.join(names) or 'none'})",
             "scenario.shaft")
    clutch = net.component(scen.clutch) if scen.clutch in [c.name for c in net.components] \
        else None
    frm = (clutch.name, clutch.side_b) if clutch is not None and \
        getattr(clutch, "side_b", None) else None
    sh = net.component(shaft)
    if frm is None or net.compile().asm.static_ratio(frm, (shaft, sh.twist_flanges[0])) is None:
        fail(f"= {shaft!r}: no gears join it to the output of the clutch {scen.clutch!r} (the "
             "shaft's capacity is the clutch's times their ratio): name a shaft behind the "
             "clutch on its gear path", "scenario.shaft")


def _check_input_ranges(scen: Scenario, net) -> None:
    """Fail at ``inputs.<name>`` when an input signal leaves the range the component that
    reads it declares (:meth:`clutchsim.network.component.Component.input_ranges`), sampled
    over the run (501 points and the signal's breakpoints: a range check, not a peak
    finder)."""
    for comp in net.components:
        for name, (low, high, unit, what) in comp.input_ranges().items():
            sig = scen.inputs.get(name)
            if sig is None:
                continue
            bps = np.asarray(sig.breakpoints(), dtype=float)
            ts = np.union1d(np.linspace(0.0, scen.t_end, 501),
                            bps[(bps >= 0.0) & (bps <= scen.t_end)])
            x = np.asarray(sig(ts), dtype=float)
            i = int(np.argmax(np.maximum(low - x, x - high)))
            if x[i] < low or x[i] > high:
                u = "" if unit == "-" else f" {unit}"
                scen.fail(f"reaches {x[i]:g}{u} at t = {ts[i]:g} s, outside [{low:g}, "
                          f"{high:g}]{u}: {comp.label} reads it as {what}",
                          f"inputs.{name}")
