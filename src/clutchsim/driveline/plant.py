"""The compiled chain plant: N inertias in series, couplings, brakes, engine, vehicle, heat.

Everything the compiled functions need travels in the float vector ``p`` (layout below;
integers are stored as floats).  The Python side (:mod:`clutchsim.driveline.chain`) builds
``p``; nothing here knows component names.

Mechanics
---------
Node ``j`` (an inertia ``J_j`` [kg·m²]) has the speed ``omega_j`` [rad/s].  Coupling ``k``
joins node ``k`` (side a) and node ``k+1`` (side b) through an ideal ratio ``r_k``: its
relative speed is ``w_k = omega_{k+1} - omega_k/r_k`` and its torque ``tau_k`` (friction
convention: in the direction of ``w_k``) acts as ``+tau_k/r_k`` on node ``k`` and
``-tau_k`` on node ``k+1`` (Modelica: ``w_rel = flange_b.w - flange_a.w``, ``tau =
flange_b.tau``).  A brake on node ``m`` is the same element with ``w = omega_m`` against
ground.

Rigid joints (ideal gears, and friction elements in their *locked* mode) join nodes into
clusters that move as one inertia ``sum J_j s_j²`` (``s_j`` the speed factor of node ``j``
relative to the first node of the cluster).  The torque a locked (or hypothetically
locked) element transmits is computed from the partial cluster downstream of it; that is
the stick torque ``F_e`` handed to the friction kernels, so several elements can stick at
once (Modelica's CoupledClutches).  A cluster that contains a locked brake stands still.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import jit
from ..friction import friction_events, friction_force, friction_reset

# ---------------------------------------------------------------- header of p
(H_N, H_NF, H_NTH, H_ENG, H_VEH, H_NODE, H_CPL, H_FE, H_TH, H_ENGB, H_VEHB,
 H_YTW, H_YZ, H_YLK, H_YTH, H_YGOV, H_YEN, H_EVSTALL, H_NEV, H_NSHIFT, H_EVSHIFT,
 H_NOUT) = range(22)
HEADER = 24

NODE_W = 4          # J, bearing viscous d, load input index (-1 none), spare
(N_J, N_D, N_LOAD) = range(3)

CPL_W = 10          # kind, ratio, fe index, state index, c1, d, knee, c2, n shifts, shift off
(C_KIND, C_RATIO, C_FE, C_Y, C_C1, C_D, C_KNEE, C_C2, C_NSH, C_SHOFF) = range(10)
GEAR, FRICTION, SPRING, SHIFT_GEAR = 0, 1, 2, 3

FE_W = 24
(F_LOC, F_IDX, F_CODE, F_NZ, F_YZ, F_YLK, F_EV, F_NEV, F_PAR, F_IN, F_ACT, F_NACT,
 F_MUT, F_NMUT, F_MUS, F_NMUS, F_THA, F_SHA, F_THB, F_SHB, F_DRAG, F_CAP, F_SHEV) = range(23)
LOC_COUPLING, LOC_BRAKE = 0, 1

TH_W = 4            # capacity C [J/K], conductance hA [W/K], ambient [°C]
(T_C, T_HA, T_AMB) = range(3)

ENG_W = 12
(E_NODE, E_TAB, E_NTAB, E_IN, E_D0, E_D1, E_IDLE, E_KP, E_KI, E_STALL, E_GOV) = range(11)

VEH_W = 10
(V_NODE, V_MASS, V_R, V_GRADE, V_FR, V_CA, V_G, V_EPS) = range(8)

N_ENERGY = 6        # W_in, W_friction, W_damping, W_road, E_grade, W_sync
EN_IN, EN_FRIC, EN_DAMP, EN_ROAD, EN_GRADE, EN_SYNC = range(6)


@jit
def interp(p, off, n, x):
    """Linear interpolation in the table stored at ``p[off:off+n]`` (x) and
    ``p[off+n:off+2n]`` (y), held constant outside."""
    if n <= 0:
        return 1.0
    if x <= p[off]:
        return p[off + n]
    if x >= p[off + n - 1]:
        return p[off + 2 * n - 1]
    lo, hi = 0, n - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if p[off + mid] <= x:
            lo = mid
        else:
            hi = mid
    x0, x1 = p[off + lo], p[off + hi]
    y0, y1 = p[off + n + lo], p[off + n + hi]
    return y0 + (y1 - y0) * (x - x0) / (x1 - x0)


@jit
def _ratio(p, y, k):
    c = int(p[H_CPL]) + k * CPL_W
    if p[c + C_KIND] == SHIFT_GEAR:
        return y[int(p[c + C_Y])]
    return p[c + C_RATIO]


@jit
def _is_locked(p, y, k):
    """Is coupling k rigid now (a gear, or a locked friction element)?"""
    c = int(p[H_CPL]) + k * CPL_W
    kind = p[c + C_KIND]
    if kind == GEAR or kind == SHIFT_GEAR:
        return True
    if kind == FRICTION:
        f = int(p[H_FE]) + int(p[c + C_FE]) * FE_W
        return y[int(p[f + F_YLK])] > 0.5
    return False


@jit
def _left(p, y, j):
    while j > 0 and _is_locked(p, y, j - 1):
        j -= 1
    return j


@jit
def _right(p, y, j):
    n = int(p[H_N])
    while j < n - 1 and _is_locked(p, y, j):
        j += 1
    return j


@jit
def _speed_factors(p, y, a, b, s):
    s[a] = 1.0
    for j in range(a, b):
        s[j + 1] = s[j] / _ratio(p, y, j)


@jit
def _locked_brake_node(p, y, a, b, skip):
    """Node of the first locked brake on nodes a..b (not element ``skip``), or -1."""
    nf = int(p[H_NF])
    for e in range(nf):
        if e == skip:
            continue
        f = int(p[H_FE]) + e * FE_W
        if p[f + F_LOC] == LOC_BRAKE and y[int(p[f + F_YLK])] > 0.5:
            m = int(p[f + F_IDX])
            if a <= m <= b:
                return m
    return -1


@jit
def lock_torque(p, y, e, Tn, s):
    """Torque friction element ``e`` transmits if it is (or were) locked.

    ``Tn`` holds the node torques of everything except locked elements and ``e`` itself.
    """
    f = int(p[H_FE]) + e * FE_W
    J0 = int(p[H_NODE])
    if p[f + F_LOC] == LOC_COUPLING:
        k = int(p[f + F_IDX])
        a = _left(p, y, k)
        b = _right(p, y, k + 1)
        _speed_factors(p, y, a, b, s)
        m = _locked_brake_node(p, y, a, b, e)
        sum_t = 0.0
        j_eq = 0.0
        for j in range(a, b + 1):
            sum_t += Tn[j] * s[j]
            j_eq += p[J0 + j * NODE_W + N_J] * s[j] * s[j]
        down = 0.0
        if m < 0:
            alpha = sum_t / j_eq
            for j in range(k + 1, b + 1):
                down += Tn[j] * s[j] - p[J0 + j * NODE_W + N_J] * s[j] * s[j] * alpha
        else:
            for j in range(k + 1, b + 1):
                down += Tn[j] * s[j]
            if m >= k + 1:
                down -= sum_t
        return down / s[k + 1]
    m0 = int(p[f + F_IDX])
    a = _left(p, y, m0)
    b = _right(p, y, m0)
    if _locked_brake_node(p, y, a, b, e) >= 0:
        return 0.0
    _speed_factors(p, y, a, b, s)
    sum_t = 0.0
    for j in range(a, b + 1):
        sum_t += Tn[j] * s[j]
    return sum_t / s[m0]


@jit
def rel_speed(p, y, e):
    f = int(p[H_FE]) + e * FE_W
    if p[f + F_LOC] == LOC_COUPLING:
        k = int(p[f + F_IDX])
        return y[k + 1] - y[k] / _ratio(p, y, k)
    return y[int(p[f + F_IDX])]


@jit
def _add_element_torque(p, y, e, tau, Tn):
    f = int(p[H_FE]) + e * FE_W
    if p[f + F_LOC] == LOC_COUPLING:
        k = int(p[f + F_IDX])
        Tn[k] += tau / _ratio(p, y, k)
        Tn[k + 1] -= tau
    else:
        Tn[int(p[f + F_IDX])] -= tau


@jit
def element_scale(p, y, u, e, w):
    """Capacity multiplier of element e: actuation × mu(theta) × mu(slip) (>= 0)."""
    f = int(p[H_FE]) + e * FE_W
    x = u[int(p[f + F_IN])]
    n_act = int(p[f + F_NACT])
    act = interp(p, int(p[f + F_ACT]), n_act, x) if n_act > 0 else x
    if act <= 0.0:
        return 0.0
    th = int(p[f + F_THA])
    if th >= 0 and p[f + F_NMUT] > 0:
        act *= interp(p, int(p[f + F_MUT]), int(p[f + F_NMUT]), y[int(p[H_YTH]) + th])
    if p[f + F_NMUS] > 0:
        act *= interp(p, int(p[f + F_MUS]), int(p[f + F_NMUS]), abs(w))
    return max(act, 0.0)


@jit
def _spring_torque(p, c, phi):
    c1 = p[c + C_C1]
    knee = p[c + C_KNEE]
    if knee <= 0.0 or abs(phi) <= knee:
        return c1 * phi
    sg = 1.0 if phi > 0.0 else -1.0
    return sg * (c1 * knee + p[c + C_C2] * (abs(phi) - knee))


@jit
def spring_energy(p, c, phi):
    c1 = p[c + C_C1]
    knee = p[c + C_KNEE]
    if knee <= 0.0 or abs(phi) <= knee:
        return 0.5 * c1 * phi * phi
    ex = abs(phi) - knee
    return 0.5 * c1 * knee * knee + c1 * knee * ex + 0.5 * p[c + C_C2] * ex * ex


@jit
def engine_torque(p, y, u, omega):
    """(fuel torque, drag torque, governor integrator derivative) of the engine."""
    b = int(p[H_ENGB])
    t_full = interp(p, int(p[b + E_TAB]), int(p[b + E_NTAB]), omega)
    throttle = u[int(p[b + E_IN])]
    gov = 0.0
    dint = 0.0
    if p[b + E_GOV] > 0.0:
        # PI idle governor, limited to the torque left above the driver's throttle;
        # back-calculation anti-windup (time constant 0.1 s) keeps the rhs continuous
        err = p[b + E_IDLE] - omega
        raw = p[b + E_KP] * err + p[b + E_KI] * y[int(p[H_YGOV])]
        room = max(1.0 - throttle, 0.0)
        gov = min(max(raw, 0.0), room)
        dint = err + (gov - raw) / (max(p[b + E_KI], 1e-12) * 0.1)
    x = min(max(throttle + gov, 0.0), 1.0)
    fuel = x * max(t_full, 0.0)
    drag = (p[b + E_D0] * math.tanh(omega / 1.0) + p[b + E_D1] * omega)
    return fuel, drag, dint


@jit
def evaluate(t, y, u, p, dy, tau_c, fe_F, fe_Fe, fe_scale, fe_w):
    """All torques, stick torques and derivatives.  Writes ``dy`` completely."""
    n = int(p[H_N])
    nf = int(p[H_NF])
    J0 = int(p[H_NODE])
    C0 = int(p[H_CPL])
    F0 = int(p[H_FE])
    yen = int(p[H_YEN])
    for i in range(dy.size):
        dy[i] = 0.0
    Tn = np.zeros(n)
    s = np.empty(n)
    p_in = 0.0
    p_damp = 0.0
    p_road = 0.0
    p_grade = 0.0
    # nodes: bearing losses and load inputs
    for j in range(n):
        nb = J0 + j * NODE_W
        d = p[nb + N_D]
        if d != 0.0:
            Tn[j] -= d * y[j]
            p_damp += d * y[j] * y[j]
        li = int(p[nb + N_LOAD])
        if li >= 0:
            Tn[j] += u[li]
            p_in += u[li] * y[j]
    # engine
    if p[H_ENG] > 0.0:
        b = int(p[H_ENGB])
        je = int(p[b + E_NODE])
        fuel, drag, dint = engine_torque(p, y, u, y[je])
        Tn[je] += fuel - drag
        p_in += fuel * y[je]
        p_damp += drag * y[je]
        if p[b + E_GOV] > 0.0:
            dy[int(p[H_YGOV])] = dint
    # vehicle road load at its node
    if p[H_VEH] > 0.0:
        b = int(p[H_VEHB])
        jv = int(p[b + V_NODE])
        r = p[b + V_R]
        v = y[jv] * r
        mg = p[b + V_MASS] * p[b + V_G]
        th = p[b + V_GRADE]
        f_roll = p[b + V_FR] * mg * math.cos(th) * math.tanh(v / p[b + V_EPS])
        f_aero = p[b + V_CA] * v * abs(v)
        f_grade = mg * math.sin(th)
        Tn[jv] -= (f_roll + f_aero + f_grade) * r
        p_road += (f_roll + f_aero) * v
        p_grade += f_grade * v
    # spring-damper couplings
    for k in range(n - 1):
        c = C0 + k * CPL_W
        kind = p[c + C_KIND]
        if kind == SPRING:
            r = p[c + C_RATIO]
            w = y[k + 1] - y[k] / r
            iy = int(p[c + C_Y])
            dy[iy] = w
            tau = _spring_torque(p, c, y[iy]) + p[c + C_D] * w
            tau_c[k] = tau
            Tn[k] += tau / r
            Tn[k + 1] -= tau
            p_damp += p[c + C_D] * w * w
    # friction elements: slip speeds and capacities
    for e in range(nf):
        w = rel_speed(p, y, e)
        fe_w[e] = w
        fe_scale[e] = element_scale(p, y, u, e, w)
    # pass 1: free (unlocked) elements with F_e = 0
    T1 = Tn.copy()
    F1 = np.zeros(nf)
    for e in range(nf):
        f = F0 + e * FE_W
        if y[int(p[f + F_YLK])] > 0.5:
            continue
        nz = int(p[f + F_NZ])
        yz = int(p[f + F_YZ])
        dzt = np.empty(nz)
        pf = p[int(p[f + F_PAR]):]
        F1[e] = friction_force(int(p[f + F_CODE]), pf, y[yz:yz + nz], fe_w[e], 0.0,
                               fe_scale[e], dzt)
        _add_element_torque(p, y, e, F1[e], T1)
    # pass 2: free elements with their stick torque
    for e in range(nf):
        f = F0 + e * FE_W
        if y[int(p[f + F_YLK])] > 0.5:
            continue
        _add_element_torque(p, y, e, -F1[e], T1)
        fe_Fe[e] = lock_torque(p, y, e, T1, s)
        _add_element_torque(p, y, e, F1[e], T1)
        nz = int(p[f + F_NZ])
        yz = int(p[f + F_YZ])
        pf = p[int(p[f + F_PAR]):]
        F = friction_force(int(p[f + F_CODE]), pf, y[yz:yz + nz], fe_w[e], fe_Fe[e],
                           fe_scale[e], dy[yz:yz + nz])
        drag = p[f + F_DRAG]
        if drag != 0.0:
            F += drag * math.tanh(fe_w[e])
        fe_F[e] = F
        _add_element_torque(p, y, e, F, Tn)
    # locked elements: the constraint torque
    for e in range(nf):
        f = F0 + e * FE_W
        if y[int(p[f + F_YLK])] <= 0.5:
            continue
        fe_Fe[e] = lock_torque(p, y, e, Tn, s)
        nz = int(p[f + F_NZ])
        yz = int(p[f + F_YZ])
        pf = p[int(p[f + F_PAR]):]
        friction_force(int(p[f + F_CODE]), pf, y[yz:yz + nz], fe_w[e], fe_Fe[e],
                       fe_scale[e], dy[yz:yz + nz])
        fe_F[e] = fe_Fe[e]
    p_fric = 0.0
    for e in range(nf):
        f = F0 + e * FE_W
        p_fric += fe_F[e] * fe_w[e]
        if p[f + F_LOC] == LOC_COUPLING:
            tau_c[int(p[f + F_IDX])] = fe_F[e]
        # heat into the thermal nodes
        heat = abs(fe_F[e] * fe_w[e])
        ta = int(p[f + F_THA])
        if ta >= 0:
            dy[int(p[H_YTH]) + ta] += p[f + F_SHA] * heat
        tb = int(p[f + F_THB])
        if tb >= 0:
            dy[int(p[H_YTH]) + tb] += p[f + F_SHB] * heat
    # thermal nodes: convection and capacity
    nth = int(p[H_NTH])
    for i in range(nth):
        tb_ = int(p[H_TH]) + i * TH_W
        iy = int(p[H_YTH]) + i
        dy[iy] = (dy[iy] - p[tb_ + T_HA] * (y[iy] - p[tb_ + T_AMB])) / p[tb_ + T_C]
    # accelerations, cluster by cluster
    j = 0
    while j < n:
        a = j
        b = _right(p, y, a)
        if a == b and _locked_brake_node(p, y, a, b, -1) < 0:
            dy[a] = Tn[a] / p[J0 + a * NODE_W + N_J]
        else:
            _speed_factors(p, y, a, b, s)
            if _locked_brake_node(p, y, a, b, -1) >= 0:
                for i in range(a, b + 1):
                    dy[i] = 0.0
            else:
                sum_t = 0.0
                j_eq = 0.0
                for i in range(a, b + 1):
                    sum_t += Tn[i] * s[i]
                    j_eq += p[J0 + i * NODE_W + N_J] * s[i] * s[i]
                alpha = sum_t / j_eq
                for i in range(a, b + 1):
                    dy[i] = alpha * s[i]
        j = b + 1
    # gear torques (constraint torques of rigid gears), for output
    for k in range(n - 1):
        c = C0 + k * CPL_W
        kind = p[c + C_KIND]
        if kind == GEAR or kind == SHIFT_GEAR:
            # downstream of node k+1 inside its cluster: J·alpha - T
            b = _right(p, y, k + 1)
            _speed_factors(p, y, k + 1, b, s)
            m = _locked_brake_node(p, y, k + 1, b, -1)
            down = 0.0
            if m < 0:
                for i in range(k + 1, b + 1):
                    down += (Tn[i] - p[J0 + i * NODE_W + N_J] * dy[i]) * s[i]
                tau_c[k] = down
            else:
                tau_c[k] = math.nan
    dy[yen + EN_IN] = p_in
    dy[yen + EN_FRIC] = p_fric
    dy[yen + EN_DAMP] = p_damp
    dy[yen + EN_ROAD] = p_road
    dy[yen + EN_GRADE] = p_grade
    dy[yen + EN_SYNC] = 0.0


@jit
def _work(p):
    n = int(p[H_N])
    nf = int(p[H_NF])
    return np.zeros(max(n - 1, 1)), np.zeros(nf), np.zeros(nf), np.zeros(nf), np.zeros(nf)


@jit
def chain_rhs(t, y, u, p, dy):
    tau_c, fF, fFe, fs, fw = _work(p)
    evaluate(t, y, u, p, dy, tau_c, fF, fFe, fs, fw)


@jit
def chain_events(t, y, u, p, g):
    tau_c, fF, fFe, fs, fw = _work(p)
    dy = np.empty(y.size)
    evaluate(t, y, u, p, dy, tau_c, fF, fFe, fs, fw)
    nf = int(p[H_NF])
    for e in range(nf):
        f = int(p[H_FE]) + e * FE_W
        ne = int(p[f + F_NEV])
        if ne == 0:
            continue
        off = int(p[f + F_EV])
        nz = int(p[f + F_NZ])
        yz = int(p[f + F_YZ])
        pf = p[int(p[f + F_PAR]):]
        # a free element (scale 0) gets a vanishing capacity so that its break-away
        # function starts strictly positive and the first torque makes it cross
        sc = fs[e] if fs[e] > 0.0 else 1e-300
        friction_events(int(p[f + F_CODE]), pf, y[yz:yz + nz], fw[e], fFe[e], sc,
                        g[off:off + ne])
    if p[H_ENG] > 0.0:
        b = int(p[H_ENGB])
        g[int(p[H_EVSTALL])] = y[int(p[b + E_NODE])] - p[b + E_STALL]
    # gear shifts: time events
    n = int(p[H_N])
    for k in range(n - 1):
        c = int(p[H_CPL]) + k * CPL_W
        if p[c + C_KIND] == SHIFT_GEAR:
            nsh = int(p[c + C_NSH])
            off = int(p[c + C_SHOFF])
            ev0 = int(p[off + 2 * nsh])
            for i in range(nsh):
                g[ev0 + i] = t - p[off + i]


@jit
def _merge(p, y, a, b, s):
    """Give nodes a..b one common motion, conserving their momentum (or stop them)."""
    J0 = int(p[H_NODE])
    _speed_factors(p, y, a, b, s)
    if _locked_brake_node(p, y, a, b, -1) >= 0:
        for i in range(a, b + 1):
            y[i] = 0.0
        return
    num = 0.0
    den = 0.0
    for i in range(a, b + 1):
        jj = p[J0 + i * NODE_W + N_J]
        num += jj * s[i] * y[i]
        den += jj * s[i] * s[i]
    w = num / den
    for i in range(a, b + 1):
        y[i] = w * s[i]


@jit
def kinetic_energy(p, y):
    n = int(p[H_N])
    J0 = int(p[H_NODE])
    ke = 0.0
    for j in range(n):
        ke += 0.5 * p[J0 + j * NODE_W + N_J] * y[j] * y[j]
    return ke


@jit
def chain_reset(t, y, u, p, k):
    tau_c, fF, fFe, fs, fw = _work(p)
    dy = np.empty(y.size)
    evaluate(t, y, u, p, dy, tau_c, fF, fFe, fs, fw)
    n = int(p[H_N])
    s = np.empty(n)
    nf = int(p[H_NF])
    yen = int(p[H_YEN])
    for e in range(nf):
        f = int(p[H_FE]) + e * FE_W
        ne = int(p[f + F_NEV])
        off = int(p[f + F_EV])
        if ne == 0 or k < off or k >= off + ne:
            continue
        nz = int(p[f + F_NZ])
        yz = int(p[f + F_YZ])
        pf = p[int(p[f + F_PAR]):]
        action = friction_reset(int(p[f + F_CODE]), pf, y[yz:yz + nz], fw[e], fFe[e], fs[e],
                                k - off)
        if action == 2:
            y[int(p[f + F_YLK])] = 1.0
            ke0 = kinetic_energy(p, y)
            if p[f + F_LOC] == LOC_COUPLING:
                kk = int(p[f + F_IDX])
                _merge(p, y, _left(p, y, kk), _right(p, y, kk), s)
            else:
                m = int(p[f + F_IDX])
                _merge(p, y, _left(p, y, m), _right(p, y, m), s)
            y[yen + EN_SYNC] += ke0 - kinetic_energy(p, y)
            return 1
        if action == 3:
            y[int(p[f + F_YLK])] = 0.0
            return 1
        return 1 if action == 1 else 0
    if p[H_ENG] > 0.0 and k == int(p[H_EVSTALL]):
        return 3
    for kk in range(n - 1):
        c = int(p[H_CPL]) + kk * CPL_W
        if p[c + C_KIND] == SHIFT_GEAR:
            nsh = int(p[c + C_NSH])
            off = int(p[c + C_SHOFF])
            ev0 = int(p[off + 2 * nsh])
            if ev0 <= k < ev0 + nsh:
                ke0 = kinetic_energy(p, y)
                y[int(p[c + C_Y])] = p[off + nsh + (k - ev0)]
                # ideal synchroniser: the input side takes the new ratio's speed
                a = _left(p, y, kk)
                b = _right(p, y, kk)
                _speed_factors(p, y, a, b, s)
                ref = y[b] / s[b]
                for i in range(a, b + 1):
                    y[i] = ref * s[i]
                y[yen + EN_SYNC] += ke0 - kinetic_energy(p, y)
                return 1
    return 0


@jit
def chain_outputs(t, y, u, p, out):
    """Coupling torques, element slip/scale/stick torque/power, engine, vehicle, energy."""
    n = int(p[H_N])
    nf = int(p[H_NF])
    tau_c, fF, fFe, fs, fw = _work(p)
    dy = np.empty(y.size)
    evaluate(t, y, u, p, dy, tau_c, fF, fFe, fs, fw)
    i = 0
    for k in range(n - 1):
        out[i] = tau_c[k]
        i += 1
    for e in range(nf):
        f = int(p[H_FE]) + e * FE_W
        out[i] = fF[e]
        out[i + 1] = fw[e]
        out[i + 2] = fs[e] * p[f + F_CAP]
        out[i + 3] = fFe[e]
        out[i + 4] = fF[e] * fw[e]
        i += 5
    ke = kinetic_energy(p, y)
    pe = 0.0
    for k in range(n - 1):
        c = int(p[H_CPL]) + k * CPL_W
        if p[c + C_KIND] == SPRING:
            pe += spring_energy(p, c, y[int(p[c + C_Y])])
    fuel = 0.0
    if p[H_ENG] > 0.0:
        b = int(p[H_ENGB])
        je = int(p[b + E_NODE])
        fuel, drag, dint = engine_torque(p, y, u, y[je])
        out[i] = fuel - drag
        i += 1
    if p[H_VEH] > 0.0:
        b = int(p[H_VEHB])
        jv = int(p[b + V_NODE])
        out[i] = y[jv] * p[b + V_R]
        out[i + 1] = dy[jv] * p[b + V_R]
        i += 2
    out[i] = ke
    out[i + 1] = pe
