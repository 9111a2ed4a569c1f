"""The launch model that :mod:`.calibrate` fits to vehicle logs, simulated for many parameter
sets at once.

Four states: engine speed ``w_e`` [rad/s], gearbox input speed ``w_i`` [rad/s] (clutch disc
and input shaft), driveshaft twist ``phi`` [rad] (at the wheels) and wheel speed ``w_w``
[rad/s].  The vehicle's mass sits on the wheels (``J_v = J_wheels + m·r²``); the gear (gear
ratio times final drive) is rigid, the driveshaft is a spring and damper (``stiffness`` c,
``damping`` d, at the wheels: the shuffle mode)::

    J_e·dw_e/dt = k_T·T_meas + T_0 − T_cl                       engine (measured torque in)
    J_i·dw_i/dt = T_cl − T_s/i − b·w_i                            disc and input shaft
    J_v·dw_w/dt = T_s − T_road − ½ρ·c_dA·r³·w_w|w_w|               vehicle
    dphi/dt    = w_i/i − w_w,   T_s = c·phi + d·(w_i/i − w_w)

The clutch carries at most ``T_cap = capacity · f(x) · (1 + mu_rise·(1 − exp(−|Δw|/slip_ref)))``
where ``x`` is the measured engagement travel (increasing closes the clutch) and the clamp map
is ``f(x) = clip((x − touch_point)/engage_travel, 0, 1) ** clamp_exponent``; ``mu_rise`` = 0
is a Coulomb clutch (what the calibration fits), another value a friction coefficient that
rises with the slip speed (the model error of the synthetic checks).  Rolling resistance and
a brake act at the wheels the same way (at most their capacity, sticking at rest).

Time stepping: fixed steps ``h`` of semi-implicit Euler, with the clutch and the wheel friction
treated as in Moreau's time stepping: the torque that would stop the slip within the step is
computed and clipped to the capacity.  So sticking (lock-up, a vehicle at rest) is exact and
the step needs no event location: what makes the model cheap enough to simulate the finite
differences of a fit, for all launches and parameter columns in one vectorised pass.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, fields

import numpy as np

__all__ = ["LAUNCH_PARAMETERS", "LaunchInputs", "LaunchVehicle", "simulate_launches"]

#: the parameters of the launch model: unit and meaning (SI, as in the spec files)
LAUNCH_PARAMETERS: Mapping[str, tuple[str, str]] = {
    "capacity": ("N·m", "clutch torque capacity at full clamp load (μ·F·r_m·faces)"),
    "touch_point": ("m", ("engagement travel at which the linings start to carry (kiss point); "
                          "a fraction [-] for a pedal position in %")),
    "engage_travel": ("m", "travel from the touch point to the full clamp load"),
    "clamp_exponent": ("-", "shape of the clamp map f = u**exponent"),
    "stiffness": ("N·m/rad", "torsional stiffness of the driveline at the wheels (shuffle)"),
    "damping": ("N·m·s/rad", "torsional damping of the driveline at the wheels"),
    "torque_scale": ("-", "engine torque = torque_scale · measured torque + torque_offset"),
    "torque_offset": ("N·m", "engine torque offset (friction and accessory losses)"),
    "mu_rise": ("-", "rise of the friction coefficient with slip (0: Coulomb)"),
    "slip_ref": ("rad/s", "slip speed of the rise of mu_rise"),
    "engine_speed0": ("rad/s", "engine speed at the start of a launch"),
}


@dataclass(frozen=True)
class LaunchVehicle:
    """The data of the vehicle that the calibration does not fit (SI units).

    Attributes: inertias ``J_engine`` (crankshaft, flywheel), ``J_input`` (clutch disc,
    gearbox input shaft), ``J_wheels`` [kg·m²]; ``ratio`` gear times final drive [-];
    ``mass`` [kg]; ``tyre_radius`` [m]; ``rolling`` coefficient [-]; ``cd_area`` [m²];
    ``air_density`` [kg/m³]; ``bearing_damping`` of the input shaft [N·m·s/rad].
    """

    J_engine: float = 0.18
    J_input: float = 0.025
    J_wheels: float = 1.6
    ratio: float = 14.76
    mass: float = 1300.0
    tyre_radius: float = 0.3
    rolling: float = 0.012
    cd_area: float = 0.65
    air_density: float = 1.2
    bearing_damping: float = 0.005

    def __post_init__(self):
        for f in fields(self):
            value = getattr(self, f.name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise ValueError(f"vehicle {f.name} = {value!r}: must be a finite number > 0")

    @property
    def J_vehicle(self) -> float:
        """Inertia at the wheels, vehicle mass included [kg·m²]."""
        return self.J_wheels + self.mass * self.tyre_radius ** 2

    @classmethod
    def names(cls) -> tuple[str, ...]:
        return tuple(f.name for f in fields(cls))


@dataclass(frozen=True, eq=False)
class LaunchInputs:
    """The inputs of one or more launches on their fixed step grids, padded to one length.

    ``travel``, ``torque`` (measured engine torque [N·m]) and ``brake`` (brake torque
    capacity at the wheels [N·m]) have shape ``(n_launches, n_steps + 1)``; ``t0`` the start
    time of each launch [s]; ``h`` the step [s].
    """

    travel: np.ndarray
    torque: np.ndarray
    brake: np.ndarray
    t0: np.ndarray
    h: float

    @property
    def n_steps(self) -> int:
        return self.travel.shape[1] - 1


def simulate_launches(vehicle: LaunchVehicle, inputs: LaunchInputs, rows: np.ndarray,
                      params: Mapping[str, np.ndarray], y0: np.ndarray,
                      governor: tuple[float, float, float] | None = None) -> np.ndarray:
    """Simulate many launches at once; returns ``(n_rows, 3, n_steps + 1)``: engine, gearbox
    input and wheel speed [rad/s] at the grid points (with a ``governor``, a fourth row: the
    engine torque produced [N·m]).

    ``rows``: the launch (index into ``inputs``) of each simulated row; ``params``: every
    name of :data:`LAUNCH_PARAMETERS` but ``engine_speed0``, an array of one value per row;
    ``y0``: ``(n_rows, 4)`` initial states ``(w_e, w_i, phi, w_w)``.  ``governor``
    ``(idle speed, kp, torque limit)`` adds an idle speed governor to the engine torque (the
    synthetic truth of :mod:`.synthetic`, which then measures the torque it produced).
    """
    v = vehicle
    h = inputs.h
    rows = np.asarray(rows, dtype=np.intp)
    X, TM, TB = inputs.travel[rows], inputs.torque[rows], inputs.brake[rows]
    p = {k: np.asarray(val, dtype=float) for k, val in params.items()}
    cap, tp, span, expo = p["capacity"], p["touch_point"], p["engage_travel"], p["clamp_exponent"]
    c, d, kT, T0 = p["stiffness"], p["damping"], p["torque_scale"], p["torque_offset"]
    rise, sref = p["mu_rise"], p["slip_ref"]
    rising = bool(np.any(rise != 0.0))
    i, Je, Ji, Jv, b = v.ratio, v.J_engine, v.J_input, v.J_vehicle, v.bearing_damping
    k_stop = 1.0 / (h * (1.0 / Je + 1.0 / Ji))
    roll = v.rolling * v.mass * 9.81 * v.tyre_radius
    aero = 0.5 * v.air_density * v.cd_area * v.tyre_radius ** 3
    y = np.array(y0, dtype=float)
    we, wi, phi, ww = y[:, 0].copy(), y[:, 1].copy(), y[:, 2].copy(), y[:, 3].copy()
    n = inputs.n_steps
    out = np.empty((rows.size, 3 if governor is None else 4, n + 1))
    out[:, 0, 0], out[:, 1, 0], out[:, 2, 0] = we, wi, ww
    # the clamp map of every step at once (it depends on the inputs only)
    u = np.clip((X - tp[:, None]) / span[:, None], 0.0, 1.0)
    CAP = cap[:, None] * u ** expo[:, None]
    TE = kT[:, None] * TM + T0[:, None]
    WCAP = roll + TB
    for k in range(n):
        ts = c * phi + d * (wi / i - ww)
        te = TE[:, k]
        if governor is not None:
            te = te + np.clip(governor[1] * (governor[0] - we), 0.0, governor[2])
            out[:, 3, k] = te
        we_s = we + (h / Je) * te
        wi_s = wi - (h / Ji) * (ts / i + b * wi)
        cap_k = CAP[:, k]
        if rising:
            cap_k = cap_k * (1.0 + rise * (1.0 - np.exp(-np.abs(we - wi) / sref)))
        tc = np.clip((we_s - wi_s) * k_stop, -cap_k, cap_k)
        we = we_s - (h / Je) * tc
        wi = wi_s + (h / Ji) * tc
        ww_s = ww + (h / Jv) * (ts - aero * ww * np.abs(ww))
        wcap = WCAP[:, k]
        ww = ww_s - np.clip(ww_s, -wcap * (h / Jv), wcap * (h / Jv))
        phi = phi + h * (wi / i - ww)
        out[:, 0, k + 1], out[:, 1, k + 1], out[:, 2, k + 1] = we, wi, ww
    if governor is not None:
        out[:, 3, n] = out[:, 3, n - 1]
    return out
