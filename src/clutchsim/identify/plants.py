"""Plants an identification drives with measured inputs: the friction rig and the EMPS loop.

A :class:`PlantSpec` names a plant kind and its options.  :func:`build_problem` turns it,
a friction model and a measured record into a :class:`Setup`: the compiled system (built
once), its input signals from the measured columns, the simulated signal compared with the
measured output, and the plant parameters a fit may adjust (by their index in ``p``).

Kinds
-----
``rig-force``
    :func:`clutchsim.rig.make_rig` with the force drive; input a force column [N], output
    by default the position ``x`` [m]; fittable plant parameter ``mass``.
``rig-velocity``
    The velocity drive (imposed motion, e.g. a tribometer or a damper test); input a
    velocity column [m/s] (or a position column with ``differentiate = True``), output the
    friction force ``F`` [N]; fittable ``offset`` (a constant force added to the simulated
    force: sensor bias or a one-sided load).
``emps``
    :func:`clutchsim.identify.emps.make_emps`; input the reference position [m], output the
    position ``q`` [m]; fittable ``M``, ``offset``, ``gtau``, ``tau_v``.  Gains default to
    the scalars ``gtau``, ``kp``, ``kv`` of the data file when it has them.  With the option
    ``voltage`` (a column of the measured controller output [V]) the fit also reports the
    benchmark's relative force error ``||gtau·(u_sim − u)|| / ||gtau·u||``.

All rig kinds accept ``scale``: a number or a column name for the normal-load ratio ``s(t)``
[-], and the plant parameter ``load_fraction`` λ (default 1, fittable in [0, 1]): the friction
capacity is multiplied by ``(1 − λ) + λ·s(t)``.  Every capacity-scaled model then follows
``F = F_0 + μ·N`` style scaling: a part ``(1 − λ)·F`` that does not depend on the load and a
part ``λ·F·s`` proportional to it (with ``s = N/N_ref``: ``F_0 = (1 − λ)·F_c`` and
``μ·N_ref = λ·F_c`` for a Coulomb level ``F_c``).  One record at one load cannot separate the
two; several records at different loads can (see :func:`clutchsim.identify.fit`).

Measured inputs beyond the drive signal (:class:`InputSpec`) enter where they are declared:
``to = "force"`` (rig-force: added to the applied force; rig-velocity: added to the simulated
force, e.g. an inertia or spring force of the fixture; emps: the disturbance force ``F_d``),
``to = "controller"`` (emps: added to the controller output ``u_d`` [V]) or ``to = "scale"``
(rig kinds: added to the normal-load ratio ``s``), each times its ``gain``.  A declared
column that a record lacks is zero for that record, and :attr:`Setup.notes` says so.

Initial state: ``z0`` replaces the friction states the plant starts from (default: at rest,
or steady sliding when the rig starts moving); ``y0`` replaces the whole state, plant and
friction (a record that continues another one starts where that one's simulation ended);
``warmup`` [s] simulates the first part of the record and leaves it out of the error.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np

from ..core import Table
from ..core.system import System, closest
from ..data import Measurement, moving_average
from ..friction.base import FrictionModel
from ..rig import RIG_HEADER, make_rig
from .emps import EMPS_HEADER, EMPS_PARAMS, make_emps

__all__ = ["INPUT_TARGETS", "PLANTS", "InputSpec", "PlantSpec", "Setup", "absent_input",
           "build_setup"]

#: plant kind -> (description, default simulated signal, options accepted)
PLANTS = {
    "rig-force": ("mass on a friction contact, force input", "x",
                  ("mass", "scale", "load_fraction", "x0", "v0")),
    "rig-velocity": ("imposed velocity (or differentiated position) on a contact", "F",
                     ("scale", "load_fraction", "differentiate", "smooth", "offset")),
    "emps": ("EMPS prismatic drive under cascade position control", "q",
             ("M", "gtau", "kp", "kv", "u_max", "offset", "tau_v", "voltage")),
}

#: plant parameters a fit may adjust, per kind, and their default bounds (None: from data)
PLANT_PARAMS = {
    "rig-force": {"mass": None, "load_fraction": (0.0, 1.0)},
    "rig-velocity": {"offset": None, "load_fraction": (0.0, 1.0)},
    "emps": {"M": (10.0, 1000.0), "offset": (-50.0, 50.0), "gtau": (1.0, 200.0),
             "tau_v": (0.0, 0.01)},
}


#: where a declared measured input may enter, per plant kind
INPUT_TARGETS = {"rig-force": ("force", "scale"), "rig-velocity": ("force", "scale"),
                 "emps": ("force", "controller")}
#: plant_index codes of plant parameters that are not entries of ``p``
POST, LOAD = -1, -2


@dataclass(frozen=True)
class InputSpec:
    """A measured input column and where it enters the plant (see the module docstring).

    Parameters
    ----------
    column : str
        Column of the record (after the spec's mapping and derived columns).
    to : str
        ``"force"``, ``"controller"`` or ``"scale"`` (:data:`INPUT_TARGETS` per plant).
    gain : float
        Factor applied to the column (its unit times the gain is the unit of the target).
    unit : str
        Unit of the column, for the reports.
    """

    column: str
    to: str
    gain: float = 1.0
    unit: str = ""

    def __post_init__(self):
        targets = sorted({t for v in INPUT_TARGETS.values() for t in v})
        if self.to not in targets:
            raise ValueError(f"input {self.column!r}: to = {self.to!r} is not known"
                             f"{closest(self.to, targets)}; targets: {', '.join(targets)}")
        if not (isinstance(self.gain, (int, float)) and math.isfinite(self.gain)):
            raise ValueError(f"input {self.column!r}: gain = {self.gain!r} must be a finite "
                             "number")


@dataclass(frozen=True)
class PlantSpec:
    """A plant kind and its options (see the module docstring).

    Parameters
    ----------
    kind : str
        One of :data:`PLANTS`.
    options : dict
        Plant options, e.g. ``{"mass": 2.0}`` or ``{"kp": 160.18}``.
    """

    kind: str = "rig-force"
    options: dict = field(default_factory=dict)

    def __post_init__(self):
        if self.kind not in PLANTS:
            raise ValueError(f"plant = {self.kind!r} is not known{closest(self.kind, PLANTS)};"
                             f" plants: {', '.join(PLANTS)}")
        allowed = PLANTS[self.kind][2]
        for key in self.options:
            if key not in allowed:
                raise ValueError(f"plant {self.kind!r}: unknown option {key!r}"
                                 f"{closest(key, allowed)}; options: {', '.join(allowed)}")
        object.__setattr__(self, "options", MappingProxyType(dict(self.options)))

    @property
    def parameters(self) -> dict:
        return PLANT_PARAMS[self.kind]


@dataclass(frozen=True, eq=False)
class Setup:
    """Everything needed to simulate one measured record with changing parameters."""

    system: System
    inputs: dict
    signal: str
    y0: np.ndarray
    t: np.ndarray
    measured: np.ndarray
    header: int
    plant_index: dict           # plant parameter -> index in p (POST: added to the output,
    #                             LOAD: the load fraction of the scale input)
    plant_values: dict          # plant parameter -> value in the base system
    normaliser: np.ndarray      # what NRMSE divides by (measured minus its mean, or so)
    extras: dict                # data for plant-specific metrics
    n_plant: int = 0            # states before the friction states
    skip: int = 0               # leading samples simulated but left out of the error (warmup)
    load: np.ndarray | None = None      # the normal-load ratio s on the grid (rig kinds)
    output_add: np.ndarray | None = None   # measured force added to the simulated output
    notes: tuple = ()           # declared inputs this record lacks (taken as zero)
    source: str = ""

    def signals(self, load_fraction: float | None = None) -> dict:
        """Input signals, with the capacity multiplier ``(1 − λ) + λ·s`` for ``λ``."""
        if load_fraction is None or self.load is None or load_fraction == 1.0:
            return self.inputs
        lam = float(load_fraction)
        return {**self.inputs, "scale": Table(self.t, (1.0 - lam) + lam * self.load,
                                              hit_knots=False, source=f"{self.source}:scale")}

    @property
    def grid(self) -> np.ndarray:
        """The samples the error is measured on."""
        return self.t[self.skip:]


def _load_ratio(opts, data: Measurement) -> np.ndarray:
    scale = opts.get("scale", 1.0)
    if isinstance(scale, str):
        return np.array(data[scale], dtype=float)
    if not (isinstance(scale, (int, float)) and math.isfinite(scale) and scale >= 0):
        raise ValueError(f"plant option scale = {scale!r} must be a number >= 0 or a column")
    return np.full(data.t.size, float(scale))


def _declared(inputs, data: Measurement, kind: str):
    """``{target: summed gain·column}`` and notes for the declared inputs a record lacks."""
    sums: dict = {}
    notes = []
    for spec in inputs:
        if spec.to not in INPUT_TARGETS[kind]:
            raise ValueError(f"input {spec.column!r}: to = {spec.to!r} is not available for "
                             f"plant {kind!r}; targets: {', '.join(INPUT_TARGETS[kind])}")
        if spec.column not in data.columns:
            notes.append(f"{data.source}: declared input {spec.column!r} (to {spec.to}) is not "
                         "in this record; taken as 0")
            continue
        sums[spec.to] = sums.get(spec.to, 0.0) + spec.gain * np.asarray(data[spec.column])
    return sums, tuple(notes)


def absent_input(inputs, fitting, validation=()) -> tuple[InputSpec, str] | None:
    """The first declared input whose column is in none of the records, fitting or
    validation, with the message (None when every one is somewhere).  A record that lacks a
    declared column takes it as zero, with a note; a column that no record has is a typo or
    a missing derived column."""
    records = list(fitting) + list(validation)
    for spec in inputs:
        if not any(spec.column in m.columns for m in records):
            cols = sorted(set().union(*(m.columns for m in records)))
            val = f"; validation: {', '.join(m.source for m in validation)}" if validation \
                else ""
            return spec, (f"declared input column {spec.column!r} (to {spec.to}) is in none "
                          f"of the records (fitting: {', '.join(m.source for m in fitting)}"
                          f"{val}); columns: {', '.join(cols)}")
    return None


def build_setup(spec: PlantSpec, model: FrictionModel, data: Measurement, *,
                input: str, output: str, signal: str | None = None, inputs=(),
                z0=None, y0=None, warmup: float = 0.0) -> Setup:
    """The compiled plant for ``model`` driven by ``data[input]``, compared with ``data[output]``.

    ``inputs`` are :class:`InputSpec` declarations; ``z0`` the initial friction states;
    ``y0`` the whole initial state (plant states, then friction states; overrides ``z0``);
    ``warmup`` [s] the leading part of the record left out of the error.
    """
    opts = dict(spec.options)
    u = data[input]
    y = data[output]
    t = data.t
    extras: dict = {}
    added, notes = _declared(inputs, data, spec.kind)
    load = None
    output_add = None
    if spec.kind != "emps" and "load_fraction" in opts:
        lam = opts["load_fraction"]
        if not (isinstance(lam, (int, float)) and 0.0 <= lam <= 1.0):
            raise ValueError(f"plant option load_fraction = {lam!r} must be a number in [0, 1]")
    lam = float(opts.get("load_fraction", 1.0))
    if spec.kind in ("rig-force", "rig-velocity"):
        load = _load_ratio(opts, data) + added.get("scale", 0.0)
        scale = Table(t, (1.0 - lam) + lam * load, hit_knots=False,
                      source=f"{data.source}:scale")
    if spec.kind == "rig-force":
        system = make_rig(model, drive="force", mass=float(opts.get("mass", 1.0)),
                          x0=float(opts.get("x0", y[0] if (signal or "x") == "x" else 0.0)),
                          v0=float(opts.get("v0", 0.0)), z0=z0)
        force = u + added.get("force", 0.0)
        inputs_ = {"force": Table(t, force, hit_knots=False, source=f"{data.source}:{input}"),
                   "scale": scale}
        plant_index = {"mass": 1, "load_fraction": LOAD}
        plant_values = {"mass": float(opts.get("mass", 1.0)), "load_fraction": lam}
        header, n_plant = RIG_HEADER, 2
    elif spec.kind == "rig-velocity":
        if opts.get("differentiate", False):
            x = moving_average(u, int(opts.get("smooth", 1)))
            u = np.gradient(x, t)
        system = make_rig(model, drive="velocity", z0=z0)
        inputs_ = {"v": Table(t, u, hit_knots=False, source=f"{data.source}:{input}"),
                   "scale": scale}
        plant_index = {"offset": POST, "load_fraction": LOAD}
        plant_values = {"offset": float(opts.get("offset", 0.0)), "load_fraction": lam}
        header, n_plant = RIG_HEADER, 1
        output_add = added.get("force")
    else:
        sc = data.scalars
        kw = {k: float(opts[k]) if k in opts else float(sc[k])
              for k in ("gtau", "kp", "kv") if k in opts or k in sc}
        missing = [k for k in ("gtau", "kp", "kv") if k not in kw]
        if missing:
            raise ValueError(f"plant 'emps': give {', '.join(missing)} as plant options (the "
                             f"data file {data.source} has no such scalars)")
        system = make_emps(model, M=float(opts.get("M", 95.11)), offset=float(
            opts.get("offset", 0.0)), u_max=float(opts.get("u_max", 10.0)), q0=float(y[0]),
            tau_v=float(opts.get("tau_v", 0.0)), z0=z0, **kw)

        def table(name, values):
            return Table(t, values, hit_knots=False, source=f"{data.source}:{name}")
        inputs_ = {"q_ref": table(input, u),
                   "u_d": table("u_d", added["controller"]) if "controller" in added else 0.0,
                   "F_d": table("F_d", added["force"]) if "force" in added else 0.0}
        plant_index = dict(EMPS_PARAMS)
        plant_values = {k: float(system.params[i]) for k, i in plant_index.items()}
        header, n_plant = EMPS_HEADER, 3
        extras = {"q_ref": u}
        if opts.get("voltage"):
            extras["voltage"] = data[str(opts["voltage"])]
    sig = signal or PLANTS[spec.kind][1]
    names = system.state_names + system.output_names
    if sig not in names:
        raise ValueError(f"plant {spec.kind!r} has no signal {sig!r}{closest(sig, names)}; "
                         f"signals: {', '.join(names)}")
    if not (math.isfinite(warmup) and 0.0 <= warmup):
        raise ValueError(f"warmup = {warmup!r} s must be a finite number >= 0")
    skip = int(np.searchsorted(t, t[0] + warmup, side="left"))
    if t.size - skip < 2:
        raise ValueError(f"{data.source}: warmup = {warmup:g} s leaves fewer than 2 samples "
                         f"(record {t[0]:g} ... {t[-1]:g} s)")
    y = np.asarray(y)[skip:]
    if spec.kind == "emps":
        # the position follows the reference closely: measure the error against the
        # tracking error, not against the travel
        normaliser = (y - u[skip:]) - np.mean(y - u[skip:])
        extras["q_ref"] = u[skip:]
        if "voltage" in extras:
            extras["voltage"] = extras["voltage"][skip:]
    else:
        normaliser = y - np.mean(y)
    if not np.any(normaliser):
        raise ValueError(f"{data.source}: the measured output {output!r} is constant; "
                         "nothing to fit")
    start = system.y0.copy()
    if y0 is not None:
        start = np.asarray(y0, dtype=float).ravel()
        if start.shape != system.y0.shape or not np.all(np.isfinite(start)):
            raise ValueError(f"y0 has {start.size} entries; plant {spec.kind!r} with "
                             f"{model.name} has {system.y0.size} states "
                             f"({', '.join(system.state_names)}), all finite")
    return Setup(system, inputs_, sig, start, t, y, header,
                 plant_index, plant_values, normaliser, extras, n_plant, skip, load,
                 output_add, notes, data.source)
