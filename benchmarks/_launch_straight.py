"""A prototype for the driveline-network issue: the default launch as one straight-line
compiled plant with an exact Jacobian, on clutchsim's own integrators.

The equations are those of ``_launch_plain.py`` (10 states: engine, disc, gearbox and wheel
speeds, damper and driveshaft twists, model (6)'s φ, two temperatures, the governor's
integral), written once as numba functions: right-hand side, exact Jacobian, the slip and
stall events, model (6)'s reset and a few outputs.  No energy accounts (the chain plant
carries six quadratures; they are outside the LU).  It answers one question: how fast can
the default launch run on the new step loop when the plant is straight-line code with an
exact Jacobian, i.e. what the generated network plant should reach.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from clutchsim.core import System, register_system

_NAMES = ("J_e", "J_d", "J_cl", "b_e", "b_d", "b_g", "b_f", "b_w", "r_c", "r_dmp", "r_sh",
          "i_gb", "T_stat", "dT", "phi0", "omega0", "k_v", "p_exp", "reset", "reset_c",
          "sh_p", "sh_f", "c_dmp", "d_dmp", "knee", "c2", "c_sh", "d_sh", "drag0", "drag1",
          "idle", "kp", "ki", "t_aw", "r_t", "roll", "f_grade", "c_aero", "v_eps", "C_p",
          "C_f", "hA_p", "hA_f", "amb_p", "amb_f", "stall", "J_w",
          "mu_o", "mu_n", "eng_o", "eng_n")
P = {n: i for i, n in enumerate(_NAMES)}
(J_E, J_D, J_CL, B_E, B_D, B_G, B_F, B_W, R_C, R_DMP, R_SH, I_GB, T_STAT, D_T, PHI0, OMEGA0,
 K_V, P_EXP, RESET, RESET_C, SH_P, SH_F, C_DMP, D_DMP, KNEE, C2, C_SH, D_SH, DRAG0, DRAG1,
 IDLE, KP, KI, T_AW, R_T, ROLL, F_GRADE, C_AERO, V_EPS, C_P, C_F, HA_P, HA_F, AMB_P, AMB_F,
 STALL, J_W, MU_O, MU_N, ENG_O, ENG_N) = range(len(_NAMES))
STATES = ("omega_engine", "omega_disc", "omega_gearbox_input", "omega_wheels",
          "phi_damper", "phi_shaft", "phi_clutch", "theta_pressure_plate", "theta_flywheel",
          "governor_integral")
_POLICIES = {"none": 0.0, "clamp": 1.0, "zero": 2.0, "plus_phi0": 3.0, "minus_phi0": 4.0}


class StraightLaunch(NamedTuple):
    k: int = 0


@njit(inline="always")
def _interp(p, o, n, x):
    """Value and slope of the table at p[o:o+n] (x), p[o+n:o+2n] (y), held outside."""
    if x <= p[o] or n == 1:
        return p[o + n], 0.0
    if x >= p[o + n - 1]:
        return p[o + 2 * n - 1], 0.0
    lo, hi = 0, n - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if p[o + mid] <= x:
            lo = mid
        else:
            hi = mid
    s = (p[o + n + hi] - p[o + n + lo]) / (p[o + hi] - p[o + lo])
    return p[o + n + lo] + s * (x - p[o + lo]), s


@njit(inline="always")
def _eval(t, y, u, p, dy, J, want_j):
    """Right-hand side into dy; with want_j the exact Jacobian into J (zeroed here)."""
    w_e, w_d, w_g, w_w, ph_d, ph_s, phi, th_p = y[0], y[1], y[2], y[3], y[4], y[5], y[6], y[7]
    th_f, gi = y[8], y[9]
    throttle, com = u[0], u[1]
    # engine with idle governor (anti-windup), full-load table minus drag
    gov = 0.0
    dgi = 0.0
    dgov_dwe = 0.0
    dgov_dgi = 0.0
    if p[IDLE] > 0.0:
        err = p[IDLE] - w_e
        raw = p[KP] * err + p[KI] * gi
        room = max(1.0 - throttle, 0.0)
        if raw <= 0.0:
            gov = 0.0
        elif raw >= room:
            gov = room
        else:
            gov = raw
            dgov_dwe = -p[KP]
            dgov_dgi = p[KI]
        dgi = err + (gov - raw) / p[T_AW]
    xr = throttle + gov
    x = min(max(xr, 0.0), 1.0)
    dx = 1.0 if 0.0 < xr < 1.0 else 0.0
    T_full, dT_full = _interp(p, int(p[ENG_O]), int(p[ENG_N]), w_e)
    if T_full < 0.0:
        T_full, dT_full = 0.0, 0.0
    th = math.tanh(w_e)
    T_eng = x * T_full - (p[DRAG0] * th + p[DRAG1] * w_e)
    # clutch, model (6): T = scale·(T_stat·tanh(φ/φ0) + k_v·w − sign(w)·ΔT·(1 − e^{−|w/ω0|^p}))
    r_c = p[R_C]
    w_c = w_d - w_e / r_c
    mu, dmu = _interp(p, int(p[MU_O]), int(p[MU_N]), th_p)
    scale = com * mu if com > 0.0 else 0.0
    dscale = com * dmu if (com > 0.0 and com * mu > 0.0) else 0.0
    if scale < 0.0:
        scale, dscale = 0.0, 0.0
    tp = math.tanh(phi / p[PHI0])
    a = abs(w_c / p[OMEGA0])
    ex = math.exp(-a ** p[P_EXP]) if a > 0.0 else 1.0
    sgn = 1.0 if w_c > 0.0 else (-1.0 if w_c < 0.0 else 0.0)
    core = p[T_STAT] * tp + p[K_V] * w_c - sgn * p[D_T] * (1.0 - ex)
    T_c = scale * core
    # damper, two-stage spring
    r_dmp = p[R_DMP]
    w_dmp = w_g - w_d / r_dmp
    knee = p[KNEE]
    if knee <= 0.0 or abs(ph_d) <= knee:
        T_sp = p[C_DMP] * ph_d
        k_sp = p[C_DMP]
    elif ph_d > 0.0:
        T_sp = p[C_DMP] * knee + p[C2] * (ph_d - knee)
        k_sp = p[C2]
    else:
        T_sp = -(p[C_DMP] * knee + p[C2] * (-ph_d - knee))
        k_sp = p[C2]
    T_dmp = T_sp + p[D_DMP] * w_dmp
    # driveshaft, road load
    i_gb = p[I_GB]
    r_sh = p[R_SH]
    w_f = w_g / i_gb
    w_sh = w_w - w_f / r_sh
    T_sh = p[C_SH] * ph_s + p[D_SH] * w_sh
    r_t = p[R_T]
    v = w_w * r_t
    tv = math.tanh(v / p[V_EPS])
    F_road = p[ROLL] * tv + p[C_AERO] * v * abs(v) + p[F_GRADE]
    J_e, J_d, J_cl, J_w = p[J_E], p[J_D], p[J_CL], p[J_W]
    dy[0] = (T_eng - p[B_E] * w_e + T_c / r_c) / J_e
    dy[1] = (-T_c - p[B_D] * w_d + T_dmp / r_dmp) / J_d
    dy[2] = (-T_dmp - p[B_G] * w_g + (T_sh / r_sh - p[B_F] * w_f) / i_gb) / J_cl
    dy[3] = (-T_sh - p[B_W] * w_w - F_road * r_t) / J_w
    dy[4] = w_dmp
    dy[5] = w_sh
    dy[6] = w_c
    q = abs(T_c * w_c)
    dy[7] = (p[SH_P] * q - p[HA_P] * (th_p - p[AMB_P])) / p[C_P]
    dy[8] = (p[SH_F] * q - p[HA_F] * (th_f - p[AMB_F])) / p[C_F]
    dy[9] = dgi
    if not want_j:
        return
    for i in range(10):
        for j in range(10):
            J[i, j] = 0.0
    # partials of T_c in w_c, phi, theta_p
    dcore_dw = p[K_V]
    if a > 0.0:
        dcore_dw -= p[D_T] * p[P_EXP] * a ** (p[P_EXP] - 1.0) * ex / p[OMEGA0]
    dTc_dw = scale * dcore_dw
    dTc_dphi = scale * p[T_STAT] * (1.0 - tp * tp) / p[PHI0]
    dTc_dth = dscale * core
    # w_c = w_d - w_e/r_c
    dTc_dwe = -dTc_dw / r_c
    dTc_dwd = dTc_dw
    # engine torque partials
    dTeng_dwe = (dx * dgov_dwe * T_full + x * dT_full - (p[DRAG0] * (1.0 - th * th)
                                                        + p[DRAG1]))
    dTeng_dgi = dx * dgov_dgi * T_full
    J[0, 0] = (dTeng_dwe - p[B_E] + dTc_dwe / r_c) / J_e
    J[0, 1] = (dTc_dwd / r_c) / J_e
    J[0, 6] = (dTc_dphi / r_c) / J_e
    J[0, 7] = (dTc_dth / r_c) / J_e
    J[0, 9] = dTeng_dgi / J_e
    d_dmp = p[D_DMP]
    J[1, 0] = -dTc_dwe / J_d
    J[1, 1] = (-dTc_dwd - p[B_D] - d_dmp / r_dmp / r_dmp) / J_d
    J[1, 2] = (d_dmp / r_dmp) / J_d
    J[1, 4] = (k_sp / r_dmp) / J_d
    J[1, 6] = -dTc_dphi / J_d
    J[1, 7] = -dTc_dth / J_d
    d_sh = p[D_SH]
    J[2, 1] = (d_dmp / r_dmp) / J_cl
    J[2, 2] = (-d_dmp - p[B_G] + (-d_sh / (i_gb * r_sh) / r_sh - p[B_F] / i_gb) / i_gb) / J_cl
    J[2, 3] = (d_sh / r_sh / i_gb) / J_cl
    J[2, 4] = -k_sp / J_cl
    J[2, 5] = (p[C_SH] / r_sh / i_gb) / J_cl
    dF_dv = p[ROLL] * (1.0 - tv * tv) / p[V_EPS] + 2.0 * p[C_AERO] * abs(v)
    J[3, 2] = (d_sh / (i_gb * r_sh)) / J_w
    J[3, 3] = (-d_sh - p[B_W] - dF_dv * r_t * r_t) / J_w
    J[3, 5] = -p[C_SH] / J_w
    J[4, 1] = -1.0 / r_dmp
    J[4, 2] = 1.0
    J[5, 2] = -1.0 / (i_gb * r_sh)
    J[5, 3] = 1.0
    J[6, 0] = -1.0 / r_c
    J[6, 1] = 1.0
    # q = |T_c·w_c|
    sq = 1.0 if T_c * w_c > 0.0 else (-1.0 if T_c * w_c < 0.0 else 0.0)
    dq_dwe = sq * (dTc_dwe * w_c - T_c / r_c)
    dq_dwd = sq * (dTc_dwd * w_c + T_c)
    dq_dphi = sq * dTc_dphi * w_c
    dq_dth = sq * dTc_dth * w_c
    for row, sh, C, hA in ((7, p[SH_P], p[C_P], p[HA_P]), (8, p[SH_F], p[C_F], p[HA_F])):
        J[row, 0] = sh * dq_dwe / C
        J[row, 1] = sh * dq_dwd / C
        J[row, 6] = sh * dq_dphi / C
        J[row, 7] = sh * dq_dth / C
    J[7, 7] -= p[HA_P] / p[C_P]
    J[8, 8] = -p[HA_F] / p[C_F]
    if p[IDLE] > 0.0:
        # dgi = err + (gov − raw)/t_aw,  err = idle − w_e,  raw = kp·err + ki·gi
        J[9, 0] = -1.0 + (dgov_dwe + p[KP]) / p[T_AW]
        J[9, 9] = (dgov_dgi - p[KI]) / p[T_AW]


@njit
def straight_rhs(t, y, u, p, dy):
    _eval(t, y, u, p, dy, dy.reshape((1, dy.size)), False)


@njit
def straight_jac(t, y, u, p, J):
    dy = np.empty(10)
    _eval(t, y, u, p, dy, J, True)


@njit
def straight_events(t, y, u, p, g):
    g[0] = y[1] - y[0] / p[R_C]
    g[1] = y[0] - p[STALL]


@njit
def straight_reset(t, y, u, p, k):
    if k == 1:
        return 3
    pol = p[RESET]
    phi = y[6]
    sgn = 1.0 if phi > 0.0 else (-1.0 if phi < 0.0 else 0.0)
    if pol == 1.0:
        y[6] = sgn * min(abs(phi), p[RESET_C] * p[PHI0])
    elif pol == 2.0:
        y[6] = 0.0
    elif pol == 3.0:
        y[6] = sgn * p[PHI0]
    elif pol == 4.0:
        y[6] = -sgn * p[PHI0]
    else:
        return 0
    return 1


@njit
def straight_outputs(t, y, u, p, out):
    dy = np.empty(10)
    _eval(t, y, u, p, dy, dy.reshape((1, 10)), False)
    out[0] = y[1] - y[0] / p[R_C]


register_system(StraightLaunch, rhs=straight_rhs, events=straight_events,
                reset=straight_reset, outputs=straight_outputs, jac=straight_jac)


class StraightLaunchFD(NamedTuple):
    """The same plant without its Jacobian (the integrators difference it)."""

    k: int = 0


register_system(StraightLaunchFD, rhs=straight_rhs, events=straight_events,
                reset=straight_reset, outputs=straight_outputs)


def build(par, exact: bool = True) -> System:
    """The straight-line launch plant from ``_launch_plain.launch_params``."""
    vals = dict(  # noqa: C408 - keywords read as the parameter list
        J_e=par.J_e, J_d=par.J_d, J_cl=par.J_g + par.J_f / par.i_gb ** 2, b_e=par.b_e,
                b_d=par.b_d, b_g=par.b_g, b_f=par.b_f, b_w=par.b_w, r_c=par.r_c,
                r_dmp=par.r_dmp, r_sh=par.r_sh, i_gb=par.i_gb, T_stat=par.T_stat,
                dT=par.T_stat - par.k_din * par.T_stat, phi0=par.phi0, omega0=par.omega0,
                k_v=par.k_v, p_exp=par.p_exp, reset=_POLICIES[par.reset],
                reset_c=par.reset_c, sh_p=par.heat_share[0], sh_f=par.heat_share[1],
                c_dmp=par.c_dmp, d_dmp=par.d_dmp, knee=par.knee_dmp, c2=par.c2_dmp,
                c_sh=par.c_sh, d_sh=par.d_sh, drag0=par.drag0, drag1=par.drag1,
                idle=par.idle, kp=par.kp, ki=par.ki, t_aw=max(par.ki, 1e-12) * 0.1,
                r_t=par.r_tyre,
                roll=par.f_roll * par.mass * par.gravity * math.cos(par.grade_angle),
                f_grade=par.mass * par.gravity * math.sin(par.grade_angle),
                c_aero=par.c_aero, v_eps=par.v_eps, C_p=par.th_C[0], C_f=par.th_C[1],
                hA_p=par.th_hA[0], hA_f=par.th_hA[1], amb_p=par.th_amb[0],
                amb_f=par.th_amb[1], stall=par.stall, J_w=par.J_w)
    head = np.array([vals.get(n, 0.0) for n in _NAMES])
    mu = np.concatenate([par.mu_theta, par.mu_factor])
    eng = np.concatenate([par.eng_speed, par.eng_torque])
    head[MU_O], head[MU_N] = len(head), len(par.mu_theta)
    head[ENG_O], head[ENG_N] = len(head) + len(mu), len(par.eng_speed)
    p = np.concatenate([head, mu, eng])
    tag = StraightLaunch() if exact else StraightLaunchFD()
    return System(tag, p, np.array(par.y0), STATES, ("rad/s",) * 4 + ("rad",) * 3
                  + ("°C", "°C", "rad"), input_names=("throttle", "command"),
                  input_units=("-", "-"), output_names=("w_slip",), output_units=("rad/s",),
                  event_names=("slip zero", "engine stalled"), event_directions=(0, -1),
                  name="straight-line launch prototype")
