"""The default launch written out by hand in plain Python, for the scipy baselines.

This is the model a user without clutchsim would write for ``solve_ivp``: one function
``rhs(t, y)`` in plain Python (``math`` only, no numba, no call into clutchsim's compiled
code), a terminal scipy event for the zero crossings of the clutch slip, the reset of
model (6) applied between two ``solve_ivp`` calls, and a restart.  It mirrors the
equations of the generated network plant (``clutchsim.network``) for the topology of
``examples/launch.toml``::

    engine --clutch-- disc --damper-- gearbox_input ==gearbox== final_drive --shaft-- wheels

Every number is read once, at set-up, from the loaded scenario (its :class:`Network`
components, the friction model and the input signals); the right-hand side then works on
Python floats only.  :func:`check` compares the result with ``run_scenario``.

States (10, SI units)::

    0 omega_engine [rad/s]     5 phi_shaft [rad]        (driveshaft twist)
    1 omega_disc [rad/s]       6 phi_clutch [rad]       (integrated slip, model (6))
    2 omega_gearbox_input      7 theta_pressure_plate [°C]
    3 omega_wheels [rad/s]     8 theta_flywheel [°C]
    4 phi_damper [rad]         9 governor integral [rad]

The gearbox is rigid, so ``gearbox_input`` and ``final_drive`` share one speed state
(``omega_final_drive = omega_gearbox_input / i``, ``i`` = gear ratio × final drive; on the
network plant the final drive's speed is an output, not a state).
clutchsim's plant also integrates the energy account; a user's model would not, so it is
left out here.
"""

from __future__ import annotations

import bisect
import math
import time
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

__all__ = ["LOCKUP_TOL_S", "SPEEDS", "SPEED_TOL_RPM", "STATE_NAMES", "LaunchParams",
           "PlainRun", "check", "grid_rows", "launch_params", "lockup_time", "make_rhs",
           "rhs_mismatch", "signal_value", "simulate_plain", "speed_diff_rpm"]

STATE_NAMES = ("omega_engine", "omega_disc", "omega_gearbox_input", "omega_wheels",
               "phi_damper", "phi_shaft", "phi_clutch", "theta_pressure_plate",
               "theta_flywheel", "governor_integral")


@dataclass(frozen=True)
class LaunchParams:
    """Every number of the default launch, as plain Python floats and tuples (SI units).

    Attributes
    ----------
    J_e, J_d, J_g, J_f, J_w : float
        Inertias of engine, disc, gearbox input, final drive and wheels [kg·m²];
        ``J_w`` includes the vehicle's ``m·r²``.
    b_e, b_d, b_g, b_f, b_w : float
        Bearing damping of the five nodes [N·m·s/rad].
    r_c, r_dmp, r_sh : float
        Input-side ratios of clutch, damper and driveshaft [-] (1 in the default launch).
    i_gb : float
        Gear ratio × final drive [-].
    T_stat, k_din, phi0, omega0, k_v, p_exp : float
        Model (6) parameters [N·m, -, rad, rad/s, N·m·s/rad, -].
    reset, reset_c : str, float
        Reset policy of the integrator at a slip zero crossing and its clamp factor [-].
    mu_theta, mu_factor : tuple of float
        mu(theta)/mu_ref table of the clutch, read at the first heat node [°C, -].
    heat_share : tuple of float
        Share of the friction power going to (pressure plate, flywheel) [-].
    c_dmp, d_dmp, knee_dmp, c2_dmp : float
        Two-stage damper [N·m/rad, N·m·s/rad, rad, N·m/rad].
    c_sh, d_sh : float
        Driveshaft stiffness and damping [N·m/rad, N·m·s/rad].
    eng_speed, eng_torque : tuple of float
        Full-load curve [rad/s, N·m].
    drag0, drag1 : float
        Engine friction [N·m] and pumping loss [N·m·s/rad].
    idle, kp, ki, stall : float
        Idle governor target [rad/s], gains [1/(rad/s)], [1/rad]; stall speed [rad/s].
    mass, r_tyre, grade_angle, f_roll, c_aero, gravity, v_eps : float
        Vehicle [kg, m, rad, -, kg/m (½·rho·c_d·A), m/s², m/s].
    th_C, th_hA, th_amb : tuple of float
        Thermal nodes (pressure plate, flywheel): capacity [J/K], conductance [W/K],
        ambient [°C].
    throttle, command : tuple
        Input signals as ``(constant, ((start, duration, height, offset), ...))`` ramps
        [s, -].
    y0 : tuple of float
        Initial state (order of :data:`STATE_NAMES`).
    t_end : float
        End time [s].
    breakpoints : tuple of float
        Slope changes of the inputs inside ``(0, t_end)`` [s]; the integration stops there.
    """

    J_e: float
    J_d: float
    J_g: float
    J_f: float
    J_w: float
    b_e: float
    b_d: float
    b_g: float
    b_f: float
    b_w: float
    r_c: float
    r_dmp: float
    r_sh: float
    i_gb: float
    T_stat: float
    k_din: float
    phi0: float
    omega0: float
    k_v: float
    p_exp: float
    reset: str
    reset_c: float
    mu_theta: tuple
    mu_factor: tuple
    heat_share: tuple
    c_dmp: float
    d_dmp: float
    knee_dmp: float
    c2_dmp: float
    c_sh: float
    d_sh: float
    eng_speed: tuple
    eng_torque: tuple
    drag0: float
    drag1: float
    idle: float
    kp: float
    ki: float
    stall: float
    mass: float
    r_tyre: float
    grade_angle: float
    f_roll: float
    c_aero: float
    gravity: float
    v_eps: float
    th_C: tuple
    th_hA: tuple
    th_amb: tuple
    throttle: tuple
    command: tuple
    y0: tuple
    t_end: float
    breakpoints: tuple


# ------------------------------------------------------------------ set-up (reads clutchsim)
def _plain_signal(sig, name: str) -> tuple:
    """``(constant, ramps)`` of a clutchsim signal made of constants and ramps."""
    from clutchsim.core.signals import Constant, Ramp
    const, ramps = 0.0, []
    for term in sig.terms():
        if isinstance(term, Constant):
            const += float(term.value)
        elif isinstance(term, Ramp):
            ramps.append((float(term.start), float(term.duration), float(term.height),
                          float(term.offset)))
        else:
            raise NotImplementedError(f"input {name!r}: the plain-Python model knows constants "
                                      f"and ramps, not {type(term).__name__}")
    return const, tuple(ramps)


def _floats(xs) -> tuple:
    return tuple(float(x) for x in xs)


def signal_value(sig: tuple, t: float) -> float:
    """Value of a plain ``(constant, ramps)`` signal at ``t`` [s] (plain Python)."""
    const, ramps = sig
    val = const
    for start, duration, height, offset in ramps:
        if t < start:
            val += offset
        elif t >= start + duration:
            val += offset + height
        else:
            val += offset + height * (t - start) / duration
    return val


def launch_params(scenario, model: str = "mykhailevych2020") -> LaunchParams:
    """Read the numbers of ``scenario`` (the default launch topology) into plain floats.

    Parameters
    ----------
    scenario : clutchsim.scenario.Scenario
        The loaded default launch (or a variant with the same components).
    model : str
        Friction model on the clutch; only ``"mykhailevych2020"`` is written out.

    Returns
    -------
    LaunchParams

    Raises
    ------
    ValueError
        The scenario's driveline is not the five-inertia launch chain this model mirrors.
    """
    from clutchsim.network import components as nc
    net = scenario.network(model)
    comps = net.components
    inert, cpl = comps[:5], comps[5:9]
    want = ((nc.Inertia,) * 5 + (nc.Clutch, nc.SpringDamper, nc.Gearbox, nc.SpringDamper,
                                 nc.Engine, nc.Vehicle, nc.ThermalNode, nc.ThermalNode))
    kinds = tuple(type(c) for c in comps)
    # the chain's series: coupling k between inertia k and k+1 (no coupling ratios, no
    # loads, no brakes), the engine on the first inertia, the vehicle on the last
    series = tuple(pair for k, c in enumerate(cpl)
                   for pair in ((f"{inert[k].name}.b", f"{c.name}.a"),
                                (f"{c.name}.b", f"{inert[k + 1].name}.a"))) \
        if len(inert) == 5 else ()
    if kinds != want or net.connections != series + (
            (f"{comps[9].name}.flange", f"{inert[0].name}.a"),
            (f"{comps[10].name}.flange", f"{inert[4].name}.a")):
        raise ValueError("plain launch model: expects inertias engine, disc, gearbox input, "
                         "final drive, wheels joined by clutch, spring-damper, gearbox, "
                         f"spring-damper, with engine, vehicle and 2 thermal nodes; got "
                         f"{[type(c).__name__ for c in comps]}")
    thermal = comps[11:13]
    clutch, damper, gearbox, shaft = cpl
    fm = clutch.model
    if fm.name != "mykhailevych2020":
        raise ValueError(f"plain launch model: clutch model {fm.name!r} is not written out")
    if clutch.clamp_table is not None or clutch.mu_slip is not None or clutch.drag != 0.0:
        raise ValueError("plain launch model: clamp_table, mu_slip and clutch drag are not "
                         "written out")
    if gearbox.shifts or clutch.locked0 or shaft.knee > 0:
        raise ValueError("plain launch model: gear shifts, a locked start and a two-stage "
                         "driveshaft are not written out")
    th_names = [t.name for t in thermal]
    heat = dict(clutch.heat)
    if not clutch.heat or clutch.heat[0][0] != th_names[0] or set(heat) - set(th_names):
        raise ValueError("plain launch model: the clutch heat must go first to thermal node "
                         f"{th_names[0]!r} (its mu(theta) node)")
    mu_theta, mu_factor = clutch.mu_temperature if clutch.mu_temperature else ((0.0,), (1.0,))
    eng, veh = comps[9], comps[10]
    z0 = fm.initial_state() if clutch.z0 is None else np.asarray(clutch.z0, dtype=float)
    phi_damp0 = damper.phi0
    i_gb = gearbox.ratios[int(gearbox.gear) - 1] * gearbox.final_drive
    w0 = [i.omega0 for i in inert]
    if not math.isclose(w0[3], w0[2] / i_gb, rel_tol=1e-12, abs_tol=1e-12):
        raise ValueError("plain launch model: initial speeds violate the gearbox ratio")
    gov = eng.idle_speed > 0
    y0 = (w0[0], w0[1], w0[2], w0[4], phi_damp0, shaft.phi0, float(z0[0]),
          thermal[0].theta0, thermal[1].theta0, 0.0)
    sigs = scenario.inputs
    throttle = _plain_signal(sigs[eng.throttle], eng.throttle)
    command = _plain_signal(sigs[clutch.command], clutch.command)
    t_end = float(scenario.t_end)
    bps = set()
    for s in (throttle, command):
        for start, duration, _, _ in s[1]:
            bps.update((start, start + duration))
    # the hand-written inputs must agree with clutchsim's own evaluation of the signals
    grid = np.linspace(0.0, t_end, 4001)
    for s, name in ((throttle, eng.throttle), (command, clutch.command)):
        mine = np.array([signal_value(s, t) for t in grid])
        ref = np.asarray(sigs[name](grid), dtype=float)
        if not np.allclose(mine, ref, rtol=0.0, atol=1e-14):
            raise AssertionError(f"plain launch model: input {name!r} differs from clutchsim "
                                 f"by {np.max(np.abs(mine - ref)):.3g}")
    return LaunchParams(
        J_e=inert[0].J, J_d=inert[1].J, J_g=inert[2].J, J_f=inert[3].J,
        J_w=inert[4].J + veh.mass * veh.tyre_radius ** 2,
        b_e=inert[0].bearing_damping, b_d=inert[1].bearing_damping,
        b_g=inert[2].bearing_damping, b_f=inert[3].bearing_damping,
        b_w=inert[4].bearing_damping,
        r_c=1.0, r_dmp=1.0, r_sh=1.0, i_gb=i_gb,
        T_stat=fm.T_stat, k_din=fm.k_din, phi0=fm.phi0, omega0=fm.omega0, k_v=fm.k_v,
        p_exp=float(fm.p), reset=fm.reset, reset_c=fm.reset_c,
        mu_theta=_floats(mu_theta), mu_factor=_floats(mu_factor),
        heat_share=(heat.get(th_names[0], 0.0), heat.get(th_names[1], 0.0)),
        c_dmp=damper.c, d_dmp=damper.d, knee_dmp=damper.knee, c2_dmp=damper.c2,
        c_sh=shaft.c, d_sh=shaft.d,
        eng_speed=_floats(eng.speeds), eng_torque=_floats(eng.torques),
        drag0=eng.drag0, drag1=eng.drag1, idle=eng.idle_speed if gov else 0.0,
        kp=eng.kp if gov else 0.0, ki=eng.ki if gov else 0.0, stall=eng.stall_speed,
        mass=veh.mass, r_tyre=veh.tyre_radius, grade_angle=math.atan(veh.grade / 100.0),
        f_roll=veh.rolling, c_aero=0.5 * veh.air_density * veh.cd_area, gravity=veh.gravity,
        v_eps=veh.v_eps,
        th_C=tuple(t.capacity for t in thermal),
        th_hA=tuple(t.conductance for t in thermal),
        th_amb=tuple(t.ambient for t in thermal),
        throttle=throttle, command=command, y0=y0, t_end=t_end,
        breakpoints=tuple(sorted(b for b in bps if 0.0 < b < t_end)),
    )


# ------------------------------------------------------------------ the plain-Python model
def _table(xs: tuple, ys: tuple, x: float) -> float:
    """Linear interpolation in ``(xs, ys)``, held constant outside (plain Python)."""
    if x <= xs[0]:
        return ys[0]
    if x >= xs[-1]:
        return ys[-1]
    i = bisect.bisect_right(xs, x)
    x0, x1 = xs[i - 1], xs[i]
    return ys[i - 1] + (ys[i] - ys[i - 1]) * (x - x0) / (x1 - x0)


def make_rhs(par: LaunchParams):
    """The right-hand side ``rhs(t, y) -> list`` and a ``clutch(t, y)`` helper.

    Parameters
    ----------
    par : LaunchParams

    Returns
    -------
    rhs : callable
        ``rhs(t, y)`` with ``t`` [s] and ``y`` the 10 states of :data:`STATE_NAMES`;
        returns their derivatives (SI units per second) as a list of floats.
    clutch : callable
        ``clutch(t, y) -> (slip [rad/s], capacity [N·m], torque [N·m])`` of the clutch.
    """
    # numbers as local names of the closures (a user's model would have them as constants)
    J_e, J_d, J_w = par.J_e, par.J_d, par.J_w
    i_gb = par.i_gb
    J_cl = par.J_g + par.J_f / i_gb ** 2            # gearbox cluster, at the input side
    b_e, b_d, b_g, b_f, b_w = par.b_e, par.b_d, par.b_g, par.b_f, par.b_w
    r_c, r_dmp, r_sh = par.r_c, par.r_dmp, par.r_sh
    T_stat, phi0, omega0, k_v, p_exp = par.T_stat, par.phi0, par.omega0, par.k_v, par.p_exp
    dT = T_stat - par.k_din * T_stat
    mu_th, mu_f = par.mu_theta, par.mu_factor
    sh_p, sh_f = par.heat_share
    c_dmp, d_dmp, knee, c2 = par.c_dmp, par.d_dmp, par.knee_dmp, par.c2_dmp
    c_sh, d_sh = par.c_sh, par.d_sh
    e_w, e_T = par.eng_speed, par.eng_torque
    drag0, drag1 = par.drag0, par.drag1
    idle, kp, ki = par.idle, par.kp, par.ki
    governor = idle > 0.0
    t_aw = max(ki, 1e-12) * 0.1                   # anti-windup: ki × 0.1 s
    r_t = par.r_tyre
    mg = par.mass * par.gravity
    roll = par.f_roll * mg * math.cos(par.grade_angle)
    f_grade = mg * math.sin(par.grade_angle)
    c_aero, v_eps = par.c_aero, par.v_eps
    (C_p, C_f), (hA_p, hA_f), (amb_p, amb_f) = par.th_C, par.th_hA, par.th_amb
    throttle_sig, command_sig = par.throttle, par.command

    def clutch_torque(t, w, phi, theta):
        """Capacity scale [-] and torque [N·m] of the clutch, model (6)."""
        com = signal_value(command_sig, t)        # COM(t); capacity = COM · mu(theta)/mu_ref
        scale = max(com * _table(mu_th, mu_f, theta), 0.0) if com > 0.0 else 0.0
        sgn = 1.0 if w > 0.0 else (-1.0 if w < 0.0 else 0.0)
        drop = dT * (1.0 - math.exp(-abs(w / omega0) ** p_exp))
        return scale, scale * (T_stat * math.tanh(phi / phi0) + k_v * w - sgn * drop)

    def clutch(t, y):
        w = y[1] - y[0] / r_c
        scale, T = clutch_torque(t, w, y[6], y[7])
        return w, scale * T_stat, T

    def rhs(t, y):
        w_e, w_d, w_g, w_w, ph_d, ph_s, phi, th_p, th_f, gi = y.tolist()
        throttle = signal_value(throttle_sig, t)
        # engine: full load × (throttle + idle governor) - drag
        gov, dgi = 0.0, 0.0
        if governor:
            err = idle - w_e
            raw = kp * err + ki * gi
            room = max(1.0 - throttle, 0.0)
            gov = min(max(raw, 0.0), room)
            dgi = err + (gov - raw) / t_aw
        x = min(max(throttle + gov, 0.0), 1.0)
        T_eng = (x * max(_table(e_w, e_T, w_e), 0.0)
                 - (drag0 * math.tanh(w_e) + drag1 * w_e))
        # clutch, model (6)
        w_c = w_d - w_e / r_c
        T_c = clutch_torque(t, w_c, phi, th_p)[1]
        # damper, two-stage spring
        w_dmp = w_g - w_d / r_dmp
        if knee <= 0.0 or abs(ph_d) <= knee:
            T_spring = c_dmp * ph_d
        elif ph_d > 0.0:
            T_spring = c_dmp * knee + c2 * (ph_d - knee)
        else:
            T_spring = -(c_dmp * knee + c2 * (-ph_d - knee))
        T_dmp = T_spring + d_dmp * w_dmp
        # driveshaft from the final drive (speed w_g / i) to the wheels
        w_f = w_g / i_gb
        w_sh = w_w - w_f / r_sh
        T_sh = c_sh * ph_s + d_sh * w_sh
        # road load
        v = w_w * r_t
        F_road = roll * math.tanh(v / v_eps) + c_aero * v * abs(v) + f_grade
        # torques on the nodes; a coupling torque T acts +T/r upstream and -T downstream
        a_e = (T_eng - b_e * w_e + T_c / r_c) / J_e
        a_d = (-T_c - b_d * w_d + T_dmp / r_dmp) / J_d
        T_g = -T_dmp - b_g * w_g
        T_f = T_sh / r_sh - b_f * w_f
        a_g = (T_g + T_f / i_gb) / J_cl
        a_w = (-T_sh - b_w * w_w - F_road * r_t) / J_w
        # heat from the clutch into the pressure plate and the flywheel
        q = abs(T_c * w_c)
        dth_p = (sh_p * q - hA_p * (th_p - amb_p)) / C_p
        dth_f = (sh_f * q - hA_f * (th_f - amb_f)) / C_f
        return [a_e, a_d, a_g, a_w, w_dmp, w_sh, w_c, dth_p, dth_f, dgi]

    return rhs, clutch


def _reset(policy: str, c: float, phi0: float, phi: float) -> float:
    """Model (6)'s re-initialisation of ``phi`` [rad] at a slip zero crossing."""
    sgn = 1.0 if phi > 0.0 else (-1.0 if phi < 0.0 else 0.0)
    if policy == "clamp":
        return sgn * min(abs(phi), c * phi0)
    if policy == "zero":
        return 0.0
    if policy == "plus_phi0":
        return sgn * phi0
    if policy == "minus_phi0":
        return -sgn * phi0
    return phi


@dataclass
class PlainRun:
    """Result of :func:`simulate_plain` on the output grid.

    Attributes
    ----------
    t : ndarray
        Output times [s] (multiples of ``dt_out``).
    y : ndarray, shape (10, len(t))
        States, see :data:`STATE_NAMES`.
    slip, capacity : ndarray
        Clutch slip ``omega_disc - omega_engine`` [rad/s] and capacity [N·m] at ``t``.
    events : list of float
        Times of the slip zero crossings [s].
    status : str
        ``"completed"``, ``"stalled"`` or ``"failed: <message>"``.
    nfev, segments : int
        Right-hand-side calls and ``solve_ivp`` calls.
    wall_s : float
        Wall time [s].
    """

    t: np.ndarray
    y: np.ndarray
    slip: np.ndarray
    capacity: np.ndarray
    events: list
    status: str
    nfev: int
    segments: int
    wall_s: float

    def __getitem__(self, name: str) -> np.ndarray:
        return self.y[STATE_NAMES.index(name)]


def simulate_plain(par: LaunchParams, method: str = "LSODA", rtol: float = 1e-6,
                   atol: float = 1e-8, dt_out: float = 0.002,
                   hysteresis: float = 1e-9) -> PlainRun:
    """Integrate the plain model with ``solve_ivp``: terminal events, reset, restart.

    The run is split at the input breakpoints.  The slip event is terminal; after it the
    integrator ``phi`` is reset by the model's policy and ``solve_ivp`` restarts from the
    event state.  The event function has a tiny hysteresis: on the side ``s = ±1`` of the
    slip ``w`` it is ``g = w + s·hysteresis``, so a crossing is found when the slip has
    passed zero by ``hysteresis``, after which the side flips and the restart begins
    ``2·hysteresis`` clear of the next root.  Without it the locked clutch, whose slip
    hovers at zero to rounding (1e-14 rad/s), makes scipy find the crossing just handled
    again, or stop with "f(a) and f(b) must have different signs" when a step starts on a
    value that is zero to rounding (LSODA's interpolant does not return exactly the step's
    initial state).  A fall of the engine speed below the stall speed ends the run.

    Parameters
    ----------
    par : LaunchParams
    method : str
        ``solve_ivp`` method (``"RK45"``, ``"LSODA"``, ``"Radau"``, ...).
    rtol, atol : float
        Tolerances [-] and [state units].
    dt_out : float
        Output interval [s].
    hysteresis : float
        Slip past zero at which a crossing counts [rad/s] (> 0; delays the event by
        ``hysteresis / |dw/dt|``: 2e-12 s at the first lock-up of the default launch,
        where ``|dw/dt|`` is about 500 rad/s²).

    Returns
    -------
    PlainRun
    """
    wall0 = time.perf_counter()
    rhs, clutch = make_rhs(par)
    t_end = par.t_end
    n_out = math.floor(t_end / dt_out + 1e-9)
    grid = dt_out * np.arange(n_out + 1)
    stall, r_c = par.stall, par.r_c

    side = [0.0]                                  # sign of the slip before the next crossing

    def slip_event(t, y):
        return y[1] - y[0] / r_c + side[0] * hysteresis

    def stall_event(t, y):
        return y[0] - stall

    slip_event.terminal = True
    stall_event.terminal = True
    stall_event.direction = -1
    y = np.array(par.y0, dtype=float)
    side[0] = 1.0 if y[1] - y[0] / r_c >= 0.0 else -1.0
    ts, ys = [0.0], [y.copy()]
    events: list[float] = []
    status = "completed"
    nfev = segments = 0
    t = 0.0
    for b in (*par.breakpoints, t_end):
        while t < b and status == "completed":
            k0 = math.floor(t / dt_out + 1e-9) + 1
            k1 = math.floor(b / dt_out + 1e-9)
            t_eval = np.unique(np.append(grid[k0:k1 + 1], b))
            sol = solve_ivp(rhs, (t, b), y, method=method, rtol=rtol, atol=atol,
                            events=(slip_event, stall_event), t_eval=t_eval)
            nfev += sol.nfev
            segments += 1
            sol_t = np.atleast_1d(np.asarray(sol.t, dtype=float))
            sol_y = np.asarray(sol.y, dtype=float).reshape(len(y), sol_t.size)
            ts.extend(sol_t.tolist())
            ys.extend(sol_y.T)
            if sol.status == -1:
                status = f"failed: {sol.message}"
            elif sol.status == 1 and sol.t_events[1].size:
                status = "stalled"
            elif sol.status == 1:
                t = float(sol.t_events[0][0])
                y = sol.y_events[0][0].copy()
                y[6] = _reset(par.reset, par.reset_c, par.phi0, float(y[6]))
                events.append(t)
                side[0] = -side[0]
            else:
                t, y = b, sol_y[:, -1].copy()
        if status != "completed":
            break
    # keep the grid points (the breakpoints are on the grid in the default launch)
    _, sel = grid_rows(np.array(ts), dt_out)
    t_out, y_out = np.array(ts)[sel], np.array(ys).T[:, sel]
    cl = [clutch(tt, yy) for tt, yy in zip(t_out, y_out.T)]
    return PlainRun(t=t_out, y=y_out, slip=np.array([c[0] for c in cl]),
                    capacity=np.array([c[1] for c in cl]), events=events, status=status,
                    nfev=int(nfev), segments=segments, wall_s=time.perf_counter() - wall0)


def lockup_time(t: np.ndarray, slip: np.ndarray, capacity: np.ndarray) -> float | None:
    """Lock-up time [s] by the definition of clutchsim's launch metrics
    (:func:`clutchsim.analysis.launch_quality.lockup_time_s` for a non-switching model:
    the slip's first zero crossing after the engaged clutch, capacity above half its
    maximum, last slipped at 1 rad/s or faster, interpolated between samples).

    Parameters
    ----------
    t : ndarray
        Times [s].
    slip, capacity : ndarray
        Clutch slip [rad/s] and capacity [N·m] at ``t``.

    Returns
    -------
    float or None
        ``None`` when the clutch is not locked at the end.
    """
    from clutchsim.analysis.launch_quality import lockup_time_s
    if np.size(slip) < 2 or np.max(capacity) <= 0:
        return None
    return lockup_time_s(t, slip, capacity > 0.5 * np.max(capacity))


# ------------------------------------------------------------------ validation
#: the speeds compared with clutchsim
SPEEDS = ("omega_engine", "omega_disc", "omega_wheels")
#: acceptance of :func:`check`: largest speed difference [rpm] and lock-up difference [s]
SPEED_TOL_RPM = 1.0
LOCKUP_TOL_S = 1e-3
_PLANT_NAME = {"phi_shaft": "phi_driveshaft", "phi_clutch": "clutch.phi",
               "governor_integral": "engine.governor_integral"}


def grid_rows(t: np.ndarray, dt_out: float) -> tuple[np.ndarray, np.ndarray]:
    """Rows of ``t`` that lie on the output grid ``k·dt_out``, one per grid point.

    clutchsim also records a row at every event; those are dropped here.

    Parameters
    ----------
    t : ndarray
        Output times [s].
    dt_out : float
        Output interval [s].

    Returns
    -------
    k : ndarray of int
        Grid indices of the kept rows.
    rows : ndarray of int
        Their row numbers in ``t`` (the first row at each grid point).
    """
    t = np.asarray(t, dtype=float)
    k = np.rint(t / dt_out)
    on = np.abs(t - k * dt_out) <= 1e-9 * max(1.0, float(np.max(np.abs(t))))
    kk, first = np.unique(k[on], return_index=True)
    return kk.astype(int), np.flatnonzero(on)[first]


def speed_diff_rpm(t_a, speeds_a: dict, t_b, speeds_b: dict, dt_out: float) -> dict:
    """Largest difference of each of :data:`SPEEDS` on the common grid points [rpm].

    Parameters
    ----------
    t_a, t_b : ndarray
        Output times of the two runs [s].
    speeds_a, speeds_b : mapping
        Speed name -> speeds [rad/s] at ``t_a`` and ``t_b``.
    dt_out : float
        Output interval [s].

    Returns
    -------
    dict
        Speed name -> max abs difference [rpm], and ``"grid_points"`` compared.
    """
    ka, ra = grid_rows(t_a, dt_out)
    kb, rb = grid_rows(t_b, dt_out)
    _, ia, ib = np.intersect1d(ka, kb, return_indices=True)
    out = {name: float(np.max(np.abs(np.asarray(speeds_a[name])[ra[ia]]
                                     - np.asarray(speeds_b[name])[rb[ib]]))) * 30 / math.pi
           for name in SPEEDS}
    out["grid_points"] = int(ia.size)
    return out


def _as_clutchsim_state(system, y: np.ndarray) -> np.ndarray:
    """The plant's state vector for a plain state ``y`` (energy states zero)."""
    names = system.state_names
    full = np.array(system.y0, dtype=float)
    for k, n in enumerate(STATE_NAMES):
        full[names.index(_PLANT_NAME.get(n, n))] = y[k]
    return full


def rhs_mismatch(scenario, n_states: int = 200, seed: int = 1) -> float:
    """Largest relative difference of the plain and the compiled right-hand sides.

    Draws ``n_states`` random states and times, maps them to the plant's state vector and
    compares the derivatives of the 10 plain states.  clutchsim's compiled ``call_rhs`` is
    called here only, never inside the plain model.

    Parameters
    ----------
    scenario : clutchsim.scenario.Scenario
    n_states : int
        Number of random states.
    seed : int
        Seed of the random draws.

    Returns
    -------
    float
        ``max |f_plain - f_plant| / max(|f_plant|, 1)`` over states and draws [-].
    """
    from clutchsim.core.signals import build_bank, eval_inputs
    from clutchsim.core.system import call_rhs
    par = launch_params(scenario)
    system = scenario.network("mykhailevych2020").build({})
    bank = build_bank([scenario.inputs[n] for n in system.input_names])
    rhs, _ = make_rhs(par)
    rng = np.random.default_rng(seed)
    idx = [system.state_names.index(_PLANT_NAME.get(n, n)) for n in STATE_NAMES]
    worst = 0.0
    for _ in range(n_states):
        t = float(rng.uniform(0.0, par.t_end))
        # slip phi inside the elastic range half of the time, saturated the other half
        phi = rng.uniform(-3e-3, 3e-3) if rng.random() < 0.5 else rng.uniform(-2.0, 2.0)
        y = np.array([rng.uniform(40, 400), rng.uniform(-50, 400), rng.uniform(-50, 400),
                      rng.uniform(-5, 30), rng.uniform(-0.15, 0.15), rng.uniform(-0.05, 0.05),
                      phi, rng.uniform(20, 350), rng.uniform(20, 350), rng.uniform(-50, 50)])
        full = _as_clutchsim_state(system, y)
        u = np.zeros(len(system.input_names))
        eval_inputs(bank, t, t, u)
        dy = np.empty_like(full)
        call_rhs(system.tag, t, full, u, system.params, dy)
        mine = np.array(rhs(t, y))
        ref = dy[idx]
        worst = max(worst, float(np.max(np.abs(mine - ref) / np.maximum(np.abs(ref), 1.0))))
    return worst


def check(method: str = "LSODA", rtol: float = 1e-8, atol: float = 1e-8,
          t_end: float | None = None, return_runs: bool = False):
    """Compare the plain model with clutchsim's ``run_scenario`` at tight tolerances.

    Both run the default launch with model (6) at ``rtol``/``atol``; the engine, disc and
    wheel speeds are compared on the common 2 ms output grid, the lock-up times by the
    launch metric's definition (:func:`lockup_time`, on the grid) and by the first slip
    zero crossing (to the event time).

    Parameters
    ----------
    method : str
        ``solve_ivp`` method for the plain model (``"LSODA"`` or ``"Radau"``).
    rtol, atol : float
        Tolerances of both runs [-], [state units].
    t_end : float, optional
        End time [s] (default: the scenario's).
    return_runs : bool
        Also return the two runs.

    Returns
    -------
    report : dict
        ``ok`` (both acceptance limits met: :data:`SPEED_TOL_RPM`, :data:`LOCKUP_TOL_S`),
        ``max_abs_speed_diff_rpm``, ``per_speed_diff_rpm``, ``lockup_time_s`` (clutchsim,
        plain), ``lockup_diff_s``, ``first_slip_zero_s`` (clutchsim, plain),
        ``first_slip_zero_diff_s``, ``slip_zero_crossings`` (clutchsim, plain),
        ``rhs_rel_mismatch`` (:func:`rhs_mismatch`), ``plain_status``, ``plain_nfev``,
        ``plain_wall_s``.
    ref, run : clutchsim Result, PlainRun
        Only with ``return_runs``.
    """
    from clutchsim.scenario import load_scenario, run_scenario
    ov = [f"solver.rtol={rtol!r}", f"solver.atol={atol!r}", "solver.wall_time=100000"]
    if t_end is not None:
        ov.append(f"scenario.t_end={t_end!r}")
    sc = load_scenario(None, overrides=ov)
    lr = run_scenario(sc, "mykhailevych2020")
    ref = lr.result
    par = launch_params(sc)
    dt = sc.options.dt_out
    run = simulate_plain(par, method, rtol, atol, dt)
    per = speed_diff_rpm(ref.t, ref, run.t, {n: run[n] for n in SPEEDS}, dt)
    n_grid = math.floor(par.t_end / dt + 1e-9) + 1
    if run.status != "completed" or per["grid_points"] != n_grid:
        raise AssertionError(f"plain run incomplete: {run.status}, {per['grid_points']} of "
                             f"{n_grid} grid points")
    _, rows = grid_rows(ref.t, dt)
    lk_ref = lockup_time(ref.t[rows], ref["w_slip_clutch"][rows], ref["capacity_clutch"][rows])
    lk_pl = lockup_time(run.t, run.slip, run.capacity)
    ev_ref = [e.t for e in ref.events if "velocity_zero_crossing" in e.name]
    d_max = max(per[n] for n in SPEEDS)
    d_lock = abs(lk_ref - lk_pl) if lk_ref is not None and lk_pl is not None else None
    report = {
        "method": method, "rtol": rtol, "atol": atol,
        "ok": bool(d_max <= SPEED_TOL_RPM and d_lock is not None and d_lock <= LOCKUP_TOL_S),
        "max_abs_speed_diff_rpm": d_max,
        "per_speed_diff_rpm": {n: per[n] for n in SPEEDS},
        "lockup_time_s": [lr.metrics["lockup_time_s"], lk_pl],
        "lockup_diff_s": d_lock,
        "first_slip_zero_s": [ev_ref[0] if ev_ref else None,
                              run.events[0] if run.events else None],
        "first_slip_zero_diff_s": (abs(ev_ref[0] - run.events[0])
                                   if ev_ref and run.events else None),
        "slip_zero_crossings": [len(ev_ref), len(run.events)],
        "rhs_rel_mismatch": rhs_mismatch(sc),
        "plain_status": run.status, "plain_nfev": run.nfev, "plain_wall_s": run.wall_s,
    }
    return (report, ref, run) if return_runs else report
