"""A scenario's plant as an FMU, FMI 2.0 or 3.0, Model Exchange, co-simulation or both
(:func:`export_fmu`).

The FMU holds ``modelDescription.xml``, ``binaries/<platform>/<id>.so`` (the printed plant,
:mod:`clutchsim.cgen.cprint`, compiled by the system C compiler with the FMI glue
``fmi2_me.c`` or ``fmi3_me.c`` over the FMI-independent core ``plant_core.c``, the
functions both versions share ``fmi_common.c`` and the co-simulation solver
``rosenbrock.c``) and
``sources/`` (the same C files, to rebuild it elsewhere).  It needs neither
Python nor clutchsim to run.  Variables carry clutchsim's own names:

* states (outputs, start = the scenario's initial state): ``omega_<inertia>``, the
  components' states (``clutch.phi``, ``phi_damper``, ...), ``theta_<node>``, the energy
  accounts ``W_in``, ``W_friction``, ...; their derivatives ``der(<state>)``;
* inputs: the scenario's input signals (``throttle``, ``clutch_command``, ...), start = the
  signal at ``t = 0``;
* outputs: the plant's output signals with their units (``T_clutch``, ``w_slip_clutch``,
  ``E_kinetic``, ...);
* parameters: the values the equations read, ``<component>.<key>`` (a friction model's
  ``<element>.friction.<parameter>``, a table's ``<component>.<key>.x[i]``/``.y[i]``),
  tunable; the values that fix inertias and ratios (they enter the reduced mass matrix
  clutchsim computes when it builds the plant) and a friction model's options (model
  (6)'s reset policy decides whether the clutch has an event indicator) are constants:
  change them in the scenario and export again.

The event indicators are the plant's event functions (a friction model's own events,
the engine's stall): see ``docs/fmu.md``.
"""

from __future__ import annotations

import copy
import dataclasses
import datetime
import hashlib
import math
import os
import platform
import re
import shutil
import sys
import tempfile
import xml.etree.ElementTree as ET
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .._version import __version__
from ..cgen.compiler import compile_shared, find_compiler
from ..cgen.cprint import print_c

__all__ = ["FMI_VERSIONS", "KINDS", "FmuError", "FmuExport", "export_fmu", "input_table"]

#: FMI versions and interface kinds this version writes
FMI_VERSIONS = ("2", "3")
KINDS = ("me", "cs", "both")
#: the plant's entry points the FMI glue calls (argument types, see cprint)
_ENTRIES = {"rhs": ("double", "a1", "a1", "a1", "a1"),
            "outputs": ("double", "a1", "a1", "a1", "a1"),
            "events": ("double", "a1", "a1", "a1", "a1"),
            "reset": ("double", "a1", "a1", "a1", "int"),
            "jac": ("double", "a1", "a1", "a1", "a2")}
_HERE = Path(__file__).parent
#: the C files of an FMU besides the printed plant: the FMI glue of each version, the core
_GLUE = {"2": "fmi2_me.c", "3": "fmi3_me.c"}
_CORE = ("plant_core.c", "fmi_common.c", "rosenbrock.c", "ros2.c")

#: SI base-unit exponents (and offset) of the units clutchsim writes
_UNITS = {
    "rad/s": {"rad": 1, "s": -1}, "rad/s²": {"rad": 1, "s": -2}, "rad": {"rad": 1},
    "N·m": {"kg": 1, "m": 2, "s": -2}, "J": {"kg": 1, "m": 2, "s": -2},
    "W": {"kg": 1, "m": 2, "s": -3}, "m/s": {"m": 1, "s": -1}, "m/s²": {"m": 1, "s": -2},
    "m": {"m": 1}, "kg": {"kg": 1}, "s": {"s": 1}, "kg·m²": {"kg": 1, "m": 2},
    "N": {"kg": 1, "m": 1, "s": -2}, "N·m·s/rad": {"kg": 1, "m": 2, "s": -1, "rad": -1},
    "J/K": {"kg": 1, "m": 2, "s": -2, "K": -1}, "W/K": {"kg": 1, "m": 2, "s": -3, "K": -1},
    "N·m/rad": {"kg": 1, "m": 2, "s": -2, "rad": -1}, "°C": {"K": 1, "offset": 273.15},
    "K": {"K": 1}, "1/s": {"s": -1}, "Pa": {"kg": 1, "m": -1, "s": -2},
    "N·s/m": {"kg": 1, "s": -1}, "N/m": {"kg": 1, "s": -2}, "N/s": {"kg": 1, "m": 1, "s": -3},
    "N·m/s": {"kg": 1, "m": 2, "s": -3},
}
_DIMLESS = {"", "-", "1"}


class FmuError(ValueError):
    """A scenario, model or option that cannot be exported (the CLI's exit status 2)."""


@dataclass(frozen=True)
class FmuExport:
    """What :func:`export_fmu` wrote."""

    path: Path
    fmi: str
    kind: str
    model: str
    model_identifier: str
    guid: str
    platform: str
    compiler: str
    states: tuple[str, ...]
    inputs: tuple[str, ...]
    outputs: tuple[str, ...]
    parameters: tuple[str, ...]
    constants: tuple[str, ...]
    event_indicators: tuple[str, ...]
    size_bytes: int

    def to_dict(self) -> dict:
        d = dataclasses.asdict(self)
        d["path"] = str(self.path)
        for k in ("states", "inputs", "outputs", "parameters", "constants",
                  "event_indicators"):
            d[k] = list(d[k])
        return d


def _platform(fmi: str) -> tuple[str, str]:
    """The binaries folder (FMI 2: ``linux64``; FMI 3: ``x86_64-linux``) and the library's
    extension for this machine."""
    if sys.platform.startswith("linux"):
        system, ext = "linux", ".so"
    elif sys.platform == "darwin":
        system, ext = "darwin", ".dylib"
    else:
        raise FmuError(f"cannot build FMU binaries on {sys.platform} ({platform.machine()}): "
                       "clutchsim builds them for Linux and macOS")
    if fmi == "2":
        return f"{system}{'64' if sys.maxsize > 2**32 else '32'}", ext
    arch = {"amd64": "x86_64", "arm64": "aarch64"}.get(platform.machine().lower(),
                                                       platform.machine().lower())
    return f"{arch}-{system}", ext


def _fixed_keys(c) -> dict:
    """The keys of ``c.pack()`` that cannot be set in the FMU alone, and why.

    ``None``: a value that fixes an inertia or a rigid ratio of ``c``.  Those values also
    enter the derived block of the parameter vector (the reduced mass matrix and its
    relatives, computed in Python when the plant is built): set alone, they would disagree
    with it.  A list of keys: the derived values of ``c.pack()`` it feeds (a vehicle's grade
    feeds its grade force ``f_grade``, which the equations read: set alone, the grade would
    change nothing).  A value merely computed from them (a rolling force from the mass) is
    the equations' own and stays tunable."""
    base = (c.inertias(), c.constraints())
    pack = c.pack()
    derived = {k: v for k, v in pack.items() if k not in c.values}
    out = {}
    for name, v in c.values.items():
        if name not in pack or isinstance(v, bool) or not isinstance(v, int | float):
            continue
        c2 = copy.copy(c)
        c2.values = dict(c.values)
        c2.values[name] = float(v) * 1.25 + 0.5
        try:
            moved = (c2.inertias(), c2.constraints()) != base
            pack2 = c2.pack()
        except (ValueError, ZeroDivisionError):
            moved, pack2 = True, pack
        if moved:
            out[name] = None
            continue
        fed = sorted(k for k, d in derived.items() if not _same(pack2.get(k), d))
        if fed:
            out[name] = fed
    return out


def _same(a, b) -> bool:
    try:
        return bool(np.array_equal(np.asarray(a, dtype=float), np.asarray(b, dtype=float)))
    except (TypeError, ValueError):
        return a == b


#: why a constant is not tunable: a value fixing an inertia or a ratio (the default), or a
#: friction model's option (a code, such as model (6)'s reset policy, that decides the
#: plant's equations and event indicators)
_STRUCTURAL = "structural (an inertia or a ratio): change it in the scenario and export again"
_OPTION = "an option of the model (it decides the equations and the event indicators): " \
    "change it in the scenario and export again"


def _param(slot: int, name: str, unit: str, doc: str, tunable: bool,
           why: str = _STRUCTURAL) -> dict:
    return {"slot": slot, "name": name, "unit": unit, "doc": doc, "tunable": tunable,
            "why": why}


def _parameters(plan, comps) -> list[dict]:
    """One entry per value of the parameter vector the equations read: slot, name, unit,
    description, tunable."""
    by_name = {c.name: c for c in comps}
    fixed_of: dict = {}
    out = []
    for c_name, key, n_val in plan._pack_shape:
        c = by_name[c_name]
        units = {p.name: p.unit for p in getattr(c, "params", ())}
        docs = {p.name: p.doc for p in getattr(c, "params", ())}
        fixed = fixed_of[c_name] if c_name in fixed_of else \
            fixed_of.setdefault(c_name, _fixed_keys(c))
        structural = key in fixed and fixed[key] is None
        if n_val == 0:
            fed = fixed.get(key)
            why = _STRUCTURAL if fed is None else (
                f"feeds {', '.join(f'{c_name}.{k}' for k in fed)}, computed when the plant is "
                "built (set those, or change it in the scenario and export again)")
            out.append(_param(plan.slot[(c_name, key)], f"{c_name}.{key}",
                              units.get(key, ""), docs.get(key, ""), key not in fixed, why))
            continue
        off, n = plan.tables[(c_name, key)]
        if key == "model" and not dataclasses.is_dataclass(c.model):
            # a lossy gear's loss table (its columns, one row per speed)
            from ..network.components.lossy_gear import LOSS_COLUMNS
            rows = n_val // len(LOSS_COLUMNS)
            for k, col in enumerate(LOSS_COLUMNS):
                for i in range(rows):
                    out.append(_param(off + k * rows + i, f"{c_name}.loss_table.{col}[{i}]",
                                      "rad/s" if col == "speed" else
                                      ("N·m" if col.startswith("tau") else "1"),
                                      f"loss table: {col}, row {i}", not structural))
            continue
        if key == "model":
            model = c.model
            fields = [f.name for f in dataclasses.fields(model)]
            options = {f.name for f in dataclasses.fields(model) if f.type in ("str", str)}
            info = getattr(model, "parameter_info", {})
            if len(fields) != n_val:
                fields = [f"model[{i}]" for i in range(n_val)]
            for i, f in enumerate(fields):
                _kind, doc = info.get(f, ("", ""))
                out.append(_param(off + i, f"{c_name}.friction.{f}",
                                  model.unit_of(f, c.domain or "rotational") if f in info
                                  else "",
                                  f"{model.name}: {doc}" if doc else model.name,
                                  not structural and f not in options,
                                  _OPTION if f in options else _STRUCTURAL))
            continue
        for i in range(n):
            out.append(_param(off + i, f"{c_name}.{key}.x[{i}]", "", f"{key}: breakpoint {i}",
                              not structural))
        for i in range(n):
            out.append(_param(off + n + i, f"{c_name}.{key}.y[{i}]", "", f"{key}: value {i}",
                              not structural))
    return out


def _num(x: float) -> str:
    x = float(x)
    if not np.isfinite(x):
        raise FmuError(f"a start value is not finite ({x!r})")
    return repr(x)


def _c_array(name: str, ctype: str, values) -> str:
    vals = ", ".join(values) if len(values) else "0"
    return f"static const {ctype} {name}[{max(len(values), 1)}] = {{{vals}}};"


def _c_string(s: str) -> str:
    return '"' + s.encode("ascii", "backslashreplace").decode().replace("\\", "\\\\") \
        .replace('"', '\\"') + '"'


def _variables(*, states, state_units, y0, inputs, input_units, u0, outputs, output_units,
               params, p, events, vr_u, vr_y, vr_p, vr_z) -> list[dict]:
    """The FMU's variables, in order: name, value reference, causality, variability,
    initial, unit, start, the value reference of the state a derivative belongs to, the
    role in the model structure and a description (one list for FMI 2 and FMI 3)."""
    out = []

    def var(name, vr, causality, variability, initial, unit="", start=None, der=None,
            role=None, desc=""):
        out.append({"name": name, "vr": vr, "causality": causality,
                    "variability": variability, "initial": initial, "unit": unit,
                    "start": None if start is None else _num(start), "der": der,
                    "role": role, "desc": desc})

    for i, (s, u) in enumerate(zip(states, state_units)):
        var(s, i, "output", "continuous", "exact", u, y0[i], role="state")
    for i, (s, u) in enumerate(zip(states, state_units)):
        var(f"der({s})", len(states) + i, "local", "continuous", "calculated", _deriv_unit(u),
            der=i, role="derivative")
    for i, (s, u) in enumerate(zip(inputs, input_units)):
        var(s, vr_u + i, "input", "continuous", None, u, u0[i],
            desc="input signal of the scenario")
    for i, (s, u) in enumerate(zip(outputs, output_units)):
        var(s, vr_y + i, "output", "continuous", "calculated", u, role="output")
    for q in params:
        if q["tunable"]:
            var(q["name"], vr_p + q["slot"], "parameter", "tunable", "exact", q["unit"],
                p[q["slot"]], desc=q["doc"])
        else:
            var(q["name"], vr_p + q["slot"], "local", "constant", "exact", q["unit"],
                p[q["slot"]], desc=(q["doc"] + "; " if q["doc"] else "") + q["why"])
    for k, e in enumerate(events):
        var(f"event_indicator[{k}]", vr_z + k, "local", "continuous", "calculated",
            role="indicator", desc=e)
    return out


def _header(root, *, ident, t_end, rtol, variables, fmi, kind, fixed_step=None):
    """The interface elements (ModelExchange, CoSimulation), the units and the default
    experiment.  Both interfaces provide directional derivatives (plant_core.c; FMI 3 also
    adjoint ones); FMI 3's co-simulation has no event mode: it handles its events inside
    fmi3DoStep, as FMI 2's does."""
    common = {"modelIdentifier": ident, "needsExecutionTool": "false",
              "canBeInstantiatedOnlyOncePerProcess": "false"}
    if fmi == "2":
        common.update({"canNotUseMemoryManagementFunctions": "false",
                       "canGetAndSetFMUstate": "false", "canSerializeFMUstate": "false",
                       "providesDirectionalDerivative": "true"})
        me = {**common, "completedIntegratorStepNotNeeded": "true"}
        cs = {**common, "canHandleVariableCommunicationStepSize": "true",
              "canInterpolateInputs": "true", "maxOutputDerivativeOrder": "0",
              "canRunAsynchronuously": "false"}
    else:
        common.update({"canGetAndSetFMUState": "false", "canSerializeFMUState": "false",
                       "providesDirectionalDerivatives": "true",
                       "providesAdjointDerivatives": "true"})
        me = {**common, "needsCompletedIntegratorStep": "false"}
        cs = {**common, "canHandleVariableCommunicationStepSize": "true",
              "maxOutputDerivativeOrder": "0", "hasEventMode": "false",
              "providesIntermediateUpdate": "false", "mightReturnEarlyFromDoStep": "false"}
    if kind in ("me", "both"):
        ET.SubElement(root, "ModelExchange", me)
    if fixed_step and fmi == "3":
        cs["fixedInternalStepSize"] = _num(fixed_step)
    if kind in ("cs", "both"):
        ET.SubElement(root, "CoSimulation", cs)
    used = sorted({v["unit"] for v in variables if v["unit"] not in _DIMLESS})
    if used:
        ud = ET.SubElement(root, "UnitDefinitions")
        for u in used:
            el = ET.SubElement(ud, "Unit", {"name": u})
            base = dict(_UNITS.get(u, {}))
            if base:
                ET.SubElement(el, "BaseUnit", {k: str(v) for k, v in base.items()})
    ET.SubElement(root, "DefaultExperiment", {"startTime": "0.0", "stopTime": _num(t_end),
                                              "tolerance": _num(rtol),
                                              **({"stepSize": _num(fixed_step)}
                                                 if fixed_step else {})})


def _attrs(v, keys=("causality", "variability", "initial")) -> dict:
    a = {"name": v["name"], "valueReference": str(v["vr"])}
    if v["desc"]:
        a["description"] = v["desc"]
    a.update({k: v[k] for k in keys if v[k] is not None})
    return a


def _model_description(*, fmi, kind, name, ident, guid, description, t_end, rtol,
                       variables, n_events, vr_time, fixed_step=None) -> bytes:
    """``modelDescription.xml`` of FMI ``fmi`` ("2" or "3") for ``variables``
    (:func:`_variables`)."""
    root = ET.Element("fmiModelDescription", {
        "fmiVersion": f"{fmi}.0", "modelName": name,
        ("guid" if fmi == "2" else "instantiationToken"): guid, "description": description,
        "generationTool": f"clutchsim {__version__}",
        "generationDateAndTime": datetime.datetime.now(datetime.UTC).strftime(
            "%Y-%m-%dT%H:%M:%SZ"),
        "variableNamingConvention": "flat",
        **({"numberOfEventIndicators": str(n_events)} if fmi == "2" else {})})
    _header(root, ident=ident, t_end=t_end, rtol=rtol, variables=variables, fmi=fmi,
            kind=kind, fixed_step=fixed_step)
    mv = ET.SubElement(root, "ModelVariables")
    if fmi == "2":
        variables = [v for v in variables if v["role"] != "indicator"]
        index = {v["vr"]: i + 1 for i, v in enumerate(variables)}
        for v in variables:
            sv = ET.SubElement(mv, "ScalarVariable", _attrs(v))
            real = {"unit": v["unit"], "start": v["start"],
                    "derivative": None if v["der"] is None else str(index[v["der"]])}
            ET.SubElement(sv, "Real", {k: x for k, x in real.items()
                                       if x is not None and not (k == "unit" and x in _DIMLESS)})
        ms = ET.SubElement(root, "ModelStructure")
        for tag, roles in (("Outputs", ("state", "output")), ("Derivatives", ("derivative",))):
            el = ET.SubElement(ms, tag)
            for v in variables:
                if v["role"] in roles:
                    ET.SubElement(el, "Unknown", {"index": str(index[v["vr"]]),
                                                  **_dependencies(v, variables, index)})
        iu = ET.SubElement(ms, "InitialUnknowns")
        for v in variables:
            if v["initial"] == "calculated" and v["role"] in ("output", "derivative"):
                ET.SubElement(iu, "Unknown", {"index": str(index[v["vr"]])})
    else:
        ET.SubElement(mv, "Float64", {"name": "time", "valueReference": str(vr_time),
                                      "causality": "independent", "variability": "continuous",
                                      "description": "simulation time"})
        for v in variables:
            a = _attrs(v)
            for k, x in (("start", v["start"]), ("unit", v["unit"]),
                         ("derivative", None if v["der"] is None else str(v["der"]))):
                if x is not None and not (k == "unit" and x in _DIMLESS):
                    a[k] = x
            ET.SubElement(mv, "Float64", a)
        ms = ET.SubElement(root, "ModelStructure")
        vrs = {v["vr"]: v["vr"] for v in variables}
        for tag, pick, deps in (
                ("Output", lambda v: v["role"] in ("state", "output"), True),
                ("ContinuousStateDerivative", lambda v: v["role"] == "derivative", True),
                ("InitialUnknown", lambda v: v["initial"] == "calculated"
                 and v["role"] in ("output", "derivative"), False),
                ("EventIndicator", lambda v: v["role"] == "indicator", False)):
            for v in variables:
                if pick(v):
                    ET.SubElement(ms, tag, {"valueReference": str(v["vr"]),
                                            **(_dependencies(v, variables, vrs, vr_time)
                                               if deps else {})})
    ET.indent(root)
    return ET.tostring(root, encoding="UTF-8", xml_declaration=True)


def _dependencies(v, variables, ref, time=None) -> dict:
    """The ``dependencies`` of an output or a derivative on the knowns (the states, the
    inputs and, in FMI 3, the time: ``time``, its value reference; ``ref``: a known's value
    reference -> its index (FMI 2) or value reference (FMI 3)).  A state as output depends on itself with the factor 1 (``constant``); a
    derivative or an output signal is declared to depend on every known (``dependent``:
    the plant's exact Jacobian says nothing of structural zeros, and a dependency left out
    would be a claim)."""
    if v["role"] == "state":
        return {"dependencies": str(ref[v["vr"]]), "dependenciesKind": "constant"}
    knowns = [ref[k["vr"]] for k in variables if k["role"] == "state"
              or k["causality"] == "input"] + ([] if time is None else [time])
    return {"dependencies": " ".join(map(str, knowns)),
            "dependenciesKind": " ".join(["dependent"] * len(knowns))}


def _deriv_unit(u: str) -> str:
    known = {"rad": "rad/s", "rad/s": "rad/s²", "J": "W", "m": "m/s", "m/s": "m/s²"}
    return known.get(u, "")


def discrete_mask(plan, comps) -> list[int]:
    """1 for each state of the plant that is discrete (:meth:`Component.discrete_states`:
    it changes only at events), 0 for the continuous ones."""
    mask = [0] * len(plan.state_names)
    for c in comps:
        for key in c.discrete_states():
            mask[plan.state_index[(c.name, key)]] = 1
    return mask


def model_h(title: str, system, u0, p, settable, defines: dict, discrete=None) -> str:
    """``model.h``: the layout of a printed plant for its C drivers (the FMUs' glue, the
    real-time kernel): sizes ``CS_NX``, ``CS_NU``, ``CS_NY``, ``CS_NZ``, ``CS_NP``, the start
    values ``cs_y0``, ``cs_u0``, ``cs_p0``, which parameters may be set (``cs_p_settable``),
    which states are discrete (``cs_discrete``, :func:`discrete_mask`; none if not given),
    the event functions' directions and names, and the driver's own ``defines``."""
    nx, nu, ny = len(system.state_names), len(system.input_names), len(system.output_names)
    nz = len(system.event_names)
    discrete = [0] * nx if discrete is None else discrete
    return "\n".join([
        f"/* Layout of {title} (clutchsim {__version__}). Do not edit. */",
        f"#define CS_NX {nx}", f"#define CS_NU {nu}", f"#define CS_NY {ny}",
        f"#define CS_NZ {nz}", f"#define CS_NP {len(p)}",
        *(f"#define {k} {v}" for k, v in defines.items()),
        _c_array("cs_y0", "double", [_num(v) for v in system.y0]),
        _c_array("cs_u0", "double", [_num(v) for v in u0]),
        _c_array("cs_p0", "double", [_num(v) for v in p]),
        _c_array("cs_p_settable", "int", [str(int(v)) for v in settable]),
        _c_array("cs_discrete", "int", [str(int(v)) for v in discrete]),
        _c_array("cs_event_dir", "int", [str(int(d)) for d in system.event_directions]),
        f"static const char *cs_event_names[{max(nz, 1)}] = {{"
        + (", ".join(_c_string(e) for e in system.event_names) or "0") + "};", ""])


def _identifier(out: Path) -> str:
    stem = out.name[:-4] if out.name.lower().endswith(".fmu") else out.name
    ident = re.sub(r"\W", "_", stem, flags=re.ASCII) or "clutchsim"
    return "_" + ident if ident[0].isdigit() else ident


def _plant_of(scenario, model):
    """(plan, components, system, inputs at t = 0) of ``scenario`` with ``model``."""
    from ..network import compile_network
    obj = scenario.network(model)
    plan = compile_network(obj)
    u0 = {n: float(np.asarray(s(0.0)).ravel()[0]) for n, s in scenario.inputs.items()}
    missing = [n for n in plan.input_names if n not in u0]
    if missing:
        raise FmuError(f"scenario {scenario.name!r} has no input signal {missing[0]!r} "
                       "that its plant reads ([inputs])")
    system = plan.system(obj.components, inputs0=u0)
    return plan, obj.components, system, u0


def printed_plant(sc, model):
    """``(plan, components, system, inputs at t = 0, program)``: the plant of scenario
    ``sc`` with ``model`` on its clutch element and its C program (:func:`print_c`), which
    the FMUs and the real-time kernel compile; :class:`FmuError` if it cannot be printed."""
    from ..cgen.cprint import CPrintError
    plan, comps, system, u0 = _plant_of(sc, model)
    try:
        program = print_c(plan.module, _ENTRIES)
    except CPrintError as exc:
        raise FmuError(f"cannot export {sc.name!r} with model {model!r}: {exc}") from exc
    return plan, comps, system, u0, program


def export_fmu(scenario, out, model: str | None = None, *, fmi: str = "2", kind: str = "me",
               overrides=None, fixed_step: float | None = None) -> FmuExport:
    """Write the FMU of ``scenario`` with ``model`` on its clutch element to ``out``.

    Parameters
    ----------
    scenario : Scenario, str, Path or None
        A loaded scenario or a path (None: the default launch).
    out : str or Path
        The ``.fmu`` file; written atomically (it appears only when complete).
    model : str, optional
        Friction model of the clutch element (default: the scenario's first model).
    fmi, kind : str
        FMI version (``"2"`` or ``"3"``) and interface (``"me"``, Model Exchange; ``"cs"``,
        co-simulation with the FMU's own ROS2 solver; ``"both"``).
    overrides : sequence of str, optional
        ``key.path=value`` assignments (with a path or None).
    fixed_step : float, optional
        Co-simulation only: integrate with fixed ROS2 steps of this size [s] and apply the
        events at the steps' ends, as the real-time kernel does
        (:mod:`clutchsim.fmu.realtime`; a communication step must be a multiple of it),
        instead of the variable-step solver.

    Raises :class:`FmuError` for an option, a scenario or a model that cannot be exported
    (and :class:`~clutchsim.cgen.compiler.CompilerError` without a C compiler).
    """
    from ..scenario import resolve_scenario
    fmi, kind = str(fmi), str(kind)
    if fmi not in FMI_VERSIONS:
        raise FmuError(f"--fmi {fmi}: this version writes FMI "
                       f"{', '.join(v + '.0' for v in FMI_VERSIONS)} only")
    if kind not in KINDS:
        raise FmuError(f"--kind {kind}: one of {', '.join(KINDS)} (Model Exchange, "
                       "co-simulation, both)")
    if fixed_step is not None:
        if kind != "cs":
            raise FmuError(f"a fixed step ({fixed_step!r} s) is for co-simulation only "
                           f"(--kind cs), not --kind {kind}")
        if isinstance(fixed_step, bool) or not isinstance(fixed_step, (int, float)) or not (
                math.isfinite(fixed_step) and 0.0 < fixed_step <= 0.1):
            raise FmuError(f"fixed step {fixed_step!r}: a number of seconds in (0, 0.1]")
    out = Path(out)
    if out.suffix.lower() != ".fmu":
        raise FmuError(f"--out {out}: an FMU file name ends in .fmu")
    if out.is_dir():
        raise FmuError(f"--out {out}: is a directory")
    plat, ext = _platform(fmi)
    cc = find_compiler()
    sc = resolve_scenario(scenario, overrides)
    if model is None and sc.models:
        model = sc.models[0]
    plan, comps, system, u0, program = printed_plant(sc, model)
    ident = _identifier(out)
    p = np.asarray(system.params, dtype=float)
    params = _parameters(plan, comps)
    nx, nu, ny = len(system.state_names), len(system.input_names), len(system.output_names)
    nz, np_ = len(system.event_names), len(p)
    vr_u, vr_y = 2 * nx, 2 * nx + nu
    vr_p = vr_y + ny
    settable = np.zeros(np_, dtype=int)
    for q in params:
        settable[q["slot"]] = int(q["tunable"])
    h = hashlib.blake2b(digest_size=16)
    for part in (program.source, repr(p.tolist()), repr(system.y0.tolist()),
                 repr(system.state_names), repr(system.output_names), __version__):
        h.update(part.encode())
    hx = h.hexdigest()
    guid = f"{{{hx[:8]}-{hx[8:12]}-{hx[12:16]}-{hx[16:20]}-{hx[20:32]}}}"
    header = model_h(f"the FMU {ident}", system, [u0[n] for n in system.input_names], p,
                     settable, {"CS_VR_U": vr_u, "CS_VR_Y": vr_y, "CS_VR_P": vr_p,
                                "CS_GUID": _c_string(guid),
                                "CS_MODEL_EXCHANGE": int(kind in ("me", "both")),
                                "CS_COSIM": int(kind in ("cs", "both")),
                                "CS_FIXED_STEP": repr(float(fixed_step or 0.0))},
                     discrete=discrete_mask(plan, comps))
    variables = _variables(
        states=system.state_names, state_units=system.state_units, y0=system.y0,
        inputs=system.input_names, input_units=system.input_units,
        u0=[u0[n] for n in system.input_names], outputs=system.output_names,
        output_units=system.output_units, params=params, p=p, events=system.event_names,
        vr_u=vr_u, vr_y=vr_y, vr_p=vr_p, vr_z=vr_p + np_)
    xml = _model_description(
        fmi=fmi, kind=kind, name=sc.name, ident=ident, guid=guid,
        description=f"{sc.name}: clutchsim plant with {model or 'its own models'}",
        t_end=sc.t_end, rtol=sc.options.rtol, variables=variables, n_events=nz,
        vr_time=vr_p + np_ + nz, fixed_step=fixed_step)
    out.parent.mkdir(parents=True, exist_ok=True)
    work = Path(tempfile.mkdtemp(prefix=f".{out.name}.", dir=out.parent))
    try:
        src = work / "sources"
        src.mkdir()
        (src / "plant.c").write_text(program.source)
        (src / "model.h").write_text(header)
        glue = _GLUE[fmi]
        for f in (glue, *_CORE):
            shutil.copyfile(_HERE / f, src / f)
        binary = work / "binaries" / plat / f"{ident}{ext}"
        binary.parent.mkdir(parents=True)
        compile_shared([src / glue, src / "plant.c"], binary, include=[src])
        (work / "modelDescription.xml").write_bytes(xml)
        zpath = work / "fmu.zip"
        with zipfile.ZipFile(zpath, "w", zipfile.ZIP_DEFLATED) as zf:
            for f in ("modelDescription.xml", f"binaries/{plat}/{ident}{ext}",
                      "sources/plant.c", "sources/model.h", f"sources/{glue}",
                      *(f"sources/{c}" for c in _CORE)):
                zf.write(work / f, f)
        os.replace(zpath, out)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return FmuExport(
        path=out, fmi=f"{fmi}.0", kind=kind, model=system.metadata["models"].get(sc.clutch, model
                                                                            or ""),
        model_identifier=ident, guid=guid, platform=plat, compiler=Path(cc).name,
        states=system.state_names, inputs=system.input_names, outputs=system.output_names,
        parameters=tuple(q["name"] for q in params if q["tunable"]),
        constants=tuple(q["name"] for q in params if not q["tunable"]),
        event_indicators=system.event_names, size_bytes=out.stat().st_size)


def input_table(scenario, t_end: float | None = None, dt: float = 1e-3,
                names=None) -> np.ndarray:
    """The scenario's input signals as the structured array FMPy's ``simulate_fmu(input=)``
    reads (``time`` and one column per input): samples every ``dt`` and at every breakpoint,
    a jump as two rows at the same time (the value before, then after), so FMPy's linear
    interpolation is exact for piecewise-linear signals."""
    from ..scenario import resolve_scenario
    sc = resolve_scenario(scenario, None)
    t_end = float(sc.t_end if t_end is None else t_end)
    names = list(sc.inputs) if names is None else list(names)
    sigs = [sc.inputs[n] for n in names]
    grid = set(np.round(np.arange(0.0, t_end + 0.5 * dt, dt), 12).tolist())
    bps = set()
    for s in sigs:
        bps.update(float(b) for b in np.asarray(s.breakpoints(), dtype=float).ravel()
                   if 0.0 < b < t_end)
    times = sorted(grid | bps | {t_end})
    rows = []
    for t in times:
        if t in bps:
            before = np.nextafter(t, -np.inf)
            rows.append((t, *[float(np.asarray(s(before)).ravel()[0]) for s in sigs]))
        rows.append((t, *[float(np.asarray(s(t)).ravel()[0]) for s in sigs]))
    dtype = [("time", np.float64)] + [(n, np.float64) for n in names]
    return np.array(rows, dtype=dtype)
