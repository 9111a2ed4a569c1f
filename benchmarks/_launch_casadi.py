"""The default launch in CasADi SX symbols, integrated by CVODES or IDAS in a restart loop.

The CasADi baseline of ``launch_speed.py``: the peer a numerical engineer would pick for
this problem.  The numbers come from :func:`_launch_plain.launch_params` (every one read
from the loaded scenario), the states are the plain model's (:data:`STATE_NAMES`, same
order, SI units) and the equations are those of ``_launch_plain.make_rhs``, written once
more as CasADi expressions: ``make_rhs`` branches on Python floats (``if``, ``max``,
``math.tanh``, ``bisect``), which symbols cannot pass through, so it cannot be traced.
:func:`rhs_mismatch` checks the two right-hand sides against each other at random states
(the plain one is itself checked against the compiled plant by its own ``rhs_mismatch``).

Model in CasADi: tables (full-load curve, mu(theta)/mu_ref) are piecewise-linear
expressions held constant outside their range (``_pwl``), the inputs (throttle and clutch
command ramps) are expressions of the absolute time, the branches are ``if_else``,
``fmin``/``fmax`` and ``sign``.  The DAE's time ``s`` is mapped to the absolute time by
two parameters, ``t = p0 + p1·s`` with ``ode = p1·f(t, x)``, so a few integrators built
once serve every interval:

* one per input segment (between the breakpoints of the ramps), output grid ``dt_out``
  from the segment start (``p = (t_start, 1)``);
* chunk integrators of ``2**j`` output intervals (``p = (t_grid_point, 1)``) that resume a
  segment at a grid point after an event;
* a hop ``s ∈ [0, 1]`` with ``p = (t_a, h)``: from any time ``t_a`` to ``t_a + h``.

Restart loop (CasADi's own event support is experimental, so it is not used): integrate a
span over its output grid; scan the outputs for a sign change of the clutch slip event
function or for the engine speed falling below the stall speed; locate the first crossing
in its grid interval (one integrator call with :data:`SCAN_POINTS` sub-outputs, then the
Illinois method, a regula falsi, on hops from the start of the piece with the sign change)
to ``EVENT_TOL_S``; apply model (6)'s reset of ``phi`` (``_launch_plain._reset``, the same
policy and hysteresis as the scipy baseline); restart there (hop to the next grid point,
then chunks to the end of the segment).  A reset that leaves ``phi`` as it is (the clamp
policy with ``|phi| <= c·phi0``: every crossing of the locked clutch's small oscillation)
changes nothing, so the trajectory already integrated is kept and the scan goes on; only
a reset that changes the state restarts the integrator.  A stall ends the run.

Limits of grid-based detection: two crossings inside one 2 ms output interval show no sign
change on the grid and are not seen; at such a pair of the locked clutch ``|phi|`` stays
inside the clamp, so the skipped resets would not have changed the state.  The number of
crossings is the integrator's: the locked clutch's slip rings, and with SUNDIALS' default
BDF orders up to 5 (not A-stable) the ringing at rtol 1e-6 lasts to the end (CVODES: ~900
grid sign changes in 4 s; ~55 with ``max_order=2``; clutchsim finds ~80 crossings).

Timing: :func:`build` (symbols and integrators, a few ms per integrator) is set-up, done
once; :func:`simulate_casadi` is what ``launch_speed.py`` times.
"""

from __future__ import annotations

import itertools
import math
import time
from dataclasses import dataclass

import casadi as ca
import numpy as np
from _launch_plain import STATE_NAMES, LaunchParams, PlainRun, _reset, make_rhs

__all__ = ["EVENT_TOL_S", "SOLVERS", "CasadiLaunch", "build", "rhs_mismatch",
           "simulate_casadi"]

#: integrators of the baseline (CasADi plugin names)
SOLVERS = ("cvodes", "idas")
#: width of the bracket at which an event is located [s]
EVENT_TOL_S = 1e-10
#: pieces of the first cut of a grid interval with a crossing (one integrator call)
SCAN_POINTS = 32


def _pwl(xs: tuple, ys: tuple, x):
    """Linear interpolation in ``(xs, ys)`` as an expression, held constant outside.

    ``ys[0] + sum_i slope_i · (clamp(x, xs[i], xs[i+1]) - xs[i])``: the same values as
    ``_launch_plain._table`` (to rounding), continuous, with the slopes of the segments.
    """
    out = ys[0]
    for i in range(len(xs) - 1):
        x0, x1 = xs[i], xs[i + 1]
        if x1 > x0:
            out = out + (ys[i + 1] - ys[i]) / (x1 - x0) * (ca.fmin(ca.fmax(x, x0), x1) - x0)
    return out


def _signal(sig: tuple, t):
    """A plain ``(constant, ramps)`` signal as an expression of the time ``t`` [s]."""
    const, ramps = sig
    val = const
    for start, duration, height, offset in ramps:
        if duration > 0.0:
            frac = ca.fmin(ca.fmax((t - start) / duration, 0.0), 1.0)
        else:
            frac = ca.if_else(t >= start, 1.0, 0.0)
        val = val + offset + height * frac
    return val


def _model(par: LaunchParams, t, y):
    """Derivatives of the 10 states and the clutch ``(slip, capacity)`` as expressions.

    The equations of ``_launch_plain.make_rhs``, term by term.
    """
    w_e, w_d, w_g, w_w, ph_d, ph_s, phi, th_p, th_f, gi = (y[k] for k in range(10))
    i_gb, r_c, r_dmp, r_sh = par.i_gb, par.r_c, par.r_dmp, par.r_sh
    J_cl = par.J_g + par.J_f / i_gb ** 2            # gearbox cluster, at the input side
    throttle = _signal(par.throttle, t)
    # engine: full load × (throttle + idle governor) - drag
    gov, dgi = 0.0, 0.0
    if par.idle > 0.0:
        t_aw = max(par.ki, 1e-12) * 0.1               # anti-windup: ki × 0.1 s
        err = par.idle - w_e
        raw = par.kp * err + par.ki * gi
        gov = ca.fmin(ca.fmax(raw, 0.0), ca.fmax(1.0 - throttle, 0.0))
        dgi = err + (gov - raw) / t_aw
    x = ca.fmin(ca.fmax(throttle + gov, 0.0), 1.0)
    T_eng = (x * ca.fmax(_pwl(par.eng_speed, par.eng_torque, w_e), 0.0)
             - (par.drag0 * ca.tanh(w_e) + par.drag1 * w_e))
    # clutch, model (6): capacity = COM · mu(theta)/mu_ref at the pressure plate
    w_c = w_d - w_e / r_c
    com = _signal(par.command, t)
    scale = ca.if_else(com > 0.0,
                       ca.fmax(com * _pwl(par.mu_theta, par.mu_factor, th_p), 0.0), 0.0)
    dT = par.T_stat - par.k_din * par.T_stat
    drop = dT * (1.0 - ca.exp(-ca.fabs(w_c / par.omega0) ** par.p_exp))
    T_c = scale * (par.T_stat * ca.tanh(phi / par.phi0) + par.k_v * w_c - ca.sign(w_c) * drop)
    # damper, two-stage spring
    w_dmp = w_g - w_d / r_dmp
    c, knee, c2 = par.c_dmp, par.knee_dmp, par.c2_dmp
    if knee <= 0.0:
        T_spring = c * ph_d
    else:
        T_spring = ca.if_else(ca.fabs(ph_d) <= knee, c * ph_d,
                              ca.sign(ph_d) * (c * knee + c2 * (ca.fabs(ph_d) - knee)))
    T_dmp = T_spring + par.d_dmp * w_dmp
    # driveshaft from the final drive (speed w_g / i) to the wheels
    w_f = w_g / i_gb
    w_sh = w_w - w_f / r_sh
    T_sh = par.c_sh * ph_s + par.d_sh * w_sh
    # road load
    mg = par.mass * par.gravity
    v = w_w * par.r_tyre
    F_road = (par.f_roll * mg * math.cos(par.grade_angle) * ca.tanh(v / par.v_eps)
              + par.c_aero * v * ca.fabs(v) + mg * math.sin(par.grade_angle))
    # torques on the nodes; a coupling torque T acts +T/r upstream and -T downstream
    a_e = (T_eng - par.b_e * w_e + T_c / r_c) / par.J_e
    a_d = (-T_c - par.b_d * w_d + T_dmp / r_dmp) / par.J_d
    a_g = ((-T_dmp - par.b_g * w_g) + (T_sh / r_sh - par.b_f * w_f) / i_gb) / J_cl
    a_w = (-T_sh - par.b_w * w_w - F_road * par.r_tyre) / par.J_w
    # heat from the clutch into the pressure plate and the flywheel
    q = ca.fabs(T_c * w_c)
    (sh_p, sh_f), (C_p, C_f) = par.heat_share, par.th_C
    (hA_p, hA_f), (amb_p, amb_f) = par.th_hA, par.th_amb
    dth_p = (sh_p * q - hA_p * (th_p - amb_p)) / C_p
    dth_f = (sh_f * q - hA_f * (th_f - amb_f)) / C_f
    f = ca.vertcat(a_e, a_d, a_g, a_w, w_dmp, w_sh, w_c, dth_p, dth_f, dgi)
    return f, w_c, scale * par.T_stat


@dataclass
class CasadiLaunch:
    """The CasADi model of one launch and its integrators, built once by :func:`build`.

    Attributes
    ----------
    par : LaunchParams
    solver : str
        ``"cvodes"`` or ``"idas"``.
    max_order : int or None
        Largest BDF order (None: SUNDIALS' default).
    rtol, atol, dt_out : float
        Tolerances [-], [state units] and output interval [s].
    rhs : casadi.Function
        ``(t, y) -> dy/dt`` (for :func:`rhs_mismatch`).
    clutch : casadi.Function
        ``(t, y) -> (slip [rad/s], capacity [N·m])`` (called on a row of times and a
        matrix of states, it is evaluated column by column).
    segments : list of (float, float, casadi.Function, ndarray)
        ``(start, end, integrator, output times)`` per input segment.
    chunks : list of casadi.Function
        ``chunks[j]``: ``2**j`` output intervals from a grid point.
    hop : casadi.Function
        One interval ``[t_a, t_a + h]`` (``p = (t_a, h)``).
    scan : casadi.Function
        The same interval with :data:`SCAN_POINTS` equal outputs (event location).
    build_s : float
        Wall time of :func:`build` [s].
    """

    par: LaunchParams
    solver: str
    max_order: int | None
    rtol: float
    atol: float
    dt_out: float
    rhs: ca.Function
    clutch: ca.Function
    segments: list
    chunks: list
    hop: ca.Function
    scan: ca.Function
    build_s: float


def build(par: LaunchParams, solver: str = "cvodes", rtol: float = 1e-6, atol: float = 1e-8,
          dt_out: float = 0.002, max_order: int | None = None) -> CasadiLaunch:
    """The CasADi symbols of the launch and the integrators of the restart loop.

    Parameters
    ----------
    par : LaunchParams
        From ``_launch_plain.launch_params``.
    solver : str
        ``"cvodes"`` (BDF, Newton) or ``"idas"`` (the ODE as a DAE residual).
    rtol, atol : float
        Integrator tolerances [-], [state units].
    dt_out : float
        Output interval [s].
    max_order : int, optional
        Largest BDF order [-] (SUNDIALS' default 5 when None).  Orders above 2 are not
        A-stable: at rtol 1e-6 they keep the locked clutch ringing, whose slip then crosses
        zero between most grid points (cvodes: ~900 crossings in 4 s against ~55 at order 2).

    Returns
    -------
    CasadiLaunch
    """
    if solver not in SOLVERS:
        raise ValueError(f"solver={solver!r}: must be one of {SOLVERS}")
    wall0 = time.perf_counter()
    y = ca.SX.sym("y", len(STATE_NAMES))
    t = ca.SX.sym("t")
    f, slip, cap = _model(par, t, y)
    rhs = ca.Function("rhs", [t, y], [f])
    n_out = math.floor(par.t_end / dt_out + 1e-9)
    clutch = ca.Function("clutch", [t, y], [slip, cap])
    # time of the integrators: t = p0 + p1·s
    s = ca.SX.sym("s")
    p = ca.SX.sym("p", 2)
    dae = {"x": y, "t": s, "p": p, "ode": p[1] * ca.substitute(f, t, p[0] + p[1] * s)}
    opts = {"reltol": rtol, "abstol": atol, "max_num_steps": 1_000_000}
    if max_order is not None:
        opts["max_order"] = max_order

    def integ(name, tgrid):
        return ca.integrator(name, solver, dae, 0.0, np.asarray(tgrid, dtype=float), opts)

    grid = dt_out * np.arange(n_out + 1)
    segments = []
    bounds = (0.0, *par.breakpoints, par.t_end)
    longest = 1
    for a, b in itertools.pairwise(bounds):
        tout = np.unique(np.append(grid[(grid > a + 1e-12) & (grid < b - 1e-12)], b))
        segments.append((a, b, integ(f"seg{len(segments)}", tout - a), tout))
        longest = max(longest, tout.size)
    chunks = [integ(f"chunk{j}", dt_out * np.arange(1, 2 ** j + 1))
              for j in range(max(1, math.ceil(math.log2(longest))) + 1)]
    hop = integ("hop", [1.0])
    scan = integ("scan", np.arange(1, SCAN_POINTS + 1) / SCAN_POINTS)
    return CasadiLaunch(par=par, solver=solver, max_order=max_order, rtol=rtol, atol=atol,
                        dt_out=dt_out, rhs=rhs, clutch=clutch, segments=segments,
                        chunks=chunks, hop=hop, scan=scan, build_s=time.perf_counter() - wall0)


class _Counter:
    """Integrator calls and the rhs evaluations they report."""

    def __init__(self):
        self.calls = self.nfev = 0

    def __call__(self, fn, x0, p0, p1) -> np.ndarray:
        out = np.asarray(fn(x0=x0, p=[p0, p1])["xf"], dtype=float)
        st = fn.stats()
        self.calls += 1
        self.nfev += int(st.get("nfevals", 0))
        return out


def _locate(m: CasadiLaunch, call: _Counter, g, t_a: float, y_a: np.ndarray, t_b: float,
            y_b: np.ndarray) -> tuple[float, np.ndarray]:
    """First zero of ``g(y)`` in ``(t_a, t_b]`` (``g(y_a)`` and ``g(y_b)`` differ in sign).

    One ``scan`` call cuts the interval into ``SCAN_POINTS`` pieces and takes the first
    with a sign change; the Illinois method on hops from the start of that piece then
    narrows it to ``EVENT_TOL_S``.  Returns the bracket end past the crossing (``g`` of
    the sign of ``g(y_b)``) and its state.
    """
    H = t_b - t_a
    ys = call(m.scan, y_a, t_a, H)
    gs = g(ys)                                       # g works on columns of states
    pos = g(y_b) > 0.0
    past = np.flatnonzero((gs == 0.0) | ((gs > 0.0) == pos))
    if past.size:
        i = int(past[0])
        g_hi, y_hi = gs[i], ys[:, i]
    else:                       # the scan ends short of the crossing the grid run passed
        i = SCAN_POINTS - 1
        g_hi, y_hi = g(y_b), y_b
    if i == 0:
        t_0, y_0, g_lo = t_a, y_a, g(y_a)
    else:
        t_0, y_0, g_lo = t_a + H * i / SCAN_POINTS, ys[:, i - 1], gs[i - 1]
    lo, hi = 0.0, t_a + H * (i + 1) / SCAN_POINTS - t_0
    side = 0
    while hi - lo > EVENT_TOL_S and g_hi != 0.0:
        h = hi - g_hi * (hi - lo) / (g_hi - g_lo)
        if not lo < h < hi:
            h = 0.5 * (lo + hi)
        y_h = call(m.hop, y_0, t_0, h)[:, 0]
        g_h = g(y_h)
        if g_h == 0.0 or (g_h > 0.0) == pos:
            hi, g_hi, y_hi = h, g_h, y_h
            if side == 1:
                g_lo *= 0.5
            side = 1
        else:
            lo, g_lo = h, g_h
            if side == -1:
                g_hi *= 0.5
            side = -1
    return t_0 + hi, y_hi


def _on_grid(t: float, dt: float) -> int | None:
    """Index of the grid point ``t`` [s] lies on (within 1e-12 s), else None."""
    k = round(t / dt)
    return k if abs(t - k * dt) <= 1e-12 else None


def _span(m: CasadiLaunch, call: _Counter, t: float, y: np.ndarray, seg: int):
    """Outputs after ``t`` to the end of segment ``seg``: times and states (10 × n)."""
    a, b, integ, tout = m.segments[seg]
    if abs(t - a) <= 1e-12:
        return tout, call(integ, y, a, 1.0)
    dt = m.dt_out
    k = _on_grid(t, dt)
    ts, ys = [], []
    if k is None:                                    # hop to the next grid point
        k = math.floor(t / dt) + 1
        t_cur = min(k * dt, b)
        ts.append(np.array([t_cur]))
        ys.append(call(m.hop, y, t, t_cur - t))
        y = ys[-1][:, -1]
    t_cur = k * dt
    n = max(math.floor(b / dt + 1e-9) - k, 0)        # grid intervals left in the segment
    j = len(m.chunks) - 1
    while n > 0:                                     # binary chunks of grid intervals
        while 2 ** j > n:
            j -= 1
        ys.append(call(m.chunks[j], y, t_cur, 1.0))
        ts.append(t_cur + dt * np.arange(1, 2 ** j + 1))
        t_cur, n, y = ts[-1][-1], n - 2 ** j, ys[-1][:, -1]
    if b - t_cur > 1e-12:                            # a breakpoint off the grid
        ys.append(call(m.hop, y, t_cur, b - t_cur))
        ts.append(np.array([b]))
    return np.concatenate(ts), np.hstack(ys)


def simulate_casadi(m: CasadiLaunch, hysteresis: float = 1e-9) -> PlainRun:
    """Run the launch with the integrators of ``m``: scan, locate, reset, restart.

    Parameters
    ----------
    m : CasadiLaunch
        From :func:`build`.
    hysteresis : float
        Slip past zero at which a crossing counts [rad/s] (as in
        ``_launch_plain.simulate_plain``: on the side ``s = ±1`` the event function is
        ``slip + s·hysteresis``).

    Returns
    -------
    PlainRun
        On the output grid; ``segments`` counts the integrator calls, ``nfev`` the rhs
        evaluations the integrators report; ``status`` is ``"completed"``, ``"stalled"``
        or ``"failed: <message>"``.
    """
    wall0 = time.perf_counter()
    par, dt = m.par, m.dt_out
    r_c, stall = par.r_c, par.stall
    call = _Counter()
    y = np.array(par.y0, dtype=float)
    side = 1.0 if y[1] - y[0] / r_c >= 0.0 else -1.0

    def g_slip(yy):
        return yy[1] - yy[0] / r_c + side * hysteresis

    def g_stall(yy):
        return yy[0] - stall

    ts, ys = [np.array([0.0])], [y[:, None]]
    events: list[float] = []
    status = "completed"
    t, seg = 0.0, 0
    try:
        while seg < len(m.segments) and status == "completed":
            tout, yout = _span(m, call, t, y, seg)
            t_prev, y_prev, restart = t, y, False
            for i in range(tout.size):
                y_i = yout[:, i]
                crossed, stalled = side * g_slip(y_i) < 0.0, g_stall(y_i) < 0.0
                if not (crossed or stalled):
                    t_prev, y_prev = tout[i], y_i
                    continue
                if crossed:
                    t_ev, y_ev = _locate(m, call, g_slip, t_prev, y_prev, tout[i], y_i)
                if stalled and (not crossed or _locate(m, call, g_stall, t_prev, y_prev,
                                                       tout[i], y_i)[0] <= t_ev):
                    status = "stalled"
                else:
                    events.append(t_ev)
                    side = -side
                    phi = _reset(par.reset, par.reset_c, par.phi0, float(y_ev[6]))
                    if phi == y_ev[6]:               # nothing changes: keep the trajectory
                        t_prev, y_prev = tout[i], y_i
                        continue
                    y = y_ev.copy()
                    y[6] = phi
                    t, restart = t_ev, True
                ts.append(tout[:i])
                ys.append(yout[:, :i])
                if restart and (k := _on_grid(t, dt)) is not None:
                    ts.append(np.array([k * dt]))     # an event on a grid point
                    ys.append(y[:, None])
                break
            else:
                ts.append(tout)
                ys.append(yout)
                t, y = tout[-1], yout[:, -1].copy()
                seg += 1
            if restart and t >= m.segments[seg][1] - 1e-12:
                seg += 1
    except RuntimeError as exc:                      # CasADi reports a failed integration
        status = f"failed: {str(exc).strip().splitlines()[-1]}"
    t_all, y_all = np.concatenate(ts), np.hstack(ys)
    k = np.rint(t_all / dt)
    on = np.abs(t_all - k * dt) <= 1e-9 * max(1.0, par.t_end)
    _, first = np.unique(k[on], return_index=True)
    sel = np.flatnonzero(on)[first]
    t_out, y_out = t_all[sel], y_all[:, sel]
    slip = np.asarray(y_out[1] - y_out[0] / r_c)
    cap = np.asarray(m.clutch(t_out[None, :], y_out)[1], dtype=float).ravel()
    return PlainRun(t=t_out, y=y_out, slip=slip, capacity=cap, events=events, status=status,
                    nfev=call.nfev, segments=call.calls, wall_s=time.perf_counter() - wall0)


#: ranges of the random states of :func:`rhs_mismatch` (order of :data:`STATE_NAMES`)
_DRAW_LO = (40.0, -50.0, -50.0, -5.0, -0.15, -0.05, -2.0, 20.0, 20.0, -50.0)
_DRAW_HI = (400.0, 400.0, 400.0, 30.0, 0.15, 0.05, 2.0, 350.0, 350.0, 50.0)


def rhs_mismatch(par: LaunchParams, n_states: int = 200, seed: int = 1) -> float:
    """Largest relative difference of the CasADi and the plain-Python right-hand sides.

    Random states and times over the ranges of ``_launch_plain.rhs_mismatch`` (half of
    the clutch slip angles inside the elastic range ``|phi| <= 3 phi0``), all evaluated by
    the CasADi function in one call.

    Returns
    -------
    float
        ``max |f_casadi - f_plain| / max(|f_plain|, 1)`` over states and draws [-].
    """
    y = ca.SX.sym("y", len(STATE_NAMES))
    t = ca.SX.sym("t")
    fn = ca.Function("rhs", [t, y], [_model(par, t, y)[0]])
    plain, _ = make_rhs(par)
    rng = np.random.default_rng(seed)
    ts = rng.uniform(0.0, par.t_end, n_states)
    ys = rng.uniform(_DRAW_LO, _DRAW_HI, (n_states, len(STATE_NAMES))).T
    elastic = rng.random(n_states) < 0.5
    ys[6, elastic] *= 3.0 * par.phi0 / _DRAW_HI[6]
    mine = np.asarray(fn(ts[None, :], ys), dtype=float)
    ref = np.array([plain(tt, ys[:, k]) for k, tt in enumerate(ts)]).T
    return float(np.max(np.abs(mine - ref) / np.maximum(np.abs(ref), 1.0)))
