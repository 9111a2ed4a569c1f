"""Synthetic vehicle logs with a known truth: launches of a launch scenario simulated by
clutchsim itself, then degraded as a data logger records them.

:func:`synthetic_log` runs the scenario's network (its own engine with its full-load map,
drag and idle governor; its clutch model, or another one: the model error of a calibration)
through ``launches`` cycles: idle with the clutch open, the actuator closing the clutch
(travel through the truth's clamp map to the clutch's command) while the driver opens the
throttle, driving on in first gear.  Each launch is one run from rest.  Between launches
the car is braked to rest and the engine returns to idle: that part of the log (after each
run's end, outside every launch window the finder cuts) is a ramp of the signals to rest,
not simulated.  The engine torque the run produced (``T_engine``) is what the engine
controller reports (``(T − torque_offset)/torque_scale``); the driver's throttle is the
accelerator pedal position it reports (EEC2, 20 Hz).  The channels are named and
scaled as the J1939 messages of ``examples/calibration/j1939_launch.dbc`` carry them, each
group at its own rate, and degraded (:class:`Degradation`): white noise, quantisation
(1 rpm, 0.1 km/h, 1 % torque, 0.4 % pedal, 0.01 mm), and stamps that lag the sampling
instant by a random delay (the logger stamps a frame when it arrives).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace

import numpy as np

from ..core import simulate
from ..core.signals import Table
from ..data.logs import Channel, VehicleLog
from .launch_plant import INPUT_DEFAULTS, check_signals, layout

__all__ = ["DEFAULT_TRUTH", "Degradation", "synthetic_log"]

#: the input parameters the synthetic logs are made with by default (SI); the scenario's
#: own values are its truth for the rest (the default launch: driveshaft c = 12,000
#: N·m/rad, d = 60 N·m·s/rad)
DEFAULT_TRUTH: Mapping[str, float] = {
    **INPUT_DEFAULTS, "capacity": 240.0, "touch_point": 0.0055, "torque_scale": 0.95,
    "torque_offset": -12.0}
#: the engine's reference torque: 100 % of the J1939 percent torque [N·m]
REFERENCE_TORQUE = 250.0
RPM = np.pi / 30.0
#: length of the simulated part of a cycle (a launch from rest and driving on) [s]
DRIVE = 5.5
#: time the car takes to brake to rest after a run [s]
STOP = 2.0


@dataclass(frozen=True)
class Degradation:
    """How the logger degrades the true signals: rates [Hz] per message group, noise (one
    standard deviation, in the logged unit), quantisation steps, and the largest stamp delay
    [s] (uniform between 0 and it)."""

    rates: Mapping[str, float] = field(default_factory=lambda: {
        "EEC1": 25.0, "CCVS": 17.0, "ETC1": 50.0, "CLUTCH": 50.0, "EEC2": 20.0})
    engine_speed_noise: float = 2.0        # rpm
    input_speed_noise: float = 2.0         # rpm
    vehicle_speed_noise: float = 0.05      # km/h
    position_noise: float = 0.01           # mm
    rpm_step: float = 1.0
    speed_step: float = 0.1                # km/h
    torque_step: float = 1.0               # % of the reference torque
    position_step: float = 0.01            # mm
    pedal_step: float = 0.4                # % (EEC2 accelerator pedal position)
    stamp_delay: float = 0.003             # s


def _profile(rng: np.random.Generator, tau: np.ndarray):
    """Clutch travel [m] and throttle [-] of one launch at its times ``tau`` [s]."""
    ramp = 0.8 + 0.6 * rng.random()                # s: the slow part of the engagement
    lift = 0.25 + 0.1 * rng.random()               # the driver's throttle
    bite = 0.0066 + 0.0006 * rng.random()          # m: where the slow part ends
    x = np.interp(tau, [0.0, 1.0, 1.2, 1.2 + ramp, 1.8 + ramp],
                  [0.0, 0.0, 0.005, bite, 0.009])
    q = np.interp(tau, [0.0, 1.0, 1.3, 1.5 + ramp, 2.5 + ramp],
                  [0.0, 0.0, lift, lift, 0.15])
    return x, q


def _sample(t, y, rate: float, t_end: float, delay: float, rng) -> tuple:
    """Values of ``y(t)`` at the instants of a ``rate`` Hz logger and their (late) stamps."""
    ts = np.arange(0.0, t_end, 1.0 / rate) + rng.random() / rate
    ts = ts[ts <= t_end]
    stamps = ts + delay * rng.random(ts.size)
    return ts, stamps, [np.interp(ts, t, yi) for yi in y]


def _quantise(x, step):
    return np.round(np.asarray(x) / step) * step


def _truth_scenario(scenario, keys: Mapping[str, float]):
    if not keys:
        return scenario
    from ..scenario.loader import apply_overrides, parse_scenario, toml_value
    data = apply_overrides(scenario.data, [f"{k}={toml_value(v)}" for k, v in keys.items()],
                           scenario.file)
    return parse_scenario(data, text=scenario.text, file=scenario.file)


def synthetic_log(scenario=None, *, model: str | None = None, launches: int = 3,
                  seed: int = 0, truth: Mapping[str, float] | None = None,
                  signals: Mapping[str, str] | None = None, cycle: float = 9.0,
                  h: float = 0.001, degradation: Degradation | None = None,
                  source: str = "synthetic") -> tuple[VehicleLog, dict]:
    """A log of ``launches`` launches of ``scenario`` (default: the packaged launch) and
    the truth it was made with (see the module notes).

    ``truth``: input parameters (:data:`DEFAULT_TRUTH` for those not given) and scenario
    keys (``{"coupling[3].c": 10000.0}``) with their true values; ``model``: the clutch's
    friction model (default: the scenario's first); ``signals``: as for
    :class:`~.launch_plant.LaunchPlant`.  Returns ``(log, truth)``: ``truth`` holds the
    ``parameters`` and the true traces (``t``, ``engine_speed``, ``input_speed``,
    ``wheel_speed`` [rad/s], ``vehicle_speed`` [m/s], ``travel`` [m]).
    """
    from ..scenario.loader import load_scenario
    if cycle < DRIVE + STOP + 1.0:
        raise ValueError(f"cycle = {cycle:g} s: at least {DRIVE + STOP + 1.0:g} s (a launch, "
                         "the stop and a second at rest)")
    rng = np.random.default_rng(seed)
    deg = degradation or Degradation()
    params = {**DEFAULT_TRUTH, **dict(truth or {})}
    base = load_scenario(None) if scenario is None else scenario
    keys = {k: v for k, v in params.items() if k not in DEFAULT_TRUTH}
    sc = _truth_scenario(base, keys)
    lay = layout(sc, model, signals)
    system = sc.network(lay.model).build(sc.inputs0())
    check_signals(system, lay.signals)
    options = replace(sc.options, dt_out=h)
    n = round(launches * cycle / h)
    t = np.arange(n + 1) * h
    names = ("engine_speed", "input_speed", "wheel_speed", "vehicle_speed")
    traces = {k: np.zeros_like(t) for k in (*names, "travel", "torque", "throttle")}
    for k in range(launches):
        tau = np.arange(0.0, DRIVE + 0.5 * h, h)
        x, q = _profile(rng, tau)
        com = params["capacity"] / lay.capacity0 * np.clip(
            (x - params["touch_point"]) / params["engage_travel"], 0.0, 1.0) \
            ** params["clamp_exponent"]
        inputs = {**{k: v for k, v in sc.inputs.items() if k in system.input_names},
                  lay.command: Table(tau, com, hit_knots=False),
                  lay.throttle: Table(tau, q, hit_knots=False)}
        res = simulate(system, (0.0, DRIVE), inputs, solver=sc.solver, options=options)
        if res.status != "completed":
            raise RuntimeError(f"synthetic launch {k + 1}: the run ended {res.outcome}: "
                               f"{res.message}")
        s = k * cycle
        inside = (t >= s) & (t <= s + DRIVE)
        for name in names:
            traces[name][inside] = np.interp(t[inside] - s, res.t, res[lay.signals[name]])
        traces["torque"][inside] = np.interp(t[inside] - s, res.t, res["T_engine"])
        traces["travel"][inside] = np.interp(t[inside] - s, tau, x)
        traces["throttle"][inside] = np.interp(t[inside] - s, tau, q)
        # braked to rest, the clutch open, the engine back to idle (not simulated)
        after = (t > s + DRIVE) & ((t < s + cycle) | (k == launches - 1))
        frac = np.clip((t[after] - s - DRIVE) / STOP, 0.0, 1.0)
        last = {name: traces[name][inside][-1] for name in (*names, "torque")}
        idle = float(res[lay.signals["engine_speed"]][0])      # where each run starts
        for name in names[1:]:
            traces[name][after] = last[name] * (1.0 - frac)
        traces["engine_speed"][after] = last["engine_speed"] + (idle - last["engine_speed"]) * frac
        traces["torque"][after] = last["torque"] * (1.0 - frac)
        traces["travel"][after] = 0.0
    # runs start at rest at idle: the part before the first run too
    w_e, w_i, v = traces["engine_speed"], traces["input_speed"], traces["vehicle_speed"]
    travel = traces["travel"]
    reported = (traces["torque"] - params["torque_offset"]) / params["torque_scale"]
    t_end = float(t[-1])
    channels = {}

    def add(group, names_units, values):
        _, stamps, vals = _sample(t, values, deg.rates[group], t_end, deg.stamp_delay, rng)
        for (name, unit, make), val in zip(names_units, vals):
            channels[name] = Channel(name, stamps, make(val), unit, group)

    add("EEC1", [("EngineSpeed", "rpm", lambda v: _quantise(
        v / RPM + deg.engine_speed_noise * rng.standard_normal(v.size), deg.rpm_step)),
                 ("ActualEnginePercentTorque", "%", lambda v: _quantise(
                     100.0 * v / REFERENCE_TORQUE, deg.torque_step))],
        [w_e, reported])
    add("ETC1", [("InputShaftSpeed", "rpm", lambda v: np.maximum(_quantise(
        v / RPM + deg.input_speed_noise * rng.standard_normal(v.size), deg.rpm_step), 0.0))],
        [w_i])
    add("CCVS", [("WheelBasedVehicleSpeed", "km/h", lambda v: np.maximum(_quantise(
        3.6 * v + deg.vehicle_speed_noise * rng.standard_normal(v.size), deg.speed_step), 0.0)),
                 ("ClutchSwitch", "", lambda v: (v < params["touch_point"] - 0.001).astype(float))],
        [v, travel])
    add("CLUTCH", [("ClutchActuatorPosition", "mm", lambda v: _quantise(
        1e3 * v + deg.position_noise * rng.standard_normal(v.size), deg.position_step))],
        [travel])
    # (last: the draws of the other channels do not depend on it)
    add("EEC2", [("AcceleratorPedalPosition1", "%", lambda v: _quantise(
        100.0 * v, deg.pedal_step))], [traces["throttle"]])
    log = VehicleLog(source, channels, ())
    truth_params = {**params, **{k: float(v) for k, v in keys.items()}}
    return log, {"parameters": truth_params, "model": lay.model, "t": t,
                 **{name: traces[name] for name in names}, "travel": travel,
                 "throttle": traces["throttle"],
                 "reference_torque": REFERENCE_TORQUE}
