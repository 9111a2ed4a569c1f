"""Calibrate a launch scenario from vehicle logs: clutch capacity, touch point, clamp map,
driveline stiffness and damping, engine-torque scale and offset, without a torque sensor.

The model is the scenario's own network (:mod:`.launch_plant`): its engine driven by the
measured engine torque (the engine controller's estimate), its clutch by the clamp map of
the measured engagement travel; the fitted parameters are those of the inputs' maps and any
of the scenario's keys (``coupling[3].c``).  The measured speeds (engine, gearbox input,
wheel or vehicle) are its outputs, each compared at its own stamps (the simulated trace, on
a 1 ms grid from the solver's dense output, is interpolated at the stamps; the measurements
are never resampled).  The residual of each
signal is divided by that signal's noise level, estimated from the residuals themselves: a
first fit with nominal levels, then a second one, started where the first ended, with each
signal's RMS residual (so that 1 rpm of engine speed and 0.1 km/h of vehicle speed weigh
what their scatter says).  ``scipy.optimize.least_squares`` (trust-region reflective, bounds)
minimises it in the scaled coordinates of :class:`~.parameters.ParameterSpace`, with the
search options of :class:`~.fit.FitOptions`; the finite-difference Jacobian runs each
launch once per parameter column on the compiled network.

Unknown initial state: each launch starts at rest with the engine speed measured over its
first 0.12 s (or fitted per launch: ``per_launch = ["engine_speed0"]``); ``torque_offset`` may
also be fitted per launch.

Confidence intervals: the residuals of a launch are correlated in time (the model error of a
shuffle, the quantisation of the torque input), so ``(JᵀJ)⁻¹s²`` is too narrow.  The
covariance is the sandwich ``H⁻¹ S H⁻¹`` with ``S`` the Newey–West (Bartlett) estimate of the
score's covariance, per launch and signal, with a lag long enough for the residual's
autocorrelation to have died out; never smaller than the independent-residual covariance.
An interval is ``x ± z·se`` in the scaled coordinate (so a log-scaled parameter's interval is
not symmetric).  A parameter is flagged *unidentified* when the Jacobian has no component
along it, or its interval covers more than half of its bounds.
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType

import numpy as np
from scipy.optimize import least_squares
from scipy.signal import savgol_filter
from scipy.stats import norm

from .._util import toml_line
from ..core.system import closest
from ..data.channels import ChannelMap, MappedLog, load_channel_map
from ..data.launches import Launch, LaunchOptions, cut_launch, find_launches, slip_end
from ..data.logs import read_toml
from .fit import FitOptions, _at_bound
from .launch_plant import (
    ENGINE_INPUTS,
    INPUT_DEFAULTS,
    INPUT_PARAMETERS,
    SIGNALS,
    TORQUE_PARAMETERS,
    LaunchInput,
    LaunchPlant,
)
from .parameters import ParameterSpace

__all__ = ["CALIBRATION_SEARCH", "CalibrationResult", "CalibrationSpec", "LaunchTrace",
           "calibrate", "load_calibration"]

#: search options of a calibration where the spec does not set them (FitOptions fields):
#: a coarser difference step than a friction fit's (the runs' own tolerance is 3e-6)
CALIBRATION_SEARCH = MappingProxyType({"diff_step": 1e-3, "max_nfev": 40, "tol": 1e-6})
#: the measured outputs, their row in a simulated launch (:data:`.launch_plant.SIGNALS`)
#: and the noise level the first pass assumes (SI)
OUTPUTS = MappingProxyType({name: (SIGNALS.index(name), sigma) for name, sigma in (
    ("engine_speed", 0.5), ("input_speed", 0.5), ("wheel_speed", 0.05),
    ("vehicle_speed", 0.03))})
PER_LAUNCH = ("engine_speed0", "torque_offset")
#: slip speed at which the result states the clutch's sliding capacity [rad/s] (a launch's
#: slip passes it on its way to lock-up)
SLIDE_SPEED = 20.0
#: the warning of a calibration whose engine runs on the logged pedal (measured:
#: docs/calibration.md, "What was measured")
THROTTLE_INTERVALS = (
    "the intervals of a calibration driven by the logged throttle are too narrow: in 20 "
    "synthetic trials the 95 % intervals of capacity and touch point held the truth in "
    "25-30 % (the estimates were within 3.2 % and 0.022 mm); read them as lower bounds "
    "(docs/calibration.md)")
#: draws of the input perturbation (per launch) of the interval's input-error term
INPUT_DRAWS = 40
#: engine speed at a launch's start: the mean over this first part [s]
START_AVERAGE = 0.12
_TABLES = ("calibration", "parameters", "fixed", "fit", "launch_finder")
_CAL_KEYS = ("scenario", "model", "engine", "signals", "channels", "logs", "validate", "step",
             "per_launch", "launches", "outputs", "windows")
_FIT_KEYS = ("starts", "seed", "max_nfev", "tol", "diff_step", "confidence")
_PARAM_KEYS = ("key", "start", "bounds", "prior")
RPM = 30.0 / math.pi


class CalibrationError(ValueError):
    """A mistake in a calibration spec: ``FILE:LINE: [table] key: problem``."""


# --------------------------------------------------------------------------- the spec
@dataclass(frozen=True, eq=False)
class CalibrationSpec:
    """A calibration specification (TOML; see docs/calibration.md), paths resolved.

    ``plant``: the scenario prepared for calibration; ``fitted``: name -> ``{"start",
    "bounds", "prior"}``; ``fixed``: name -> value (the input parameters' defaults
    :data:`~.launch_plant.INPUT_DEFAULTS` and the scenario's values for the rest);
    ``keys``: a scenario parameter's name -> its scenario key (``stiffness`` ->
    ``coupling[3].c``); ``search``: the FitOptions fields.
    """

    path: Path | None
    channel_map: ChannelMap | None
    plant: LaunchPlant
    fitted: Mapping[str, Mapping]
    fixed: Mapping[str, float]
    keys: Mapping[str, str] = field(default_factory=dict)
    logs: tuple[Path, ...] = ()
    validate: tuple[Path, ...] = ()
    step: float = 0.001
    per_launch: tuple[str, ...] = ()
    launches: tuple[int, ...] | None = None
    windows: tuple[tuple[float, float], ...] = ()
    outputs: tuple[str, ...] | None = None
    finder: LaunchOptions = field(default_factory=LaunchOptions)
    search: Mapping = field(default_factory=dict)
    confidence: float = 0.95
    text: str = ""

    def where(self, table: str, key: str | None = None) -> str:
        line = toml_line(self.text, table, key) if self.text else None
        name = str(self.path) if self.path else "<spec>"
        return f"{name}:{line}" if line else name

    def fit_options(self) -> FitOptions:
        return FitOptions(**{**CALIBRATION_SEARCH, **self.search})

    def unit(self, name: str) -> str:
        """The unit of a parameter (``name`` or ``name@k``)."""
        base = name.partition("@")[0]
        if base in INPUT_PARAMETERS:
            return INPUT_PARAMETERS[base][0]
        from ..studies.sweeps.design import key_unit
        return key_unit(self.plant.scenario.data, self.keys[base]) or "-"

    def read(self, path) -> MappedLog:
        if self.channel_map is None:
            raise CalibrationError(f"{self.where('calibration', 'channels')}: reading {path} "
                                   "needs a channel map ([calibration] channels)")
        return self.channel_map.read(path)


def _number(where, value, *, positive=False) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise CalibrationError(f"{where}: {value!r} is not a finite number")
    if positive and value <= 0:
        raise CalibrationError(f"{where}: {value!r} must be > 0")
    return float(value)


def load_calibration(path: str | Path) -> CalibrationSpec:
    """Read and check a calibration spec; :class:`CalibrationError` names file, line, key."""
    path = Path(path)
    at, doc, text = read_toml(path, CalibrationError)

    for top in doc:
        if top not in _TABLES:
            raise CalibrationError(f"{at(top)}: unknown table{closest(top, _TABLES)}; tables: "
                                   f"{', '.join(_TABLES)}")
    cal = doc.get("calibration", {})
    _keys(cal, _CAL_KEYS, "calibration", at)
    cmap = None
    if "channels" in cal:
        try:
            cmap = load_channel_map(path.parent / cal["channels"])
        except FileNotFoundError:
            raise CalibrationError(f"{at('calibration', 'channels')}: no such channel map "
                                   f"{path.parent / cal['channels']}") from None
    plant = _plant(path, cal, at)
    fitted: dict = {}
    keys: dict = {}
    for name, entry in doc.get("parameters", {}).items():
        where = at("parameters", name)
        if not isinstance(entry, dict) or "start" not in entry:
            raise CalibrationError(f"{where}: give a table {{ start = ..., bounds = [lo, hi] }}")
        _keys(entry, _PARAM_KEYS, "parameters", at, name)
        _param_name(name, entry.get("key"), where, plant, keys)
        item = {"start": _number(f"{where} start", entry["start"])}
        for key in ("bounds", "prior"):
            if key in entry:
                pair = entry[key]
                if not (isinstance(pair, list) and len(pair) == 2):
                    raise CalibrationError(f"{where} {key} = {pair!r}: give two numbers "
                                           f"{'[lo, hi]' if key == 'bounds' else '[mean, sd]'}")
                a, b = (_number(f"{where} {key}", v) for v in pair)
                if key == "bounds" and not a < b:
                    raise CalibrationError(f"{where} bounds = {pair!r}: lo must be < hi")
                if key == "bounds" and not a <= item["start"] <= b:
                    raise CalibrationError(f"{where} start = {item['start']:g} lies outside "
                                           f"bounds [{a:g}, {b:g}]")
                if key == "prior" and b <= 0:
                    raise CalibrationError(f"{where} prior = {pair!r}: the sd must be > 0")
                item[key] = (a, b)
        fitted[name] = item
    if not fitted:
        raise CalibrationError(f"{at('parameters')}: no parameters to fit; e.g. capacity = "
                               "{ start = 200.0, bounds = [50.0, 600.0] }")
    fixed = {}
    for name, value in doc.get("fixed", {}).items():
        _param_name(name, None, at("fixed", name), plant, keys)
        if name in fitted:
            raise CalibrationError(f"{at('fixed', name)}: {name} is both fitted and fixed")
        fixed[name] = _number(at("fixed", name), value)
    if plant.engine != "torque":
        for name in TORQUE_PARAMETERS:
            if name in fitted or name in fixed or name in cal.get("per_launch", []):
                table = "parameters" if name in fitted else (
                    "fixed" if name in fixed else "calibration")
                raise CalibrationError(
                    f"{at(table, name if table != 'calibration' else 'per_launch')}: "
                    f"{name} scales the measured engine torque; with engine = "
                    f"{plant.engine!r} the scenario's engine makes the torque: drop it")
    for name in ("capacity", "touch_point"):
        if name not in fitted and name not in fixed:
            raise CalibrationError(f"{at('parameters')}: {name} is neither fitted nor fixed "
                                   "(it has no default: give it in [parameters] or [fixed])")
    fit = doc.get("fit", {})
    _keys(fit, _FIT_KEYS, "fit", at)
    search = {k: v for k, v in fit.items() if k != "confidence"}
    try:
        FitOptions(**{**CALIBRATION_SEARCH, **search})
    except (TypeError, ValueError) as exc:
        raise CalibrationError(f"{at('fit')}: {exc}") from None
    confidence = _number(at("fit", "confidence"), fit.get("confidence", 0.95))
    if not 0.5 <= confidence < 1:
        raise CalibrationError(f"{at('fit', 'confidence')} = {confidence:g}: must be in "
                               "[0.5, 1)")
    finder_raw = doc.get("launch_finder", {})
    _keys(finder_raw, tuple(LaunchOptions.__dataclass_fields__), "launch_finder", at)
    try:
        finder = LaunchOptions(**{"ratio": plant.ratio, "tyre_radius": plant.tyre_radius,
                                  **finder_raw})
    except (TypeError, ValueError) as exc:
        raise CalibrationError(f"{at('launch_finder')}: {exc}") from None
    per = cal.get("per_launch", [])
    for name in per:
        if name not in PER_LAUNCH:
            raise CalibrationError(f"{at('calibration', 'per_launch')}: {name!r} cannot be "
                                   f"fitted per launch; these can: {', '.join(PER_LAUNCH)}")
        if name == "torque_offset" and name in fitted:
            raise CalibrationError(f"{at('calibration', 'per_launch')}: torque_offset is "
                                   "fitted per launch and in [parameters]: choose one")
    outputs = cal.get("outputs")
    for name in outputs or ():
        if name not in OUTPUTS:
            raise CalibrationError(f"{at('calibration', 'outputs')}: {name!r} is not an "
                                   f"output{closest(name, OUTPUTS)}; outputs: {', '.join(OUTPUTS)}")
    step = _number(at("calibration", "step"), cal.get("step", 0.001), positive=True)
    if step > 0.005:
        raise CalibrationError(f"{at('calibration', 'step')} = {step:g} s: at most 0.005 s "
                               "(the shuffle mode needs it)")
    windows = []
    for w in cal.get("windows", []):
        if not (isinstance(w, list) and len(w) == 2):
            raise CalibrationError(f"{at('calibration', 'windows')}: {w!r}: each window is "
                                   "[t0, t1] in s")
        windows.append((_number(at("calibration", "windows"), w[0]),
                        _number(at("calibration", "windows"), w[1])))
    launches = cal.get("launches")
    if launches is not None and not (isinstance(launches, list) and all(
            isinstance(k, int) and k >= 1 for k in launches)):
        raise CalibrationError(f"{at('calibration', 'launches')} = {launches!r}: give the "
                               "numbers (1, 2, ...) of the launches found to fit")
    return CalibrationSpec(
        path, cmap, plant, MappingProxyType(fitted), MappingProxyType(fixed),
        MappingProxyType(keys),
        tuple(path.parent / f for f in cal.get("logs", [])),
        tuple(path.parent / f for f in cal.get("validate", [])), step, tuple(per),
        tuple(launches) if launches is not None else None, tuple(windows),
        tuple(outputs) if outputs is not None else None, finder, MappingProxyType(search),
        confidence, text)


def _keys(table, allowed, name, at, sub=None):
    if not isinstance(table, dict):
        raise CalibrationError(f"{at(name)}: must be a table")
    for key in table:
        if key not in allowed:
            raise CalibrationError(f"{at(name, sub or key)}: unknown key {key!r}"
                                   f"{closest(key, allowed)}; keys: {', '.join(allowed)}")


def _plant(path: Path, cal: dict, at) -> LaunchPlant:
    """The spec's scenario prepared for calibration (:class:`~.launch_plant.LaunchPlant`)."""
    from ..scenario.errors import ScenarioError
    from ..scenario.loader import load_scenario
    if "scenario" not in cal:
        raise CalibrationError(f"{at('calibration')}: give the launch scenario to calibrate: "
                               '[calibration] scenario = "launch.toml" (a path from the spec)')
    file = path.parent / str(cal["scenario"])
    if not file.is_file():
        raise CalibrationError(f"{at('calibration', 'scenario')}: no such scenario {file}")
    signals = cal.get("signals", {})
    _keys(signals, SIGNALS, "calibration", at, "signals")
    engine = cal.get("engine", "torque")
    if engine not in ENGINE_INPUTS:
        raise CalibrationError(f"{at('calibration', 'engine')}: engine = {engine!r}: the "
                               "engine is driven by the measured \"torque\" (the engine "
                               "controller's estimate) or \"throttle\" (the accelerator "
                               "pedal, into the scenario's engine)")
    try:
        scenario = load_scenario(file)
        model = cal.get("model")
        if model is not None and model not in scenario.models:
            from ..friction import MODELS
            if model not in MODELS:
                raise CalibrationError(f"{at('calibration', 'model')}: {model!r} is not a "
                                       f"friction model{closest(str(model), MODELS)}")
        return LaunchPlant(scenario, model, signals=signals, engine=engine)
    except ScenarioError as exc:
        raise CalibrationError(f"{at('calibration', 'scenario')}: {exc}") from None
    except ValueError as exc:
        if isinstance(exc, CalibrationError):
            raise
        msg = str(exc)
        if msg.startswith("signals: "):
            raise CalibrationError(f"{at('calibration', 'signals')}: "
                                   f"{msg.removeprefix('signals: ')}") from None
        raise CalibrationError(f"{at('calibration', 'scenario')}: {msg}") from None


def _param_name(name: str, key, where: str, plant: LaunchPlant, keys: dict) -> None:
    """Check a parameter's name: an input parameter, or a scenario key (its own name, or
    ``key = "..."``) that the scenario has as a number; records the key in ``keys``."""
    if name in INPUT_PARAMETERS and name != "engine_speed0":
        if key is not None:
            raise CalibrationError(f"{where}: {name} is a parameter of the measured inputs, "
                                   "not of the scenario: drop its key")
        return
    if name == "engine_speed0":
        raise CalibrationError(f"{where}: engine_speed0 is measured per launch; fit it with "
                               '[calibration] per_launch = ["engine_speed0"]')
    from ..scenario.variants import value_at
    valid = [n for n in INPUT_PARAMETERS if n != "engine_speed0"]
    given = key is not None
    key = name if key is None else key
    if not isinstance(key, str):
        raise CalibrationError(f"{where}: key = {key!r} must be a scenario key path")
    base = value_at(plant.scenario.data, key)
    if isinstance(base, bool) or not isinstance(base, (int, float)):
        parent, _, leaf = key.rpartition(".")
        table = value_at(plant.scenario.data, parent) if parent else None
        numbers = [k for k, v in table.items() if isinstance(v, (int, float))
                   and not isinstance(v, bool)] if isinstance(table, dict) else []
        where_to = (f"a key path as --set takes, written in {plant.scenario.file}: "
                    'coupling[3].c, or a name with key = "coupling[3].c"')
        if given:
            raise CalibrationError(f"{where}: key = {key!r}: the scenario has no number there"
                                   f"{closest(leaf, numbers)} ({where_to})")
        raise CalibrationError(
            f"{where}: {name!r} is neither a parameter of the measured inputs"
            f"{closest(name, valid)} ({', '.join(valid)}) nor a number of the scenario "
            f"({where_to})")
    keys[name] = key


# --------------------------------------------------------------------------- launch data
@dataclass(frozen=True, eq=False)
class _Output:
    signal: str
    row: int
    t: np.ndarray
    y: np.ndarray
    idx: np.ndarray
    w: np.ndarray

    def of(self, Y: np.ndarray) -> np.ndarray:
        """The simulated signal at its stamps, from the launch's grid ``Y``."""
        return Y[self.row, self.idx] * (1 - self.w) + Y[self.row, self.idx + 1] * self.w


@dataclass(frozen=True, eq=False)
class _LaunchData:
    launch: Launch
    n: int
    inputs: LaunchInput
    engine_speed0: float
    outputs: tuple[_Output, ...]
    #: the measured inputs near the launch: name -> (stamps, values, error level)
    raw: Mapping[str, tuple[np.ndarray, np.ndarray, float]] = field(default_factory=dict)

    def grid(self, h: float) -> np.ndarray:
        """The simulated grid on the launch's own clock [s]."""
        return h * np.arange(self.n + 1)


def _prepare(launch: Launch, spec: CalibrationSpec) -> _LaunchData:
    sig = launch.signals
    engine = ENGINE_INPUTS[spec.plant.engine]
    for need in ("clutch_position", engine, "engine_speed"):
        if need not in sig or sig[need].t.size < 2:
            raise ValueError(f"{launch.name}: the calibration needs {need} (mapped and "
                             f"sampled in the launch window {launch.t_start:.3f} ... "
                             f"{launch.t_end:.3f} s)")
    h = spec.step
    t0 = launch.t_start
    n = max(2, math.ceil((launch.t_end - t0) / h))
    e = sig["engine_speed"]
    first = e.values[e.t <= t0 + START_AVERAGE]
    we0 = float(np.mean(first)) if first.size else float(e.values[0])
    wanted = spec.outputs or tuple(OUTPUTS)
    outputs = []
    for name in wanted:
        if name not in sig:
            if spec.outputs is not None:
                raise ValueError(f"{launch.name}: output {name} is not mapped")
            continue
        ch = sig[name]
        keep = (ch.t >= t0) & (ch.t <= t0 + n * h)
        t = ch.t[keep]
        if t.size < 2:
            continue
        pos = (t - t0) / h
        idx = np.clip(np.floor(pos).astype(np.intp), 0, n - 1)
        outputs.append(_Output(name, OUTPUTS[name][0], t, ch.values[keep], idx, pos - idx))
    if not any(o.signal == "engine_speed" for o in outputs):
        raise ValueError(f"{launch.name}: the engine speed has no samples in the window")
    raw = {}
    for name in ("clutch_position", engine):
        ch = sig[name]
        raw[name] = (ch.t, ch.values, _input_sigma(ch.values))
    return _LaunchData(launch, n, _launch_input(launch, raw), we0, tuple(outputs),
                       MappingProxyType(raw))


def _launch_input(launch: Launch, raw, travel=None, engine=None) -> LaunchInput:
    """The measured inputs of ``launch`` on its own clock (``raw``: the travel, then the
    engine's input; ``travel``, ``engine``: other values at the same stamps)."""
    (tt, vt, _), (te, ve, _) = raw.values()
    return LaunchInput(tt - launch.t_start, vt if travel is None else travel,
                       te - launch.t_start, ve if engine is None else engine)


def _input_sigma(v: np.ndarray) -> float:
    """The error level of an input's samples: its quantisation (the typical step between
    its distinct values, variance q²/12) and what linear interpolation between samples
    misses (0.4 times the RMS of each sample minus the mean of its neighbours)."""
    steps = np.diff(np.unique(v))
    q = float(np.median(steps)) if steps.size else 0.0
    loo = v[1:-1] - 0.5 * (v[:-2] + v[2:])
    return float(math.sqrt(q * q / 12.0 + 0.16 * float(np.mean(loo ** 2)))) if loo.size else q


# --------------------------------------------------------------------------- the problem
class _Problem:
    """Residuals of all launches; a row is a launch simulated with one parameter vector."""

    def __init__(self, spec: CalibrationSpec, data: list[_LaunchData], names, space):
        self.spec, self.data, self.names, self.space = spec, data, list(names), space
        self.fixed = {**INPUT_DEFAULTS, **spec.fixed}
        self.sigma = {name: OUTPUTS[name][1] for name in OUTPUTS}
        self.evaluations = 0
        self.prior = [(j, *spec.fitted[n]["prior"]) for j, n in enumerate(names)
                      if n in spec.fitted and "prior" in spec.fitted[n]]

    def values_for(self, values: np.ndarray, k: int) -> tuple[dict, tuple]:
        """The input parameters of launch ``k`` (``k < 0``: a launch not fitted, with the
        mean of the per-launch values) and its scenario changes ``((key, value), ...)``."""
        out = dict(self.fixed)
        per: dict[str, list] = {}
        for n, v in zip(self.names, values):
            base, at, idx = n.partition("@")
            if at:
                per.setdefault(base, []).append(v)
                if int(idx) != k + 1:
                    continue
            out[base] = float(v)
        if k < 0:
            out.update({b: float(np.mean(v)) for b, v in per.items() if b != "engine_speed0"})
        keys = self.spec.keys
        changes = tuple((keys[n], v) for n, v in out.items() if n in keys)
        return {n: v for n, v in out.items() if n not in keys}, changes

    def simulate(self, rows_values: list[tuple[int, np.ndarray]], data=None,
                 inputs: Sequence[LaunchInput] | None = None) -> list[np.ndarray]:
        """Each row ``(launch k, parameter values)`` simulated: ``(len(SIGNALS), n + 1)``
        on the launch's grid (``inputs``: other measured inputs, one per row)."""
        data = data or self.data
        h = self.spec.step
        out = []
        for i, (k, values) in enumerate(rows_values):
            vals, changes = self.values_for(values, k if data is self.data else -1)
            vals.setdefault("engine_speed0", data[k].engine_speed0)
            d = data[k]
            out.append(self.spec.plant.run(d.inputs if inputs is None else inputs[i], vals,
                                           changes, d.grid(h)))
        self.evaluations += len(rows_values)
        return out

    def residual_of(self, Y: np.ndarray, d: _LaunchData) -> np.ndarray:
        """The launch's residual: per signal, simulated minus measured over its noise level
        (a run that ended early counts as far off: its NaNs become 1e6 noise levels)."""
        parts = [(o.of(Y) - o.y) / self.sigma[o.signal] for o in d.outputs]
        return np.nan_to_num(np.concatenate(parts), nan=1e6)

    def noise_model(self, x: np.ndarray) -> None:
        """Each signal's noise level: its RMS residual (over all launches) at ``x``."""
        r = self.residual(x)
        for signal in {b[0] for b in self.blocks()}:
            parts = np.concatenate([r[a:b] for s, a, b in self.blocks() if s == signal])
            self.sigma[signal] = float(max(np.sqrt(np.mean(parts ** 2)), 1e-12)
                                       * self.sigma[signal])

    def prior_residual(self, values):
        return np.array([(values[j] - mean) / sd for j, mean, sd in self.prior])

    def residual(self, x: np.ndarray) -> np.ndarray:
        values = self.space.to_physical(x)
        Y = self.simulate([(k, values) for k in range(len(self.data))])
        r = [self.residual_of(Y[k], d) for k, d in enumerate(self.data)]
        return np.concatenate(r + [self.prior_residual(values)])

    def affects(self, j: int) -> list[int]:
        _, at, idx = self.names[j].partition("@")
        return [int(idx) - 1] if at else list(range(len(self.data)))

    def offsets(self) -> np.ndarray:
        """Where each launch's residual starts (and the priors': the last entry)."""
        sizes = [sum(o.t.size for o in d.outputs) for d in self.data]
        return np.concatenate([[0], np.cumsum(sizes)])

    def jacobian(self, x: np.ndarray, r0: np.ndarray, diff_step: float) -> np.ndarray:
        _, hi = self.space.scaled_bounds
        steps = diff_step * np.maximum(1.0, np.abs(x))
        steps = np.where(x + steps > hi, -steps, steps)
        rows, where = [], []
        for j in range(len(x)):
            xj = x.copy()
            xj[j] += steps[j]
            vj = self.space.to_physical(xj)
            for k in self.affects(j):
                rows.append((k, vj))
                where.append((j, k))
        Y = self.simulate(rows)
        offsets = self.offsets()
        J = np.zeros((r0.size, len(x)))
        for (j, k), Yr in zip(where, Y):
            a, b = offsets[k], offsets[k + 1]
            J[a:b, j] = (self.residual_of(Yr, self.data[k]) - r0[a:b]) / steps[j]
        deriv = self.space.derivative(x)
        for i, (j, _, sd) in enumerate(self.prior):
            J[offsets[-1] + i, j] = deriv[j] / sd
        return J

    def blocks(self) -> list[tuple[str, int, int]]:
        """``(signal, start, stop)`` of each launch's signal in the residual."""
        out, pos = [], 0
        for d in self.data:
            for o in d.outputs:
                out.append((o.signal, pos, pos + o.t.size))
                pos += o.t.size
        return out


def _solve(problem: _Problem, x0: np.ndarray, options: FitOptions):
    cache: dict = {}

    def fun(x):
        r = problem.residual(x)
        cache["x"], cache["r"] = x.copy(), r
        return r

    def jac(x):
        r0 = cache["r"] if "x" in cache and np.array_equal(cache["x"], x) else fun(x)
        return problem.jacobian(x, r0, options.diff_step)

    return least_squares(fun, x0, jac=jac, bounds=problem.space.scaled_bounds, method="trf",
                         max_nfev=options.max_nfev, ftol=options.tol, xtol=options.tol,
                         x_scale=1.0)


# --------------------------------------------------------------------------- uncertainty
def _bandwidth(r: np.ndarray) -> int:
    """Newey–West lag of one residual block: where its autocorrelation has died out (below
    2/√m), at least the usual ``4·(m/100)^(2/9)``, at most a third of the block."""
    m = r.size
    rule = math.floor(4.0 * (m / 100.0) ** (2.0 / 9.0))
    c = r - r.mean()
    den = float(c @ c)
    lag = 1
    if den > 0:
        limit = 2.0 / math.sqrt(m)
        while lag < m // 3 and float(c[lag:] @ c[:-lag]) / den > limit:
            lag += 1
    return max(1, min(max(rule, lag), max(1, m // 3)))


def _covariance(J: np.ndarray, r: np.ndarray, blocks, n_prior: int):
    """``(cov, null, H⁻¹)`` in scaled coordinates: the HAC sandwich (never below the plain
    ``s²·H⁻¹``), a mask of the parameters along a direction the data do not see, and the
    pseudo-inverse of ``JᵀJ``."""
    m, n = J.shape
    _, sv, vt = np.linalg.svd(J, full_matrices=False)
    keep = sv > 1e-8 * sv[0] if sv.size and sv[0] > 0 else np.zeros(sv.size, bool)
    Hinv = (vt[keep].T / sv[keep] ** 2) @ vt[keep]
    null = np.zeros(n, bool)
    if np.any(~keep):
        null = np.max(np.abs(vt[~keep]), axis=0) > 1e-3
    s2 = float(r @ r) / max(m - n, 1)
    S = np.zeros((n, n))
    for _, a, b in blocks:
        g = J[a:b] * r[a:b, None]
        S += g.T @ g
        for lag in range(1, _bandwidth(r[a:b]) + 1):
            wgt = 1.0 - lag / (_bandwidth(r[a:b]) + 1.0)
            G = g[lag:].T @ g[:-lag]
            S += wgt * (G + G.T)
    if n_prior:
        Jp = J[m - n_prior:]
        S += Jp.T @ Jp
    cov = Hinv @ S @ Hinv
    plain = Hinv * s2
    d = np.sqrt(np.maximum(np.diag(cov), 0.0))
    floor = np.sqrt(np.maximum(np.diag(plain), 0.0))
    scale = np.where(d > 0, np.maximum(floor / np.where(d > 0, d, 1.0), 1.0), 1.0)
    cov = cov * scale[:, None] * scale[None, :]
    return cov, null, Hinv


def _input_covariance(problem: _Problem, x: np.ndarray, J: np.ndarray, Hinv: np.ndarray,
                      rng: np.random.Generator, draws: int = INPUT_DRAWS) -> np.ndarray:
    """The estimates' covariance (scaled coordinates) from the errors of the measured inputs:
    each launch simulated with its clutch travel and engine input (torque or throttle)
    samples perturbed by their error level (:func:`_input_sigma`), the change of its
    residual mapped to the parameters by the Gauss–Newton step ``−H⁻¹Jᵀδr``; the second moment over the draws, summed over
    the launches."""
    values = problem.space.to_physical(x)
    data = problem.data
    pert, owner = [], []
    for k, d in enumerate(data):
        (_, vt, st), (_, vq, sq) = d.raw.values()
        for _ in range(draws):
            pert.append(_launch_input(d.launch, d.raw,
                                      vt + st * rng.standard_normal(vt.size),
                                      vq + sq * rng.standard_normal(vq.size)))
            owner.append(k)
    Y = problem.simulate([(k, values) for k in owner], inputs=pert)
    r0 = problem.residual(x)
    offsets = problem.offsets()
    cov = np.zeros((x.size, x.size))
    for i, k in enumerate(owner):
        a, b = offsets[k], offsets[k + 1]
        dr = problem.residual_of(Y[i], data[k]) - r0[a:b]
        dx = -Hinv @ (J[a:b].T @ dr)
        cov += np.outer(dx, dx) / draws
    return cov


# --------------------------------------------------------------------------- results
@dataclass(frozen=True, eq=False)
class LaunchTrace:
    """One launch measured and simulated: per signal ``(t, measured, simulated)`` at the
    measured stamps (SI), the simulated grid ``t_grid`` [s, log clock] with the engine,
    input and wheel speeds [rad/s] and the vehicle speed [m/s] (rows of
    :data:`~.launch_plant.SIGNALS`) ``states``, and its error measures ``metrics``."""

    name: str
    role: str
    signals: Mapping[str, tuple[np.ndarray, np.ndarray, np.ndarray]]
    t_grid: np.ndarray
    states: np.ndarray
    metrics: Mapping[str, float | None]
    launch: Launch

    def as_dict(self) -> dict:
        return {"name": self.name, "role": self.role, **self.launch.describe(),
                **dict(self.metrics)}


@dataclass(frozen=True, eq=False)
class CalibrationResult:
    """Outcome of :func:`calibrate`.

    ``parameters``, ``stderr``, ``intervals`` (at ``confidence``): the fitted values (SI,
    per-launch ones as ``name@k``); ``correlation`` the correlation matrix of the estimates
    in ``names`` order; ``at_bound``, ``unidentified`` and ``warnings`` as for
    :class:`~.fit.FitResult`; ``units`` each parameter's unit; ``keys`` the scenario key of
    each scenario parameter; ``sliding_capacity`` the clutch's sliding torque at full clamp
    load at :data:`SLIDE_SPEED` of slip (``value``, ``interval`` [N·m], ``speed`` [rad/s]:
    what a launch measures of the capacity, comparable across friction models; None
    where capacity is not fitted); ``fixed`` the values held; ``sigma`` each signal's noise
    level used (RMS residual); ``launches``, ``validation`` the traces; ``evaluations``
    simulated launches; ``wall_time`` [s].
    """

    parameters: Mapping[str, float]
    stderr: Mapping[str, float | None]
    intervals: Mapping[str, tuple[float, float] | None]
    confidence: float
    names: tuple[str, ...]
    correlation: np.ndarray
    bounds: Mapping[str, tuple[float, float]]
    at_bound: tuple[str, ...]
    unidentified: tuple[str, ...]
    warnings: tuple[str, ...]
    fixed: Mapping[str, float]
    sigma: Mapping[str, float]
    launches: tuple[LaunchTrace, ...]
    validation: tuple[LaunchTrace, ...]
    evaluations: int
    wall_time: float
    message: str
    notes: tuple[str, ...] = ()
    units: Mapping[str, str] = field(default_factory=dict)
    keys: Mapping[str, str] = field(default_factory=dict)
    sliding_capacity: Mapping[str, object] | None = None

    def summary(self) -> dict:
        """The document ``clutchsim calibrate --json`` prints."""
        return {"parameters": dict(self.parameters), "stderr": dict(self.stderr),
                "intervals": {k: list(v) if v else None for k, v in self.intervals.items()},
                "confidence": self.confidence,
                "units": dict(self.units), "keys": dict(self.keys),
                "correlation": {"names": list(self.names),
                                "matrix": np.round(self.correlation, 4).tolist()},
                "at_bound": list(self.at_bound), "unidentified": list(self.unidentified),
                "warnings": list(self.warnings),
                "launches": [t.as_dict() for t in self.launches],
                "validation": [t.as_dict() for t in self.validation],
                "sliding_capacity": None if self.sliding_capacity is None else {
                    k: list(v) if isinstance(v, tuple) else v
                    for k, v in self.sliding_capacity.items()},
                "sigma": dict(self.sigma), "notes": list(self.notes),
                "evaluations": self.evaluations, "wall_time_s": self.wall_time}

    def as_dict(self) -> dict:
        return {**self.summary(), "fixed": dict(self.fixed),
                "bounds": {k: list(v) for k, v in self.bounds.items()},
                "message": self.message}

    def parameters_toml(self) -> str:
        """The fitted and fixed values as a TOML parameter file, intervals beside them."""
        pct = f"{100 * self.confidence:g} %"
        lines = ["# Launch parameters calibrated by clutchsim calibrate (SI units); a",
                 "# scenario parameter's key path follows its unit.",
                 f"# Each fitted value with its {pct} interval; see calibration.json.", "",
                 "[parameters]"]
        for n in self.names:
            iv = self.intervals[n]
            unit = self.units.get(n, "")
            key = self.keys.get(n.partition("@")[0])
            note = "not identified" if n in self.unidentified else (
                f"{pct}: [{iv[0]:.6g}, {iv[1]:.6g}]" if iv else "no interval")
            lines.append(f'"{n}" = {self.parameters[n]!r}   # {unit}'
                         + (f" ({key})" if key else "") + f"; {note}")
        lines += ["", "[intervals]"]
        lines += [f'"{n}" = [{iv[0]!r}, {iv[1]!r}]' for n, iv in self.intervals.items() if iv]
        lines += ["", "[fixed]"]
        lines += [f'"{n}" = {v!r}' for n, v in self.fixed.items()]
        return "\n".join(lines) + "\n"


def _metrics(problem: _Problem, d: _LaunchData, Y: np.ndarray) -> dict:
    """Engine-speed RMS [rpm], slip-end time error [ms], peak jerk (measured, simulated,
    error [m/s³]) of one launch simulated as ``Y``."""
    spec = problem.spec
    plant = spec.plant
    grid = d.launch.t_start + d.grid(spec.step)
    out: dict[str, float | None] = {}
    by = {o.signal: o for o in d.outputs}
    e = by["engine_speed"]
    out["engine_rms_rpm"] = float(np.sqrt(np.mean((e.of(Y) - e.y) ** 2)) * RPM)
    f = spec.finder
    sig = d.launch.signals
    v = by.get("vehicle_speed") or by.get("wheel_speed")
    # (a vehicle speed in m/s, a wheel speed in rad/s: to the wheels' rad/s)
    to_wheel = 1.0 / plant.tyre_radius if v is not None and v.signal == "vehicle_speed" else 1.0
    if "input_speed" in sig:
        w_in_t, w_in = sig["input_speed"].t, sig["input_speed"].values
    else:
        w_in_t = v.t if v else None
        w_in = (v.y * to_wheel * plant.ratio) if v and plant.ratio else None
    meas = slip_end(e.t, e.y, w_in_t, w_in, d.launch.t_clutch, f.lockup_slip,
                    f.lockup_time) if w_in is not None else None
    row_in = SIGNALS.index("input_speed")
    sim = slip_end(grid, Y[0], grid, Y[row_in], d.launch.t_clutch, f.lockup_slip,
                   f.lockup_time)
    out["slip_end_measured_s"] = meas
    out["slip_end_simulated_s"] = sim
    out["slip_end_error_ms"] = None if meas is None or sim is None else 1e3 * (sim - meas)
    if v is not None and v.t.size > 12:
        r = to_wheel * plant.tyre_radius          # m/s per unit of v
        jm, js = _peak_jerk(v.t, v.y * r), _peak_jerk(v.t, v.of(Y) * r)
        out["peak_jerk_measured"] = jm
        out["peak_jerk_simulated"] = js
        out["peak_jerk_error"] = js - jm
    return {k: None if v is None or not math.isfinite(v) else float(v) for k, v in out.items()}


def _peak_jerk(t: np.ndarray, v: np.ndarray) -> float:
    """Largest |jerk| [m/s³] of a speed record: resampled at its median rate, then a
    Savitzky–Golay second derivative over 0.4 s (the same for measured and simulated)."""
    dt = float(np.median(np.diff(t)))
    grid = np.arange(t[0], t[-1], dt)
    window = max(5, round(0.4 / dt) | 1)
    if grid.size <= window:
        return float("nan")
    u = np.interp(grid, t, v)
    return float(np.max(np.abs(savgol_filter(u, window, 3, deriv=2, delta=dt))))


def _trace(problem: _Problem, d: _LaunchData, Y: np.ndarray, role: str) -> LaunchTrace:
    signals = {o.signal: (o.t, o.y, o.of(Y)) for o in d.outputs}
    grid = d.launch.t_start + d.grid(problem.spec.step)
    return LaunchTrace(d.launch.name, role, MappingProxyType(signals), grid, Y,
                       MappingProxyType(_metrics(problem, d, Y)), d.launch)


# --------------------------------------------------------------------------- entry point
def launches_of(spec: CalibrationSpec, logs, *, role: str = "fit") -> list[Launch]:
    """The launches of ``logs`` (paths, mapped logs or launches): found by the launch
    finder, or cut at the spec's ``windows``; ``launches`` picks some (fitting only)."""
    out = []
    for item in logs:
        if isinstance(item, Launch):
            out.append(item)
            continue
        mapped = item if isinstance(item, MappedLog) else spec.read(item)
        if spec.windows and role == "fit":
            found = [cut_launch(mapped, a, b, spec.finder, k + 1)
                     for k, (a, b) in enumerate(spec.windows)]
        else:
            found = find_launches(mapped, spec.finder)
        if not found:
            raise ValueError(f"{mapped.source}: no launch found (a standstill of "
                             f"{spec.finder.rest_time:g} s, then the vehicle above "
                             f"{spec.finder.move_speed:g} m/s with a clutch event); the "
                             "rule: a calibration log holds at least one launch")
        if spec.launches is not None and role == "fit":
            missing = [k for k in spec.launches if k > len(found)]
            if missing:
                raise CalibrationError(f"{spec.where('calibration', 'launches')}: launch(es) "
                                       f"{missing} asked, {mapped.source} has {len(found)}")
            found = [found[k - 1] for k in spec.launches]
        out.extend(found)
    return out


def calibrate(spec: CalibrationSpec | str | Path, logs=None, validate=None, *,
              options: FitOptions | None = None, progress=None) -> CalibrationResult:
    """Fit the spec's launch scenario to the launches of vehicle logs (see the module notes).

    Parameters
    ----------
    spec : CalibrationSpec or path
        The calibration spec (:func:`load_calibration`).
    logs, validate : sequence of paths, MappedLog or Launch, optional
        Logs to fit (default: the spec's ``logs``) and logs whose launches are predicted at
        the fitted values (default: the spec's ``validate``).
    options : FitOptions, optional
        Search options (default: the spec's ``[fit]`` over :data:`CALIBRATION_SEARCH`).
    progress : callable, optional
        ``progress(done, total)`` after each pass.

    Returns
    -------
    CalibrationResult
    """
    wall0 = time.perf_counter()
    spec = spec if isinstance(spec, CalibrationSpec) else load_calibration(spec)
    options = options or spec.fit_options()
    fit_launches = launches_of(spec, list(logs) if logs is not None else list(spec.logs))
    if not fit_launches:
        raise ValueError("calibrate: no logs to fit (give --log or [calibration] logs)")
    val_launches = launches_of(spec, list(validate) if validate is not None
                               else list(spec.validate), role="validate")
    data = [_prepare(la, spec) for la in fit_launches]
    names = list(spec.fitted)
    start = {n: spec.fitted[n]["start"] for n in names}
    bounds = {n: spec.fitted[n]["bounds"] for n in names if "bounds" in spec.fitted[n]}
    for base in spec.per_launch:
        for k, d in enumerate(data):
            n = f"{base}@{k + 1}"
            names.append(n)
            if base == "engine_speed0":
                start[n] = d.engine_speed0
                bounds[n] = (d.engine_speed0 - 10.0, d.engine_speed0 + 10.0)
            else:
                start[n] = spec.fixed.get(base, INPUT_DEFAULTS[base])
                bounds[n] = (-100.0, 100.0)
    space = ParameterSpace.build(names, start, bounds, {})
    problem = _Problem(spec, data, names, space)
    rng = np.random.default_rng(options.seed)
    x_first = space.clip_inside(space.to_scaled(np.array([start[n] for n in names])))
    if isinstance(options.starts, int):
        points = [x_first] + [space.clip_inside(space.random(rng))
                              for _ in range(options.starts - 1)]
    else:                       # explicit start points: name -> value, the rest as given
        points = []
        for k, point in enumerate(options.starts):
            bad = [n for n in point if n not in names]
            if bad:
                raise ValueError(f"starts[{k}]: {', '.join(bad)} not fitted; fitted: "
                                 f"{', '.join(names)}")
            vals = np.array([float(point.get(n, start[n])) for n in names])
            points.append(space.clip_inside(space.to_scaled(vals)))
    best = None
    for k, x0 in enumerate(points):
        sol = _solve(problem, x0, options)
        if best is None or sol.cost < best.cost:
            best = sol
        if progress is not None:
            progress(k + 1, len(points) + 1)
    # second pass: each signal whitened and weighted by its own noise model
    blocks = problem.blocks()
    problem.noise_model(best.x)
    best = _solve(problem, best.x, options)
    if progress is not None:
        progress(len(points) + 1, len(points) + 1)
    r = problem.residual(best.x)
    J = problem.jacobian(best.x, r, options.diff_step)
    cov, null, Hinv = _covariance(J, r, blocks, len(problem.prior))
    cov = cov + _input_covariance(problem, best.x, J, Hinv, rng)
    values = space.to_physical(best.x)
    deriv = space.derivative(best.x)
    z = float(norm.ppf(0.5 + spec.confidence / 2))
    se_x = np.sqrt(np.maximum(np.diag(cov), 0.0))
    params, stderr, intervals, phys_bounds = {}, {}, {}, {}
    for j, n in enumerate(names):
        params[n] = float(values[j])
        phys_bounds[n] = (float(space.lower[j]), float(space.upper[j]))
        if null[j]:
            stderr[n], intervals[n] = None, None
            continue
        stderr[n] = float(abs(deriv[j]) * se_x[j])
        half = z * se_x[j]
        lo_hi = (10.0 ** (best.x[j] + np.array([-half, half])) if space.log[j]
                 else values[j] + np.array([-1.0, 1.0]) * z * stderr[n])
        intervals[n] = (float(min(lo_hi)), float(max(lo_hi)))
    d = np.sqrt(np.maximum(np.diag(cov), 1e-300))
    corr = np.clip(cov / d[:, None] / d[None, :], -1.0, 1.0)
    at_bound, unidentified, warnings = [], [], []
    if spec.plant.engine == "throttle":
        warnings.append(THROTTLE_INTERVALS)
    for j, n in enumerate(names):
        side = _at_bound(params[n], *phys_bounds[n])
        if side:
            at_bound.append(n)
            warnings.append(f"{n} = {params[n]:.6g} is at its {side} bound: the logs push it "
                            "there, so this is the bound, not an estimate; widen the bound or "
                            "fix the parameter")
        iv = intervals[n]
        lo, hi = phys_bounds[n]
        if iv is None or (iv[1] - iv[0]) > 0.5 * (hi - lo):
            unidentified.append(n)
            warnings.append(f"{n} cannot be identified from these logs: "
                            + ("no simulated signal depends on it" if iv is None else
                               f"its {100 * spec.confidence:g} % interval [{iv[0]:.4g}, "
                               f"{iv[1]:.4g}] covers more than half of its bounds")
                            + "; fix it ([fixed]) or log launches that excite it")
    Y = problem.simulate([(k, values) for k in range(len(data))])
    traces = tuple(_trace(problem, dk, Y[k], "fit") for k, dk in enumerate(data))
    val = []
    if val_launches:
        vdata = [_prepare(la, spec) for la in val_launches]
        Yv = problem.simulate([(k, values) for k in range(len(vdata))], vdata)
        val = [_trace(problem, dk, Yv[k], "validate") for k, dk in enumerate(vdata)]
    plant = spec.plant
    sliding = None
    if "capacity" in params:
        model = plant.plan.net.component(plant.layout.clutch).model
        k = float(model.steady_state_force(SLIDE_SPEED)) / plant.capacity0
        iv = intervals["capacity"]
        sliding = MappingProxyType({"value": k * params["capacity"], "speed": SLIDE_SPEED,
                                    "interval": None if iv is None else (k * iv[0], k * iv[1])})
    notes = [(f"model: the network of {plant.scenario.file or plant.scenario.name} with "
              f"{plant.model} on its clutch (static capacity {plant.capacity0:.6g} N·m at "
              f"COM 1), its engine driven by the measured {plant.engine}"),
             f"{len(data)} launch(es) fitted: " + ", ".join(
        f"{d.launch.name} ({d.launch.t_start:.2f} ... {d.launch.t_end:.2f} s)" for d in data)]
    fixed = {**INPUT_DEFAULTS, **spec.fixed}
    if plant.engine != "torque":
        fixed = {k: v for k, v in fixed.items() if k not in TORQUE_PARAMETERS}
    fixed = {k: v for k, v in fixed.items() if k not in spec.fitted
             and not any(n.startswith(k + "@") for n in names)}
    return CalibrationResult(
        MappingProxyType(params), MappingProxyType(stderr), MappingProxyType(intervals),
        spec.confidence, tuple(names), corr, MappingProxyType(phys_bounds), tuple(at_bound),
        tuple(unidentified), tuple(warnings), MappingProxyType(fixed),
        MappingProxyType({s: problem.sigma[s] for s in {b[0] for b in blocks}}), traces,
        tuple(val), problem.evaluations, time.perf_counter() - wall0, str(best.message),
        tuple(notes), MappingProxyType({n: spec.unit(n) for n in names}),
        MappingProxyType(dict(spec.keys)), sliding)
