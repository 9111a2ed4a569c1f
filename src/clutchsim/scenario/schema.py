"""The scenario file schema: every table and key, its type, unit, range and meaning.

The same tables drive validation (:func:`check_table`) and the generated reference
``docs/scenario-reference.md`` (:func:`reference_markdown`).
"""

from __future__ import annotations

import difflib
import functools
import math
from dataclasses import dataclass, replace

from .._util import quote
from ..core.controllers import CONTROLLERS
from ..core.options import DEFAULT_METHOD, SOLVERS
from ..network.wear import WearLaw
from .chain_format import CHAIN_ONLY, COUPLING_TYPES, KIND_OF

__all__ = ["LINING_KEYS", "SECTIONS", "Key", "chain_keys", "check_lining", "check_table",
           "key_spec", "reference_markdown", "table_keys"]


@dataclass(frozen=True)
class Key:
    """One key of a scenario table."""

    name: str
    kind: str            # number, int, str, bool, numbers, strs, table, tables, signal
    doc: str
    unit: str = ""
    required: bool = False
    low: float | None = None
    high: float | None = None
    strict: bool = False   # low is exclusive
    nonzero: bool = False  # 0 excluded


def _n(name, doc, unit="", **kw):
    return Key(name, "number", doc, unit, **kw)


SCENARIO = (
    Key("name", "str", "Short name of the scenario.", required=True),
    Key("description", "str", "What the scenario shows."),
    _n("t_end", "End time of the run.", "s", required=True, low=0.0, strict=True, high=1e6),
    Key("models", "strs", "Friction models to run for the element named by `clutch` "
        "(default: the element's own model)."),
    Key("clutch", "str", "Name of the friction element the models replace and the launch "
        "metrics refer to (default `clutch`)."),
    Key("expect_lockup", "bool", "Whether that element should lock up during the run: if it "
        "never does, the run gets a warning (default: true when it is a `clutch`, as in a "
        "launch; false for the other kinds)."),
    Key("shaft", "str", "A compliant coupling (a `spring_damper`, a lash, ...) whose peak "
        "torque each run reports against what the clutch can put through it: "
        "`peak_shaft_torque_Nm`, `shaft_capacity_Nm` (the clutch's nominal capacity times "
        "the gears' ratio to the shaft), `peak_shaft_torque_over_capacity` (the abuse load "
        "cases of clutch sizing, docs/components.md)."),
    Key("compare", "str", "Another scenario file (relative to this one) to compare this "
        "launch with: `clutchsim run` runs it too and writes `quality_comparison.json` (the "
        "launch-quality metrics, one row per launch, in the report) and "
        "`comparison_launch.png`."),
)
SOLVER = (
    Key("method", "str", f"{DEFAULT_METHOD} (default), "
        + ", ".join(m for m in SOLVERS if m != DEFAULT_METHOD) + "."),
    _n("rtol", "Relative tolerance.", low=1e-14, high=1.0),
    _n("atol", "Absolute tolerance.", low=0.0, strict=True, high=1.0),
    _n("h_max", "Largest step (0: none).", "s", low=0.0, high=1e6),
    _n("dt_out", "Output grid spacing (0: every step).", "s", low=0.0, high=1e6),
    Key("max_steps", "int", "Step budget.", low=1, high=1e9),
    _n("wall_time", "Wall-time budget of one run (0: none).", "s", low=0.0, high=1e6),
    Key("chatter_events", "int", "Chatter detection: this many events ...", low=0, high=1e9),
    _n("chatter_window", "... within this time stop the run (default: 1e-4 of t_end, at most 0.4 ms).", "s",
       low=0.0, high=1e6),
    Key("controller", "str", "Step-size controller: " + ", ".join(CONTROLLERS)
        + " (default: the method's own; see docs/core.md)."),
)
FRICTION = (
    Key("model", "str", "Friction model name (`clutchsim models`).", required=True),
    Key("parameter_set", "str", "Parameter set (default: the model's own)."),
    Key("overrides", "table", "Model parameters replacing those of the set (SI, in the "
        "element's domain: N·m, rad, rad/s on a clutch or brake; N, m, m/s on a translational "
        "friction element)."),
    Key("alternatives", "table", "Parameters per model name, used when `--model` selects "
        "another model for this element: `{coulomb-robust = {F_c = .., F_s = ..}}`."),
)
#: the keys of a friction element besides its parameters (a clutch, a brake)
FRICTION_ELEMENT = (
    Key("command", "str", "Actuation input: COM in [0, 1] (seed eqs. 1-2), or the pedal / "
        "actuator position read through `clamp_table`; in a network also another "
        "component's signal (`<component>.<signal>`), e.g. a release system's clamp force "
        "[N] with `clamp_reference`.", required=True),
    Key("friction", "table", "Friction model of the element (see [friction]).", required=True),
    Key("clamp_table", "table", "Diaphragm-spring characteristic `{position = [...], force = "
        "[...]}`: clamp force normalised by the force at which the model's capacity is given "
        "[-] against position [-]."),
    Key("mu_temperature", "table", "`{theta = [°C ...], factor = [...]}`: mu(theta)/mu_ref at the "
        "first heat node."),
    Key("mu_slip", "table", "`{slip = [rad/s ...], factor = [...]}`: mu(|w|)/mu_ref."),
    Key("heat", "tables", "`[{node = \"pressure_plate\", share = 0.5}, ...]`: where the "
        "friction power |T·w| goes."),
    Key("wear", "table", "Lining wear law `{"
        + ", ".join(f"{k} = {u}" for k, u in WearLaw.UNITS.items())
        + "}` (clutchsim.network.wear; needs `heat`): adds the state `wear_<name>` [m]."),
)
#: the signal that strikes a clutch's or brake's fault (docs/components.md, faults)
FAULT_INPUT = Key("fault_input", "str", "Fault trigger: an input signal; the fault "
                  "(`fault_capacity_factor`, `fault_drag`) strikes when it first rises past "
                  "0.5, instead of at `fault_time` (fault injection from a test bench or an "
                  "FMU input).")
#: the lining geometry keys of a clutch: the launch metrics read them, the plant does not
LINING = (
    _n("r_inner", "Inner radius of the friction linings (with `r_outer`; only for the "
       "launch-quality metrics per lining area, docs/launch-quality.md).", "m", low=0.0,
       strict=True, high=0.5),
    _n("r_outer", "Outer radius of the friction linings (> `r_inner`; a dry clutch disc is "
       "180-280 mm across in a car, up to 430 mm in a truck: at most 0.5 m).", "m", low=0.0,
       strict=True, high=0.5),
    Key("faces", "int", "Number of friction faces (default 2: a single-plate dry clutch).",
        "-", low=1, high=100),
)
LINING_KEYS = tuple(k.name for k in LINING)
#: pressure-plate runout of a clutch (a clamp-load oscillation; docs/judder.md)
RUNOUT = Key("runout", "table", "`{amplitude = 0.02, order = 1}`: clamp-load oscillation "
             "`1 + amplitude·sin(order·φ_b)` of pressure-plate runout, `φ_b` the angle of "
             "side b (the input shaft); amplitude in [0, 1), order > 0 per turn.")
LOSS_TABLE = Key("loss_table", "table", "`{speed = [rad/s ...], eta_mf1 = [...], eta_mf2 = "
                 "[...], tau_bf1 = [N·m ...], tau_bf2 = [N·m ...]}`: mesh efficiency with "
                 "power flowing a->b (eta_mf1) and b->a (eta_mf2), in (0, 1], and bearing "
                 "friction torques (>= 0), against |omega_a| (first >= 0, increasing). "
                 "Default: no losses (an ideal gear).")

#: network component types with a `friction` table (a friction model; `--model` acts on them)
FRICTION_TYPES = ("clutch", "brake", "support_friction", "translational_brake", "cone_clutch",
                  "wet_clutch")

#: the keys of a translational friction element besides its parameters
TRANSLATIONAL_FRICTION = (
    Key("friction", "table", "Friction model of the element (see [friction]); its numbers are "
        "read in translational units (N, m, m/s): a rotational parameter set is refused.",
        required=True),
    Key("mu_slip", "table", "`{slip = [m/s ...], factor = [...]}`: mu(|v|)/mu_ref (a "
        "tabulated friction characteristic, as Modelica's f_pos table)."),
    Key("heat", "tables", "`[{node = \"housing\", share = 1.0}, ...]`: where the friction "
        "power |F·v| goes."),
)


@functools.cache
def _component_keys(cls) -> tuple:
    """The scenario keys of a network component, generated from its declaration."""
    keys = [Key("name", "str", "Unique name.", required=True),
            Key("type", "str", f"{cls.kind}: {cls.title}.", required=True)]
    for p in cls.params:
        optional = getattr(cls, "alternative_keys", {}).get(p.name)
        doc = p.doc[:1].upper() + p.doc[1:] + (f" (or give {optional})." if optional else ".")
        keys.append(Key(p.name, "number", doc, "" if p.unit == "-" else p.unit,
                        required=p.default is None and not optional,
                        low=p.low, high=p.high, strict=p.strict, nonzero=p.nonzero))
    extra = {
        "clutch": (*FRICTION_ELEMENT, RUNOUT, FAULT_INPUT, *LINING),
        "brake": (*FRICTION_ELEMENT, RUNOUT, FAULT_INPUT),
        "dual_mass_flywheel": (FRICTION_ELEMENT[1], *FRICTION_ELEMENT[3:6]),
        "torque_converter": (
            Key("speed_ratio", "numbers", "Speed ratios turbine/pump of the tables, strictly "
                "increasing in [0, 1), ending at the coupling point.", required=True),
            Key("K", "numbers", "Capacity factor at each speed ratio, > 0 "
                "(pump torque = (pump speed/K)²).", "rad/s/sqrt(N·m)", required=True),
            Key("torque_ratio", "numbers", "Turbine/pump torque at each speed ratio, > 0, "
                "with speed_ratio·torque_ratio <= 1.", required=True)),
        "torque": (Key("input", "str", "Input signal: the torque [N·m].", required=True),),
        "force": (Key("input", "str", "Input signal: the force [N].", required=True),),
        "support_friction": TRANSLATIONAL_FRICTION,
        "translational_brake": (
            Key("command", "str", "Normal force input, normalised by the force at which the "
                "model's capacity is given [-] (Modelica f_normalized).", required=True),
            *TRANSLATIONAL_FRICTION),
        "torque_pulsation": (Key("amplitude_table", "table", "`{speed = [rad/s ...], "
                                 "amplitude = [N·m ...]}`: amplitude against |speed| "
                                 "(instead of `amplitude`)."),),
        "engine": (Key("full_load", "table", "`{speed = [rad/s ...], torque = [N·m ...]}`.",
                       required=True),
                   Key("throttle", "str", "Throttle input signal [-].", required=True)),
        "thermal_node": (Key("link", "str", "Another thermal node this one conducts to."),),
        "release_system": (
            Key("travel", "str", "Signal of the engagement travel [m] (e.g. an actuator's "
                "`<name>.position`).", required=True),
            Key("cushion", "table", "Cushion (lining) spring `{compression = [m ...], force = "
                "[N ...]}` from (0, 0), both strictly increasing.", required=True),
            Key("spring", "table", "Diaphragm (lever) spring in series, at the bearing: "
                "`{deflection = [m ...], force = [N ...]}` from (0, 0), both strictly "
                "increasing (default: rigid).")),
        "hydraulic_actuator": (Key("command", "str", "Signal of the pressure command [Pa].",
                                   required=True),),
        "electromechanical_actuator": (Key("command", "str", "Signal of the position command "
                                           "[m].", required=True),),
        "launch_controller": (
            Key("target", "str", "Signal of the target speed ω_a − ω_b [rad/s].",
                required=True),
            Key("feedforward", "str", "Signal of the engine torque [N·m] (e.g. "
                "`engine.torque`), times `k_ff`."),
            Key("command_unit", "str", "Unit of the command it produces: -, N, Pa or m.")),
        "driver": (
            Key("target", "str", "Signal of the target speed [m/s].", required=True),
            Key("feedforward", "str", "Signal of a throttle feed-forward [-].")),
        "lossy_gear": (LOSS_TABLE,),
        "lossy_gear_with_lash": (LOSS_TABLE,),
        "gearbox": (
            Key("ratios", "numbers", "Gear ratios, gear 1 first.", required=True),
            Key("shifts", "tables", "`[{time = 3.0, gear = 2}]`: ratio changes (an ideal "
                "synchroniser that conserves the angular momentum of what it joins; the "
                "energy it removes is `W_sync`).  With `synchronizer`, each shift goes "
                "through the new gear's synchroniser instead."),
            Key("synchronizer", "table", "A synchroniser per gear instead of the ideal one "
                "(clutchsim.scenario.composites; docs/components.md, \"Gearbox with "
                "synchronizers\"): `{force = N, neutral = s, J_idler = kg·m², R_m = m, "
                "alpha = °, w_sync = rad/s, F_block = N, friction = {...}}` and the other "
                "keys of a `synchronizer` component.")),
        "one_way_clutch": (
            Key("command", "str", "Normalised clamp force input (0 open .. 1 full).",
                required=True), *FRICTION_ELEMENT[3:4], *FRICTION_ELEMENT[5:6]),
        "band_brake": (
            Key("command", "str", "Apply force of the band [N] (a signal; negative values "
                "read as 0).", required=True),
            *FRICTION_ELEMENT[5:6]),
        "limited_slip_differential": (
            Key("command", "str", "Signal of the torque into the input flange [N·m] (an "
                "input torque source's signal, or the torque of the propshaft's "
                "compliance): the ramps press the packs with ratio·|T|·tan(ramp_angle)/"
                "r_ramp beside the preload.", required=True),
            *FRICTION_ELEMENT[5:6]),
        "dog_clutch": (
            Key("command", "str", "Sleeve engagement command [-] (a signal; the teeth are "
                "pushed in from 0.5).", required=True),),
        "cone_clutch": (
            Key("command", "str", "Axial force on the cone [N] (a signal; negative values "
                "read as 0).", required=True),
            Key("friction", "table", "Friction model of the cone (see [friction]): its force "
                "levels are read as the friction coefficient mu [-] (e.g. coulomb-robust "
                "`overrides = {F_c = 0.1, F_s = 0.12}`).", required=True),
            *FRICTION_ELEMENT[3:6]),
        "wet_clutch": (
            Key("command", "str", "Piston pressure [Pa] (a signal; below the kiss point "
                "(spring_preload + spring_rate·stroke)/piston_area the pack is open).",
                required=True),
            Key("friction", "table", "Friction model of the plates (see [friction]): its "
                "force levels are read as the friction coefficient mu [-] (e.g. "
                "coulomb-robust `overrides = {F_c = 0.12, F_s = 0.13}`).", required=True),
            *FRICTION_ELEMENT[3:6]),
        "synchronizer": (
            Key("command", "str", "Sleeve force [N] (a signal; negative values read as 0): "
                "it presses the cone, passes the blocker from `F_block` and holds the "
                "engaged dog while positive.", required=True),
            Key("friction", "table", "Friction model of the cone: coulomb-robust, its levels "
                "read as the friction coefficient mu [-] (`overrides = {F_c = 0.1, F_s = "
                "0.12}`).", required=True),
            *FRICTION_ELEMENT[5:6]),
        "planetary": (Key("z_sun", "int", "Sun teeth (with z_ring, instead of ratio).",
                          low=1, high=1e4),
                      Key("z_ring", "int", "Ring teeth.", low=1, high=1e4)),
    }.get(cls.kind, ())
    # input signals a component declares itself: ``signal_docs`` {key: (doc, required)}
    extra += tuple(Key(k, "str", doc, required=req)
                   for k, (doc, req) in getattr(cls, "signal_docs", {}).items())
    return tuple(keys) + tuple(extra)


def component_types() -> dict:
    """``type`` -> scenario keys of every network component."""
    from ..network.components import COMPONENTS
    return {kind: _component_keys(cls) for kind, cls in COMPONENTS.items()}


NETWORK = (
    Key("connect", "connections", "Flanges joined: `[[\"engine.b\", \"clutch.a\"], ...]`; "
        "each entry joins two or more flanges (`component.flange`, or `ground`).",
        required=True),
)

OUTPUTS = (
    Key("angles", "bool", "Add an exact angle state per inertia node, `phi_<inertia>` [rad] "
        "(`s_<mass>` [m] in a translational network; from the inertia's `phi0`, the mass's "
        "`s0`): its derivative is the node's speed, with exact Jacobian entries; a "
        "quadrature, outside the implicit solve (default false: the default runs keep their "
        "states; a spring's twist and a torque pulsation's crank angle are states anyway)."),
)


def chain_keys(section: str, ctype=None) -> tuple:
    """The keys of a chain table (``inertia``, ``coupling`` of type ``ctype``, ``brake``,
    ``engine``, ``vehicle``, ``thermal``), generated from the network component it is read
    as (:mod:`clutchsim.scenario.chain_format`): its keys, and the chain's own keys that
    become structure (an inertia's ``load``, a coupling's ``ratio``, a ``node``), each with
    the rule of the component parameter it becomes; () for an unknown coupling type."""
    kind = COUPLING_TYPES.get(ctype) if section == "coupling" else KIND_OF.get(section)
    if kind is None:
        return ()
    from ..network.components import COMPONENTS

    def keys_of(kind):
        return _component_keys(COMPONENTS[kind])
    keys = [k for k in keys_of(kind) if k.name != "type"
            and not (k.name == "name" and section in ("engine", "vehicle"))]
    if section == "coupling":
        title = keys_of(kind)[1].doc.split(": ", 1)[1].rstrip(".")
        keys.insert(1, Key("type", "str", f"{ctype}: read as the network component "
                           f"`{kind}` ({title}).", required=True))
    for (table, ctypes), extra in CHAIN_ONLY.items():
        if table != section or (ctypes is not None and ctype not in ctypes):
            continue
        for name, (comp, comp_key, doc, required) in extra.items():
            if comp is None:
                keys.append(Key(name, "str", doc, required=required))
                continue
            spec = next(k for k in keys_of(comp) if k.name == comp_key)
            keys.append(replace(spec, name=name, doc=doc, required=required))
    return tuple(keys)


#: top-level tables: name -> (keys, kind) with kind "table" or "tables" (array of tables)
SECTIONS = {
    "scenario": (SCENARIO, "table"),
    "solver": (SOLVER, "table"),
    "inputs": ((), "map"),
    "inertia": (None, "tables"),
    "coupling": (None, "tables"),
    "brake": (None, "tables"),
    "engine": (None, "table"),
    "vehicle": (None, "table"),
    "thermal": (None, "tables"),
    "network": (NETWORK, "table"),
    "component": (None, "tables"),
    "outputs": (OUTPUTS, "table"),
}


def suggest(name: str, valid) -> str:
    m = difflib.get_close_matches(str(name), list(valid), n=1, cutoff=0.5)
    return f"; did you mean {m[0]!r}?" if m else ""


def table_keys(data: dict, section: str, index: str = "") -> tuple:
    """The schema keys of the table ``section`` (entry ``index`` of an array of tables:
    a coupling's or a component's keys follow its ``type``); () if unknown."""
    keys = SECTIONS.get(section, ((), ""))[0]
    if section in ("coupling", "component"):
        table = data.get(section)
        if not index or not isinstance(table, list) or int(index) >= len(table) or \
                not isinstance(table[int(index)], dict):
            return ()
        ctype = table[int(index)].get("type")
        if section == "coupling":
            return chain_keys(section, ctype)
        return component_types().get(ctype, ())
    if section in KIND_OF:
        return chain_keys(section)
    return keys or ()


def key_spec(data: dict, key: str) -> Key | None:
    """The schema :class:`Key` of a scenario key one level into its table
    (``vehicle.mass``, ``inertia[2].J``, ``coupling[0].c``, ``component[1].J``), or None."""
    import re
    parts = re.findall(r"([A-Za-z0-9_\-]+)(?:\[(\d+)\])?", key)
    if len(parts) != 2 or parts[1][1]:
        return None
    (section, index), (name, _) = parts
    return next((k for k in table_keys(data, section, index) if k.name == name), None)


def check_table(table: dict, keys: tuple, path: str, fail) -> None:
    """Check one table against its keys; ``fail(problem, key_path)`` raises."""
    known = {k.name: k for k in keys}
    for name, value in table.items():
        if name not in known and name.startswith("fault_") and \
                not any(k.startswith("fault_") for k in known):
            fail(f"= {quote(value)} declares a fault on a part that cannot have one: "
                 "faults are the fault_* keys of clutch, brake and spring_damper components "
                 "(docs/components.md, faults)", f"{path}.{name}")
        if name not in known:
            fail(f"unknown key {name!r}{suggest(name, known)} (valid keys: "
                 f"{', '.join(known)})", f"{path}.{name}")
    for k in keys:
        kp = f"{path}.{k.name}"
        if k.name not in table:
            if k.required:
                fail(f"missing required key {k.name!r} ({k.doc})", path)
            continue
        v = table[k.name]
        if k.kind in ("number", "int"):
            if isinstance(v, str):
                fail(f"must be a number in {k.unit or 'SI units'}, got the string {quote(v)} "
                     "(scenario values are plain SI numbers; the unit is fixed by the key)", kp)
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                fail(f"must be a number, got {type(v).__name__} {quote(v)}", kp)
            if k.kind == "int" and not isinstance(v, int):
                fail(f"must be an integer, got {quote(v)}", kp)
            if not math.isfinite(v):
                fail(f"must be finite, got {quote(v)}", kp)
            u = f" {k.unit}" if k.unit and k.unit != "-" else ""
            if k.low is not None and (v <= k.low if k.strict else v < k.low):
                rule = f"{'>' if k.strict else '>='} {k.low:g}{u}"
            elif k.high is not None and v > k.high:
                rule = f"<= {k.high:g}{u}"
            elif k.nonzero and v == 0:
                fail(f"= {v!r} is not allowed: must be non-zero ({k.doc[:1].lower()}"
                     f"{k.doc[1:].rstrip('.')})", kp)
            else:
                continue
            fail(f"= {v!r}{u} is out of range: must be {rule} (range {range_text(k)}{u}"
                 f"{'' if k.high is None else ', the physical range of this key'})", kp)
        elif k.kind == "str" and not isinstance(v, str):
            fail(f"must be a string, got {quote(v)}", kp)
        elif k.kind == "numbers":
            if not isinstance(v, list) or not all(
                    isinstance(x, (int, float)) and not isinstance(x, bool)
                    and math.isfinite(x) for x in v):
                fail(f"must be a list of finite numbers, got {quote(v)}", kp)
        elif k.kind == "connections":
            if not isinstance(v, list) or not all(
                    isinstance(c, list) and all(isinstance(x, str) for x in c) for c in v):
                fail(f"must be a list of lists of flange names, got {quote(v)}", kp)
        elif k.kind == "strs":
            if not isinstance(v, list) or not all(isinstance(x, str) for x in v):
                fail(f"must be a list of strings, got {quote(v)}", kp)
        elif k.kind == "table" and not isinstance(v, dict):
            fail(f"must be a table {{...}}, got {quote(v)}{_table_hint(k, v)}", kp)
        elif k.kind == "tables" and not (isinstance(v, list) and
                                         all(isinstance(x, dict) for x in v)):
            fail(f"must be a list of tables [{{...}}, ...], got {quote(v)}", kp)


def check_lining(table: dict, path: str, fail) -> None:
    """The lining geometry of a clutch coupling: ``r_inner`` and ``r_outer`` together,
    ``r_inner < r_outer`` (each key's own range is checked by :func:`check_table`)."""
    given = [k for k in ("r_inner", "r_outer") if k in table]
    if len(given) == 1:
        other = "r_outer" if given[0] == "r_inner" else "r_inner"
        fail(f"{given[0]} = {table[given[0]]!r} m needs {other} too (the lining area "
             "faces·π·(r_outer² − r_inner²) takes both)", f"{path}.{given[0]}")
    if len(given) == 2 and not table["r_inner"] < table["r_outer"]:
        fail(f"= {table['r_inner']!r} m must be below r_outer = {table['r_outer']!r} m "
             "(rule: 0 < r_inner < r_outer)", f"{path}.r_inner")
    if "faces" in table and not given:
        fail(f"faces = {table['faces']!r} needs r_inner and r_outer (the lining radii)",
             f"{path}.faces")


def range_text(k: Key) -> str:
    """The range of a numeric key in interval notation: ``(0, 1e+06]``, ``[0, inf)``."""
    lo = "(-inf" if k.low is None else f"{'(' if k.strict else '['}{k.low:g}"
    hi = "inf)" if k.high is None else f"{k.high:g}]"
    return f"{lo}, {hi}"


def _table_hint(k: Key, v) -> str:
    """A valid TOML line for a table key given as something else."""
    if k.name == "friction":
        model = v if isinstance(v, str) and v.strip() else "lugre"
        return (f"; write it as an inline table, e.g. friction = {{ model = \"{model}\" }} "
                f"or friction = {{ model = \"{model}\", overrides = {{ ... }} }}")
    if k.name in ("overrides", "alternatives"):
        return (f"; write it as an inline table, e.g. {k.name} = "
                + ("{ F_c = 1.0 }" if k.name == "overrides"
                   else "{ coulomb-robust = { F_c = 192.0, F_s = 240.0 } }"))
    return ""


def _rows(keys):
    out = ["| key | type | unit | required | range | meaning |", "|---|---|---|---|---|---|"]
    for k in keys:
        rng = range_text(k) if k.kind in ("number", "int") and \
            (k.low is not None or k.high is not None) else ""
        out.append(f"| `{k.name}` | {k.kind} | {k.unit} | {'yes' if k.required else ''} | "
                   f"{rng} | {k.doc} |")
    return out


#: what the reference says of the chain tables
CHAIN_NOTE = ("Chain files list inertias in series (`[[inertia]]`) joined by couplings "
              "(`[[coupling]]`), with `[[brake]]`, `[engine]`, `[vehicle]` and `[[thermal]]`. "
              "Each table is read as the network component it stands for (docs/network.md, "
              "\"Chain files\"); its keys, units and ranges below are generated from that "
              "component's declaration.")


def reference_markdown() -> str:
    """The scenario file reference (``docs/scenario-reference.md``), generated from SECTIONS."""
    out = ["# Scenario file reference", "",
           ("Generated by `clutchsim.scenario.schema.reference_markdown()`; do not edit by "
            "hand (a test compares this file with the generated text)."), "",
           ("A scenario is a TOML file. All values are plain SI numbers; the unit is fixed by "
            "the key (listed below). Unknown keys are errors (the closest valid key is "
            "suggested); every error names the file, the key path and the line."), "",
           ("Input signals (`[inputs]`, name = signal) are a formula string such as "
            "`\"ramp(0.5, 1.5, 1.0)\"` or `\"0.5 + sine(0.4, 1)\"`, a CSV path (header row, "
            "then `time [s], value`; relative to the scenario file; gaps are errors), or a "
            "table `{type = \"ramp\", start = .., duration = .., height = .., offset = ..}`, "
            "`{type = \"step\", time = .., height = .., offset = ..}`, "
            "`{type = \"table\", time = [...], value = [...]}`, "
            "`{type = \"const\", value = ..}`, "
            "`{type = \"sine\", amplitude = .., freq = .., phase = .., offset = ..}`."), ""]
    for name, (keys, kind) in SECTIONS.items():
        header = f"[[{name}]]" if kind == "tables" else f"[{name}]"
        out += [f"## `{header}`", ""]
        if name == "inputs":
            out += ["Free-form: `input_name = signal` (see above).", ""]
            continue
        if name == "component":
            out += [("Network scenarios list components and join their flanges in "
                     "`[network] connect` (instead of `[[inertia]]`/`[[coupling]]`). The "
                     "keys depend on `type` (generated from the component declarations, "
                     "docs/network.md)."), ""]
            for t, tkeys in component_types().items():
                out += [f"### `type = \"{t}\"`", ""] + _rows(tkeys) + [""]
            continue
        if name == "inertia":
            out += [CHAIN_NOTE, ""]
        if name == "coupling":
            out += [("Coupling k joins inertia k and inertia k+1; there is one coupling "
                     "fewer than inertias. The keys depend on `type`."), ""]
            for t in COUPLING_TYPES:
                out += [f"### `type = \"{t}\"`", ""] + _rows(chain_keys(name, t)) + [""]
            out += ["### `friction` (of a clutch or a brake)", ""] + _rows(FRICTION) + [""]
            continue
        out += _rows(chain_keys(name) if keys is None else keys) + [""]
    return "\n".join(out)
