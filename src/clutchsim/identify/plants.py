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

All rig kinds accept ``scale``: a number or a column name for the capacity multiplier
(normal-load proxy).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np

from ..core import Constant, Table
from ..core.system import System, closest
from ..data import Measurement, moving_average
from ..friction.base import FrictionModel
from ..rig import RIG_HEADER, make_rig
from .emps import EMPS_HEADER, EMPS_PARAMS, make_emps

__all__ = ["PLANTS", "PlantSpec", "Setup", "build_setup"]

#: plant kind -> (description, default simulated signal, options accepted)
PLANTS = {
    "rig-force": ("mass on a friction contact, force input", "x",
                  ("mass", "scale", "x0", "v0")),
    "rig-velocity": ("imposed velocity (or differentiated position) on a contact", "F",
                     ("scale", "differentiate", "smooth", "offset")),
    "emps": ("EMPS prismatic drive under cascade position control", "q",
             ("M", "gtau", "kp", "kv", "u_max", "offset", "tau_v", "voltage")),
}

#: plant parameters a fit may adjust, per kind, and their default bounds (None: from data)
PLANT_PARAMS = {
    "rig-force": {"mass": None},
    "rig-velocity": {"offset": None},
    "emps": {"M": (10.0, 1000.0), "offset": (-50.0, 50.0), "gtau": (1.0, 200.0),
             "tau_v": (0.0, 0.01)},
}


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
    plant_index: dict           # plant parameter -> index in p (or -1: added to the output)
    plant_values: dict          # plant parameter -> value in the base system
    normaliser: np.ndarray      # what NRMSE divides by (measured minus its mean, or so)
    extras: dict                # data for plant-specific metrics


def _scale_signal(opts, data: Measurement):
    scale = opts.get("scale", 1.0)
    if isinstance(scale, str):
        return Table(data.t, data[scale], hit_knots=False, source=f"{data.source}:{scale}")
    if not (isinstance(scale, (int, float)) and math.isfinite(scale) and scale >= 0):
        raise ValueError(f"plant option scale = {scale!r} must be a number >= 0 or a column")
    return Constant(float(scale))


def build_setup(spec: PlantSpec, model: FrictionModel, data: Measurement, *,
                input: str, output: str, signal: str | None = None) -> Setup:
    """The compiled plant for ``model`` driven by ``data[input]``, compared with ``data[output]``."""
    opts = dict(spec.options)
    u = data[input]
    y = data[output]
    t = data.t
    extras: dict = {}
    if spec.kind == "rig-force":
        system = make_rig(model, drive="force", mass=float(opts.get("mass", 1.0)),
                          x0=float(opts.get("x0", y[0] if (signal or "x") == "x" else 0.0)),
                          v0=float(opts.get("v0", 0.0)))
        inputs = {"force": Table(t, u, hit_knots=False, source=f"{data.source}:{input}"),
                  "scale": _scale_signal(opts, data)}
        plant_index = {"mass": 1}
        plant_values = {"mass": float(opts.get("mass", 1.0))}
        header = RIG_HEADER
    elif spec.kind == "rig-velocity":
        if opts.get("differentiate", False):
            x = moving_average(u, int(opts.get("smooth", 1)))
            u = np.gradient(x, t)
        system = make_rig(model, drive="velocity")
        inputs = {"v": Table(t, u, hit_knots=False, source=f"{data.source}:{input}"),
                  "scale": _scale_signal(opts, data)}
        plant_index = {"offset": -1}
        plant_values = {"offset": float(opts.get("offset", 0.0))}
        header = RIG_HEADER
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
            tau_v=float(opts.get("tau_v", 0.0)), **kw)
        inputs = {"q_ref": Table(t, u, hit_knots=False, source=f"{data.source}:{input}")}
        plant_index = dict(EMPS_PARAMS)
        plant_values = {k: float(system.params[i]) for k, i in plant_index.items()}
        header = EMPS_HEADER
        extras = {"q_ref": u}
        if opts.get("voltage"):
            extras["voltage"] = data[str(opts["voltage"])]
    sig = signal or PLANTS[spec.kind][1]
    names = system.state_names + system.output_names
    if sig not in names:
        raise ValueError(f"plant {spec.kind!r} has no signal {sig!r}{closest(sig, names)}; "
                         f"signals: {', '.join(names)}")
    if spec.kind == "emps":
        # the position follows the reference closely: measure the error against the
        # tracking error, not against the travel
        normaliser = (y - u) - np.mean(y - u)
    else:
        normaliser = y - np.mean(y)
    if not np.any(normaliser):
        raise ValueError(f"{data.source}: the measured output {output!r} is constant; "
                         "nothing to fit")
    return Setup(system, inputs, sig, system.y0.copy(), t, np.asarray(y), header,
                 plant_index, plant_values, normaliser, extras)
