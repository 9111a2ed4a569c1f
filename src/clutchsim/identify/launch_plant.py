"""The launch scenario that :mod:`.calibrate` fits to vehicle logs: its own network, compiled
once, run with each launch's measured inputs.

What the calibration changes in the scenario (:class:`LaunchPlant`):

- its engine is driven by what the log measured of it (``engine``): the engine torque
  (the engine controller's estimate, ``"torque"``), when the engine becomes a torque source
  on the same inertia, ``T = torque_scale · T_measured + torque_offset`` (the full-load map,
  drag and idle governor of the scenario's engine are not used: the measured torque already
  holds them); or the throttle (the accelerator pedal, ``"throttle"``), the input of the
  scenario's own engine (its full-load map, drag and idle governor act as the scenario says);
- its clutch's command (COM, 0 open ... 1 engaged) is the clamp map of the measured
  engagement travel ``x``: ``COM = capacity / C₀ · clip((x − touch_point) /
  engage_travel, 0, 1) ** clamp_exponent``, with ``C₀`` the static capacity of the clutch's
  friction model at full actuation (:meth:`~clutchsim.friction.FrictionModel.static_capacity`;
  at the friction coefficient's reference temperature): ``capacity`` is the clutch's torque
  capacity at full clamp load [N·m] whatever the friction model;
- every launch starts at rest with the engine at its measured (or fitted) start speed.

The other parameters are the scenario's own keys (``coupling[3].c``, the same key paths as
``--set`` and sweeps), set on the compiled network as a sweep sets its variants
(:class:`~clutchsim.scenario.variants.VariantPlan`): no parse, no compile per evaluation.
The measured inputs enter as piecewise-linear tables at their own stamps (no resampling);
the simulated speeds come back on a uniform grid of the calibration's ``step``, from the
solver's dense output.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Mapping
from dataclasses import dataclass, replace
from types import MappingProxyType

import numpy as np

from ..core import simulate
from ..core.signals import Table
from ..core.system import closest

__all__ = [
    "ENGINE_INPUT",
    "ENGINE_INPUTS",
    "INPUT_DEFAULTS",
    "INPUT_PARAMETERS",
    "SIGNALS",
    "TORQUE_PARAMETERS",
    "LaunchInput",
    "LaunchPlant",
    "Layout",
    "check_signals",
    "layout",
]

#: the input signal that replaces the scenario's engine: the engine torque [N·m]
ENGINE_INPUT = "engine_torque_log"
#: what of the engine a log measured, and the log signal that is (docs/calibration.md)
ENGINE_INPUTS = {"torque": "engine_torque", "throttle": "throttle"}
#: the input parameters that act on the measured engine torque only
TORQUE_PARAMETERS = ("torque_scale", "torque_offset")
#: the parameters that act on the measured inputs (not on the network): unit and meaning
INPUT_PARAMETERS: Mapping[str, tuple[str, str]] = MappingProxyType({
    "capacity": ("N·m", "clutch torque capacity at full clamp load (μ·F·r_m·faces)"),
    "touch_point": ("m", ("engagement travel at which the linings start to carry (kiss point); "
                          "a fraction [-] for a pedal position in %")),
    "engage_travel": ("m", "travel from the touch point to the full clamp load"),
    "clamp_exponent": ("-", "shape of the clamp map f = u**exponent"),
    "torque_scale": ("-", "engine torque = torque_scale · measured torque + torque_offset"),
    "torque_offset": ("N·m", "engine torque offset (friction and accessory losses)"),
    "engine_speed0": ("rad/s", "engine speed at the start of a launch"),
})
#: values of the input parameters that are neither fitted nor fixed (capacity and touch
#: point have none: a spec must give them)
INPUT_DEFAULTS: Mapping[str, float] = MappingProxyType({
    "engage_travel": 0.0025, "clamp_exponent": 1.5, "torque_scale": 1.0, "torque_offset": 0.0})
#: the measured speeds a launch is compared on, in the rows of :meth:`LaunchPlant.run`
SIGNALS = ("engine_speed", "input_speed", "wheel_speed", "vehicle_speed")


@dataclass(frozen=True, eq=False)
class LaunchInput:
    """The measured inputs of one launch, on its own clock (0 at the launch's start):
    engagement travel [m] and the engine's input (torque [N·m] or throttle [-]: the plant's
    ``engine``) at their stamps [s]."""

    t_travel: np.ndarray
    travel: np.ndarray
    t_engine: np.ndarray
    engine: np.ndarray


def _find(tables, name):
    return next((k for k, t in enumerate(tables) if isinstance(t, dict)
                 and t.get("name") == name), None)


@dataclass(frozen=True)
class Layout:
    """Where a launch scenario's parts are (its network with ``model`` on the clutch).

    ``engine``, ``clutch``: component names; ``engine_inertia``: the inertia the engine
    drives; ``command``, ``throttle``: the input signals of the clutch's command and the
    engine's throttle; ``signals``: measured speed -> the run's signal; ``tyre_radius`` [m];
    ``ratio``: gear times final drive from the clutch to the wheels (None: no fixed ratio);
    ``capacity0``: the clutch model's static capacity at COM 1 [N·m].
    """

    model: str
    engine: str
    engine_inertia: str
    clutch: str
    command: str
    throttle: str
    signals: Mapping[str, str]
    tyre_radius: float
    ratio: float | None
    capacity0: float


def layout(scenario, model: str | None = None,
           signals: Mapping[str, str] | None = None) -> Layout:
    """The :class:`Layout` of a launch scenario; ``signals`` overrides the default measured
    speeds (the engine's inertia, the inertia on the clutch's driven side, the vehicle's
    inertia, ``v_vehicle``).  ValueError: not a launch scenario the calibration can drive."""
    model = model or scenario.models[0]
    net = scenario.network(model)
    kinds = {c.kind: c for c in net.components}
    label = scenario.file or scenario.name
    for kind, why in (("engine", "the logged torque or pedal drives its engine"),
                      ("vehicle", "the logs measure the vehicle's speed")):
        if kind not in kinds:
            raise ValueError(f"{label}: the scenario has no {kind} component; a calibration "
                             f"needs a launch scenario ({why})")
    clutch = net.component(scenario.clutch)
    if clutch.reads_force or clutch.clamp_table is not None:
        raise ValueError(f"{label}: clutch {clutch.name!r} reads a clamp force or a clamp "
                         "table; the calibration drives it with COM [-] through its own "
                         "clamp map (touch_point, engage_travel, clamp_exponent): remove "
                         "clamp_reference/clamp_table")
    capacity0 = float(clutch.model.static_capacity())
    if not (math.isfinite(capacity0) and capacity0 > 0):
        raise ValueError(f"{label}: the friction model {model} of clutch {clutch.name!r} has "
                         f"no static capacity ({capacity0!r})")
    for k in signals or {}:
        if k not in SIGNALS:
            raise ValueError(f"signals: {k!r} is not a measured speed; these are: "
                             f"{', '.join(SIGNALS)}")
    asm = net.compile().asm
    engine, vehicle = kinds["engine"], kinds["vehicle"]

    def inertia_at(comp, flange):
        return asm.node_names[asm.node_of[(comp, flange)]]
    engine_inertia = inertia_at(engine.name, "flange")
    defaults = {"engine_speed": f"omega_{engine_inertia}",
                "input_speed": f"omega_{inertia_at(clutch.name, clutch.side_b)}",
                "wheel_speed": f"omega_{inertia_at(vehicle.name, 'flange')}",
                "vehicle_speed": "v_vehicle"}
    ratio = asm.static_ratio((clutch.name, clutch.side_b), (vehicle.name, "flange"))
    return Layout(model, engine.name, engine_inertia, clutch.name, clutch.command,
                  engine.throttle, MappingProxyType({**defaults, **dict(signals or {})}),
                  float(vehicle.values["tyre_radius"]), abs(ratio) if ratio else None,
                  capacity0)


def check_signals(system, signals: Mapping[str, str]) -> None:
    """ValueError when a measured speed's signal is not one of ``system``'s."""
    names = tuple(system.output_names) + tuple(system.state_names)
    speeds = [n for n in names if n.startswith(("omega_", "v_"))]
    for measured, name in signals.items():
        if name not in names:
            raise ValueError(f"signals: {measured} = {name!r} is not a signal of the run"
                             f"{closest(name, speeds)}; its speeds: {', '.join(speeds)}")


class LaunchPlant:
    """A launch scenario prepared for calibration (see the module notes).

    Parameters
    ----------
    scenario : Scenario
        The launch scenario (a clutch, an engine and a vehicle in its network).
    model : str, optional
        Friction model of its clutch (default: the scenario's first).
    signals : mapping, optional
        Measured speed -> the run's signal that it is (``input_speed =
        "omega_gearbox_input"``; defaults: :func:`layout`).
    engine : {"torque", "throttle"}
        What drives the engine: the measured engine torque (the engine is replaced by a
        torque source), or the measured throttle (the scenario's engine, its throttle
        input).

    Attributes: ``layout`` (:class:`Layout`), ``engine``, ``scenario`` (the scenario with
    its engine replaced where ``engine`` is "torque"), ``plan`` (its compiled
    :class:`~clutchsim.scenario.variants.VariantPlan`), ``engine_key`` (the key of the
    engine inertia's start speed).  Raises ValueError (a scenario the calibration cannot
    drive, a signal it does not have).
    """

    def __init__(self, scenario, model: str | None = None, *,
                 signals: Mapping[str, str] | None = None, engine: str = "torque"):
        from ..scenario.loader import parse_scenario
        from ..scenario.variants import VariantPlan
        if engine not in ENGINE_INPUTS:
            raise ValueError(f"engine = {engine!r}: the engine is driven by the measured "
                             f"{' or '.join(map(repr, ENGINE_INPUTS))}")
        self.engine = engine
        self.layout = lay = layout(scenario, model, signals)
        self.model = lay.model
        data = scenario.data
        if engine == "torque":
            data = _with_measured_engine(data, lay.engine, lay.engine_inertia,
                                         scenario.file or scenario.name)
            self.scenario = parse_scenario(data, text=scenario.text, file=scenario.file)
        else:
            self.scenario = scenario
        self.plan = VariantPlan(self.scenario, self.model)
        self.engine_key = _omega0_key(data, lay.engine_inertia)
        self.options = self.scenario.options
        names = self.plan.base_system().input_names
        #: the scenario's other inputs (a grade, a load), as it defines them
        self.inputs = {k: v for k, v in self.scenario.inputs.items() if k in names}
        check_signals(self.plan.base_system(), lay.signals)

    @property
    def capacity0(self) -> float:
        return self.layout.capacity0

    @property
    def ratio(self) -> float | None:
        return self.layout.ratio

    @property
    def tyre_radius(self) -> float:
        return self.layout.tyre_radius

    def system(self, changes: tuple):
        """The compiled system with ``changes`` = ``((scenario key, value), ...)``."""
        system = self.plan.system(changes)
        if system is None:
            _sc, system = self.plan.rebuilt(changes)
        return system

    def run(self, launch: LaunchInput, values: Mapping[str, float], changes: tuple,
            grid: np.ndarray) -> np.ndarray:
        """The measured speeds (rows :data:`SIGNALS`) of ``launch`` simulated with the input
        parameters ``values`` and the scenario ``changes`` (the engine's start speed
        ``values["engine_speed0"]`` among them here), on ``grid`` [s, launch clock].  A run
        that does not complete gives NaN after its end."""
        changes = (*changes, (self.engine_key, float(values["engine_speed0"])))
        system = self.system(changes)
        com = self.command_map(values, launch.travel)
        if self.engine == "torque":
            engine_input = ENGINE_INPUT
            engine = values["torque_scale"] * launch.engine + values["torque_offset"]
        else:
            engine_input, engine = self.layout.throttle, launch.engine
        inputs = {**self.inputs,
                  self.layout.command: Table(launch.t_travel, com, hit_knots=False),
                  engine_input: Table(launch.t_engine, engine, hit_knots=False)}
        options = replace(self.options, dt_out=float(grid[1] - grid[0]))
        res = simulate(system, (0.0, float(grid[-1])), inputs, solver=self.scenario.solver,
                       options=options)
        out = np.full((len(SIGNALS), grid.size), np.nan)
        inside = grid <= res.t[-1] * (1 + 1e-12)
        for row, name in enumerate(SIGNALS):
            out[row, inside] = np.interp(grid[inside], res.t, res[self.layout.signals[name]])
        return out

    def command_map(self, values: Mapping[str, float], x: np.ndarray) -> np.ndarray:
        """COM of engagement travel samples ``x`` under the input parameters ``values``."""
        u = np.clip((np.asarray(x, dtype=float) - values["touch_point"])
                    / values["engage_travel"], 0.0, 1.0)
        return values["capacity"] / self.capacity0 * u ** values["clamp_exponent"]


def _with_measured_engine(data: dict, engine: str, inertia: str, label: str) -> dict:
    """The scenario's tables with its engine replaced by a torque source of the input
    :data:`ENGINE_INPUT` on the inertia it drove."""
    out = copy.deepcopy(data)
    if isinstance(out.get("engine"), dict):            # the chain format
        del out["engine"]
        k = _find(out.get("inertia", []), inertia)
        if k is None:
            raise ValueError(f"{label}: the engine's node {inertia!r} is not an [[inertia]]")
        if "load" in out["inertia"][k]:
            raise ValueError(f"{label}: inertia[{k}] ({inertia}) has a load "
                             f"{out['inertia'][k]['load']!r} beside the engine; the "
                             "calibration drives it with the measured engine torque alone")
        out["inertia"][k]["load"] = ENGINE_INPUT
    else:                                              # a network: the same flanges
        comps = out.get("component", [])
        k = _find(comps, engine)
        comps[k] = {"type": "torque", "name": engine, "input": ENGINE_INPUT}
    out.setdefault("inputs", {})[ENGINE_INPUT] = 0.0
    return out


def _omega0_key(data: dict, inertia: str) -> str:
    """The key path of ``inertia``'s initial speed in the scenario's tables."""
    for table in ("inertia", "component"):
        k = _find(data.get(table, []), inertia)
        if k is not None:
            return f"{table}[{k}].omega0"
    raise ValueError(f"the engine's inertia {inertia!r} is not a table of the scenario")
