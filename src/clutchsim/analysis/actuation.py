"""What the actuation figures and the launch comparison show, computed apart from the
plotting (:mod:`clutchsim.plot.actuation`): the static characteristic of each release
system and hydraulic actuator of a network, the signals of the actuation chain in a run,
and the launch-quality metrics of two launches side by side (docs/actuation.md)."""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

__all__ = ["ACTUATION_KINDS", "CONTROLLER_KINDS", "QUALITY_KEYS", "Characteristic",
           "actuation_signals", "compare_quality", "has_controller", "static_characteristics"]

#: component kinds of the actuation chain and of closed-loop control
ACTUATION_KINDS = ("release_system", "hydraulic_actuator", "electromechanical_actuator",
                   "launch_controller", "driver")
#: component kinds that close a loop (their stability is checked on each run's result)
CONTROLLER_KINDS = ("launch_controller", "driver")
#: the launch-quality metrics a comparison lists (docs/launch-quality.md)
QUALITY_KEYS = ("engagement_start_s", "lockup_time_s", "slip_energy_J", "vdv_mps175",
                "aw_rms_mps2", "jerk_peak_mps3", "jerk_rms_mps3", "lockup_shock_mps2",
                "engine_dip_rpm", "engine_flare_rpm", "engine_speed_min_rpm",
                "peak_temperature_C")


class Characteristic(NamedTuple):
    """One static characteristic: clamp force [N] against ``x`` (travel [m] or pressure
    [Pa]); ``branches`` holds (label, x, force) curves (engaging and releasing with a
    play)."""

    component: str
    x_label: str
    branches: tuple


def static_characteristics(components, *, n: int = 200) -> list[Characteristic]:
    """The static characteristic of every release system (clamp force against engagement
    travel; with a play, the engaging and the releasing branch) and hydraulic actuator
    (piston force against pressure, up to 4 × its threshold or 5 MPa) of ``components``."""
    out = []
    for c in components:
        if c.kind == "release_system":
            xt, _f = c.characteristic
            x = np.linspace(0.0, 1.15 * (c.touch_point + xt[-1] + c.hysteresis), n)
            if c.has_play:
                h = 0.5 * c.hysteresis
                br = (("engaging", x, c.clamp_force(x - h)),
                      ("releasing", x, c.clamp_force(x + h)))
            else:
                br = (("static", x, c.clamp_force(x)),)
            out.append(Characteristic(c.name, "engagement travel [m]", br))
        elif c.kind == "hydraulic_actuator":
            p = np.linspace(0.0, max(4.0 * c.threshold_pressure, 5e6), n)
            f = c.area * np.maximum(p - c.threshold_pressure, 0.0)
            out.append(Characteristic(c.name, "pressure [Pa]", (("static", p, f),)))
    return out


def actuation_signals(result) -> list[tuple[str, str, list[str]]]:
    """``(title, unit, [signal, ...])`` panels of a run's actuation chain: commands of
    controllers and drivers, actuator positions and pressures, clamp forces."""
    sig = result.signals
    units = result.units
    groups: dict = {}
    for name in sig:
        if "." not in name:
            continue
        local = name.rsplit(".", 1)[1]
        what = {"command": "controller commands", "throttle": "throttle",
                "position": "actuator positions", "pressure": "pressures",
                "force": "clamp forces", "clamp_force": "clamp forces"}.get(local)
        if what is not None:
            groups.setdefault((what, units.get(name, "")), []).append(name)
    return [(title, unit, names) for (title, unit), names in groups.items()]


def compare_quality(runs: dict) -> dict:
    """``{label: {metric: value}}`` of the launch-quality metrics (:data:`QUALITY_KEYS`)
    of each run's metrics ``runs[label]``, for a table of one row per launch."""
    return {label: {k: m[k] for k in QUALITY_KEYS if k in m} for label, m in runs.items()}


#: a linearised loop is unstable where an eigenvalue grows faster than this [1/s]
GROWTH_TOL = 1e-3


def _growth(system, params, t, y, u) -> float:
    """Largest real part [1/s] of the eigenvalues of the plant linearised about (t, y, u)
    with the parameter vector ``params``."""
    from dataclasses import replace

    from .linear import linearise
    lin = linearise(replace(system, params=params), t, y, u)
    return float(np.max(np.linalg.eigvals(lin.A).real)) if lin.n else 0.0


def controller_margin(scenario, system, result, plan) -> list[tuple]:
    """``(controller, t [s], growth rate [1/s], gain margin [-])`` of every launch
    controller and driver model of a run: the plant is linearised at the middle sample of
    the run in which the controller's output lies strictly inside its limits (its loop
    closed), and the gain margin is the factor on ``kp`` and ``ki`` together at which the
    largest eigenvalue's real part crosses :data:`GROWTH_TOL` (found by bisection over
    [1/64, 64]; ``inf`` when it stays stable).  A margin below 1: the loop is unstable at
    the given gains."""
    kinds = system.metadata.get("kinds", {})
    out = []
    for name, kind in kinds.items():
        if kind not in CONTROLLER_KINDS:
            continue
        sig = f"{name}.{'command' if kind == 'launch_controller' else 'throttle'}"
        if sig not in result.signals or result.t.size < 3:
            continue
        comp = next(c for c in plan.net.components if c.name == name)
        lo, hi = (comp.u_min, comp.u_max) if kind == "launch_controller" else (0.0, 1.0)
        v = result[sig]
        span = 1e-6 * (hi - lo)
        inside = np.flatnonzero((v > lo + span) & (v < hi - span))
        if inside.size == 0:
            continue
        k = int(inside[inside.size // 2])
        t = float(result.t[k])
        y = np.array([float(result[n][k]) for n in system.state_names])
        u = np.array([float(np.asarray(scenario.inputs[n](t)).ravel()[0])
                      for n in system.input_names])
        slots = [plan.slot[(name, "kp")], plan.slot[(name, "ki")]]

        def growth(f, slots=slots, t=t, y=y, u=u):
            p = system.params.copy()
            p[slots] *= f
            return _growth(system, p, t, y, u)

        g1 = growth(1.0)
        lo_f, hi_f = 1.0 / 64.0, 64.0
        if growth(hi_f) <= GROWTH_TOL:
            margin = math.inf
        elif growth(lo_f) > GROWTH_TOL:
            margin = 0.0
        else:
            for _ in range(30):
                mid = math.sqrt(lo_f * hi_f)
                if growth(mid) > GROWTH_TOL:
                    hi_f = mid
                else:
                    lo_f = mid
            margin = math.sqrt(lo_f * hi_f)
        out.append((name, t, g1, margin))
    return out


def has_controller(system) -> bool:
    """Whether ``system`` has a component that closes a loop (:data:`CONTROLLER_KINDS`)."""
    return any(k in CONTROLLER_KINDS for k in system.metadata.get("kinds", {}).values())


def controller_warnings(scenario, system, result) -> list[str]:
    """A warning for each controller whose linearised loop is unstable at its gains
    (:func:`controller_margin`), with the margin and the remedy."""
    if not has_controller(system):
        return []
    kinds = system.metadata.get("kinds", {})
    if "component" not in scenario.data:
        return []
    from ..network import compile_network
    model = system.metadata.get("models", {}).get(scenario.clutch)
    plan = compile_network(scenario.network(model))
    out = []
    for name, t, g, margin in controller_margin(scenario, system, result, plan):
        if g > GROWTH_TOL:
            out.append(f"{kinds[name].replace('_', ' ')} {name!r}: its loop, linearised at "
                       f"t = {t:.3f} s, is unstable (growth rate {g:.3g} 1/s); gain margin "
                       f"{margin:.3g}: kp and ki must be lowered below {margin:.3g} times "
                       "their values")
    return out
