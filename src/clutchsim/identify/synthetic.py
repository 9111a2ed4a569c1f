"""Synthetic vehicle logs with a known truth: launches simulated with the launch model, then
degraded as a data logger records them.

:func:`synthetic_log` drives the model of :mod:`.launch_model` through ``launches`` cycles:
idle with the clutch open, the actuator closing the clutch while the driver adds torque (an
idle governor holds the engine up), driving on in first gear, then the clutch opens and the
brake stops the car.  The engine torque the model produced is what the engine controller
reports (``(T − torque_offset)/torque_scale``).  The channels are named and scaled as the
J1939 messages of ``examples/calibration/j1939_launch.dbc`` carry them, each group at its own
rate, and degraded (:class:`Degradation`): white noise, quantisation (1 rpm, 0.1 km/h,
1 % torque, 0.01 mm), and stamps that lag the sampling instant by a random delay (the
logger stamps a frame when it arrives).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from ..data.logs import Channel, VehicleLog
from .launch_model import LaunchInputs, LaunchVehicle, simulate_launches

__all__ = ["DEFAULT_TRUTH", "Degradation", "synthetic_log"]

#: the parameters the synthetic logs are made with by default (SI)
DEFAULT_TRUTH: Mapping[str, float] = {
    "capacity": 240.0, "touch_point": 0.0055, "engage_travel": 0.0025, "clamp_exponent": 1.5,
    "stiffness": 12000.0, "damping": 60.0, "torque_scale": 0.95, "torque_offset": -12.0,
    "mu_rise": 0.0, "slip_ref": 20.0,
}
#: the engine's reference torque: 100 % of the J1939 percent torque [N·m]
REFERENCE_TORQUE = 250.0
RPM = np.pi / 30.0


@dataclass(frozen=True)
class Degradation:
    """How the logger degrades the true signals: rates [Hz] per message group, noise (one
    standard deviation, in the logged unit), quantisation steps, and the largest stamp delay
    [s] (uniform between 0 and it)."""

    rates: Mapping[str, float] = field(default_factory=lambda: {
        "EEC1": 25.0, "CCVS": 17.0, "ETC1": 50.0, "CLUTCH": 50.0})
    engine_speed_noise: float = 2.0        # rpm
    input_speed_noise: float = 2.0         # rpm
    vehicle_speed_noise: float = 0.05      # km/h
    position_noise: float = 0.01           # mm
    rpm_step: float = 1.0
    speed_step: float = 0.1                # km/h
    torque_step: float = 1.0               # % of the reference torque
    position_step: float = 0.01            # mm
    stamp_delay: float = 0.003             # s


def _profiles(n_launches: int, cycle: float, h: float, rng: np.random.Generator):
    """Clutch travel [m], torque demand [N·m] and brake capacity [N·m] on one grid."""
    n = round(n_launches * cycle / h)
    t = np.arange(n + 1) * h
    travel, demand, brake = np.zeros_like(t), np.zeros_like(t), np.zeros_like(t)
    for k in range(n_launches):
        s = k * cycle
        tau = t - s
        ramp = 0.8 + 0.6 * rng.random()                # s: the slow part of the engagement
        lift = 45.0 + 25.0 * rng.random()              # N·m: the driver's extra torque
        inside = (tau >= 0) & (tau < cycle)
        x = np.interp(tau, [0.0, 1.0, 1.2, 1.2 + ramp, 1.4 + ramp, 5.5, 5.6, cycle],
                      [0.0, 0.0, 0.004, 0.008, 0.009, 0.009, 0.0, 0.0])
        q = np.interp(tau, [0.0, 1.1, 1.5, 1.5 + ramp, 2.5 + ramp, 5.5, 5.6, cycle],
                      [0.0, 0.0, lift, lift, 25.0, 25.0, 0.0, 0.0])
        b = np.interp(tau, [0.0, 0.3, 0.4, 5.6, 5.8, cycle - 1.5, cycle - 1.4, cycle],
                      [2000.0, 2000.0, 0.0, 0.0, 1500.0, 1500.0, 2000.0, 2000.0])
        travel[inside], demand[inside], brake[inside] = x[inside], q[inside], b[inside]
    return t, travel, demand, brake


def _sample(t, y, rate: float, t_end: float, delay: float, rng) -> tuple:
    """Values of ``y(t)`` at the instants of a ``rate`` Hz logger and their (late) stamps."""
    ts = np.arange(0.0, t_end, 1.0 / rate) + rng.random() / rate
    ts = ts[ts <= t_end]
    stamps = ts + delay * rng.random(ts.size)
    return ts, stamps, [np.interp(ts, t, yi) for yi in y]


def _quantise(x, step):
    return np.round(np.asarray(x) / step) * step


def synthetic_log(*, launches: int = 3, seed: int = 0, truth: Mapping[str, float] | None = None,
                  vehicle: LaunchVehicle | None = None, cycle: float = 9.0, h: float = 0.001,
                  degradation: Degradation | None = None, source: str = "synthetic"
                  ) -> tuple[VehicleLog, dict]:
    """A log of ``launches`` launches and the truth it was made with (see the module notes).

    Returns ``(log, truth)``: ``truth`` holds the model parameters and the true traces
    (``t``, ``engine_speed``, ``input_speed``, ``wheel_speed`` [rad/s]).
    """
    rng = np.random.default_rng(seed)
    vehicle = vehicle or LaunchVehicle()
    deg = degradation or Degradation()
    params = dict(DEFAULT_TRUTH)
    params.update(truth or {})
    t, travel, demand, brake = _profiles(launches, cycle, h, rng)
    # the engine produces k·demand + offset + governor; the controller reports it back
    inputs = LaunchInputs(travel[None], demand[None], brake[None], np.zeros(1), h)
    y0 = np.array([[83.78, 0.0, 0.0, 0.0]])
    out = simulate_launches(vehicle, inputs, np.zeros(1, dtype=int),
                            {k: np.array([v]) for k, v in params.items()}, y0,
                            governor=(83.78, 3.0, 100.0))[0]
    w_e, w_i, w_w, torque = out
    reported = (torque - params["torque_offset"]) / params["torque_scale"]
    t_end = float(t[-1])
    r = vehicle.tyre_radius
    channels = {}

    def add(group, names_units, values):
        _, stamps, vals = _sample(t, values, deg.rates[group], t_end, deg.stamp_delay, rng)
        for (name, unit, make), v in zip(names_units, vals):
            channels[name] = Channel(name, stamps, make(v), unit, group)

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
        [w_w * r, travel])
    add("CLUTCH", [("ClutchActuatorPosition", "mm", lambda v: _quantise(
        1e3 * v + deg.position_noise * rng.standard_normal(v.size), deg.position_step))],
        [travel])
    log = VehicleLog(source, channels, ())
    return log, {"parameters": params, "t": t, "engine_speed": w_e, "input_speed": w_i,
                 "wheel_speed": w_w, "travel": travel, "reference_torque": REFERENCE_TORQUE}
