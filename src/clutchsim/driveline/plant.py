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

Rigid joints (ideal gears, lossy gears, and friction elements in their *locked* mode) join
nodes into clusters that move as one inertia ``sum J_j s_j²`` (``s_j`` the speed factor of
node ``j`` relative to the first node of the cluster).  The torque a locked (or
hypothetically locked) element transmits is computed from the partial cluster downstream
of it; that is the stick torque ``F_e`` handed to the friction kernels, so several
elements can stick at once (Modelica's CoupledClutches).

A cluster that contains a locked *holder* (a brake, or a lossy gear in its stuck mode)
stands still.  Several holders in one cluster share the torque by priority: brakes in
element order each take up to their static capacity, the last holder (a stuck lossy gear
if there is one, else the last brake) takes the rest, and breaks away when that exceeds
its own limit.  This is one admissible split of a statically indeterminate case (Modelica's
LossyGearDemo2 documentation says there is no unique solution).

Switching elements
------------------
``F_KIND`` selects the element law: ``FK_MODEL`` a friction model of
:mod:`clutchsim.friction` (its kernels decide stick and slip), ``FK_ONE_WAY`` a freewheel in
parallel with a coulomb-robust clutch (slides only with ``w > 0``; locked it holds any
torque ``<= 0`` and up to the clutch's static capacity above), ``FK_LOSSY`` the loss of a
lossy gear (a brake-like element on the gear's flange-a node whose sliding torque depends
on the transmitted torque, Modelica's ``LossyGear``).  After a structural reset (an element
locks or frees) the plant re-checks every other switching element at the same instant
(an event iteration): a locked element whose stick torque now exceeds its limit breaks
away, and a sliding element whose slip was made exactly zero by the merge goes through its
stop decision.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import jit
from ..core.status import Action
from ..friction import friction_events, friction_force, friction_reset, uses_stick_force
from ..friction.base import RESET_CHANGED, RESET_NONE, RESET_RELEASED, RESET_STUCK

# ---------------------------------------------------------------- header of p
(H_N, H_NF, H_NTH, H_ENG, H_VEH, H_NODE, H_CPL, H_FE, H_TH, H_ENGB, H_VEHB,
 H_YTW, H_YZ, H_YLK, H_YTH, H_YGOV, H_YEN, H_EVSTALL, H_NEV, H_NSHIFT, H_EVSHIFT,
 H_NOUT) = range(22)
HEADER = 24

NODE_W = 4          # J, bearing viscous d, load input index (-1 none), spare
(N_J, N_D, N_LOAD) = range(3)

CPL_W = 10          # kind, ratio, fe index, state index, c1, d, knee, c2, n shifts, shift off
(C_KIND, C_RATIO, C_FE, C_Y, C_C1, C_D, C_KNEE, C_C2, C_NSH, C_SHOFF) = range(10)
GEAR, FRICTION, SPRING, SHIFT_GEAR, LOSSY_GEAR = 0, 1, 2, 3, 4

FE_W = 26
(F_LOC, F_IDX, F_CODE, F_NZ, F_YZ, F_YLK, F_EV, F_NEV, F_PAR, F_IN, F_ACT, F_NACT,
 F_MUT, F_NMUT, F_MUS, F_NMUS, F_THA, F_SHA, F_THB, F_SHB, F_DRAG, F_CAP, F_SHEV,
 F_KIND, F_AUX) = range(25)
LOC_COUPLING, LOC_BRAKE = 0, 1
#: element kinds; F_AUX holds the one-way clutch's open release torque [N·m] or the offset
#: of a lossy gear's loss table (n, |w| column, eta_mf1, eta_mf2, tau_bf1, tau_bf2 columns)
FK_MODEL, FK_ONE_WAY, FK_LOSSY = 0, 1, 2
#: the coulomb-robust model code (the switching model the plant locks and frees)
CODE_ROBUST = 2

TH_W = 6            # capacity C [J/K], conductance hA [W/K], ambient [°C], link node, G [W/K]
(T_C, T_HA, T_AMB, T_LINK, T_G) = range(5)

ENG_W = 12
(E_NODE, E_TAB, E_NTAB, E_IN, E_D0, E_D1, E_IDLE, E_KP, E_KI, E_STALL, E_GOV) = range(11)

VEH_W = 10
(V_NODE, V_MASS, V_R, V_FR, V_CA, V_G, V_EPS, V_COS, V_SIN) = range(9)   # cos, sin of grade

N_ENERGY = 6        # W_in, W_friction, W_damping, W_road, E_grade, W_sync
EN_IN, EN_FRIC, EN_DAMP, EN_ROAD, EN_GRADE, EN_SYNC = range(6)

NO_EVENT = 1.0
#: the plant's answers to the integrator (core.Action)
_CONTINUE, _STATE_CHANGED, _FAIL = (int(Action.CONTINUE), int(Action.STATE_CHANGED),
                                    int(Action.FAIL))
#: rows of the per-call workspace ``W`` (:func:`workspace`): coupling torques, element
#: torque / stick torque / capacity scale / slip / auxiliary (lossy flange-a torque), node
#: torques, speed factors, node torques of pass 1, holding scratch, pass-1 element torques,
#: holder torques, and the holding scratch of the stick-torque solves.  One 2-D array
#: indexed by row: a view per array would cost two atomic reference counts per call.
(R_TAU, R_F, R_FE, R_FS, R_FW, R_FA, R_TN, R_S, R_T1, R_TH, R_F1, R_HB, R_THH,
 R_HBH) = range(14)
N_ROWS = 14
#: torque band [N·m] by which a stuck lossy gear's holding torque may leave its limits
#: before it rolls.  An unloaded gear without bearing friction holds exactly its limits
#: (0 = 0), and round-off torques (~1e-16 N·m) around a standstill would otherwise pick
#: its rolling direction at random; the band makes the break-away function start
#: positive and the rolling direction follow the first real torque.
LOSSY_TOL = 1e-9


@jit(inline="always")
def _interp_xy(p, xo, yo, n, x):
    """Linear interpolation in the table with breakpoints ``p[xo:xo+n]`` and values
    ``p[yo:yo+n]``, held constant outside."""
    if x <= p[xo]:
        return p[yo]
    if x >= p[xo + n - 1]:
        return p[yo + n - 1]
    lo, hi = 0, n - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if p[xo + mid] <= x:
            lo = mid
        else:
            hi = mid
    x0, x1 = p[xo + lo], p[xo + hi]
    y0, y1 = p[yo + lo], p[yo + hi]
    return y0 + (y1 - y0) * (x - x0) / (x1 - x0)


@jit(inline="always")
def interp(p, off, n, x):
    """Linear interpolation in the table stored at ``p[off:off+n]`` (x) and
    ``p[off+n:off+2n]`` (y), held constant outside."""
    if n <= 0:
        return 1.0
    return _interp_xy(p, off, off + n, n, x)


@jit(inline="always")
def _ratio(p, y, k):
    c = int(p[H_CPL]) + k * CPL_W
    if p[c + C_KIND] == SHIFT_GEAR:
        return y[int(p[c + C_Y])]
    return p[c + C_RATIO]


@jit(inline="always")
def _is_locked(p, y, k):
    """Is coupling k rigid now (a gear, or a locked friction element)?"""
    c = int(p[H_CPL]) + k * CPL_W
    kind = p[c + C_KIND]
    if kind == GEAR or kind == SHIFT_GEAR or kind == LOSSY_GEAR:
        return True
    if kind == FRICTION:
        f = int(p[H_FE]) + int(p[c + C_FE]) * FE_W
        return y[int(p[f + F_YLK])] > 0.5
    return False


@jit(inline="always")
def _left(p, y, j):
    while j > 0 and _is_locked(p, y, j - 1):
        j -= 1
    return j


@jit(inline="always")
def _right(p, y, j):
    n = int(p[H_N])
    while j < n - 1 and _is_locked(p, y, j):
        j += 1
    return j


@jit(inline="always")
def _speed_factors(p, y, a, b, W):
    W[R_S, a] = 1.0
    for j in range(a, b):
        W[R_S, j + 1] = W[R_S, j] / _ratio(p, y, j)


@jit(inline="always")
def _locked_brake_node(p, y, a, b, skip):
    """Node of the first locked holder (brake or stuck lossy gear) on nodes a..b (not
    element ``skip``), or -1."""
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


# ------------------------------------------------------------------ lossy gear law
@jit
def lossy_coeffs(p, f, w):
    """(eta_mf1, eta_mf2, tau_bf1, tau_bf2, tau_bf_a) of the lossy element at ``p[f:]``,
    read in its loss table at ``|w|`` [rad/s]."""
    aux = int(p[f + F_AUX])
    n = int(p[aux])
    xo = aux + 1
    x = abs(w)
    e1 = _interp_xy(p, xo, xo + n, n, x)
    e2 = _interp_xy(p, xo, xo + 2 * n, n, x)
    b1 = _interp_xy(p, xo, xo + 3 * n, n, x)
    b2 = _interp_xy(p, xo, xo + 4 * n, n, x)
    if abs(e1 - 1.0) <= 1e-15 and abs(e2 - 1.0) <= 1e-15:
        ba = 0.5 * b1
    else:
        ba = (b1 - b2) / (e1 - 1.0 / e2)
    return e1, e2, b1, b2, ba


@jit
def lossy_bounds(p, f, Ta):
    """(lower, upper) loss torque [N·m] a stuck lossy gear holds at the flange-a torque
    ``Ta`` (Modelica ``tauLossMin_m``, ``tauLossMax_p``: the rolling laws at |w| = 0)."""
    e1, e2, b1, b2, ba = lossy_coeffs(p, f, 0.0)
    if Ta - ba > 0.0:
        up = (1.0 - e1) * Ta + b1
    else:
        up = (1.0 - 1.0 / e2) * Ta + b2
    if Ta + ba > 0.0:
        lo = (1.0 - 1.0 / e2) * Ta - b2
    else:
        lo = (1.0 - e1) * Ta - b1
    return lo, up


@jit
def lossy_solve(mode, T0, kk, e1, e2, b1, b2, ba):
    """Loss ``L`` and flange-a torque ``T`` of a rolling lossy gear.

    Solves ``L = law(T)``, ``T = T0 + kk·L`` (0 <= kk <= 1: how much of the loss comes
    back to flange a through the accelerations or the holder of the cluster).  The law is
    continuous and piecewise linear with slopes ``1 - eta_mf1 < 1`` and ``1 - 1/eta_mf2
    <= 0``, so ``T - kk·law(T)`` is increasing and the solution is unique: the branch above
    the power-flow switch point is tried first.
    """
    if mode > 0.0:
        sw, cu, du, cl, dl = ba, 1.0 - e1, b1, 1.0 - 1.0 / e2, b2
    else:
        sw, cu, du, cl, dl = -ba, 1.0 - 1.0 / e2, -b2, 1.0 - e1, -b1
    L = (cu * T0 + du) / (1.0 - cu * kk)
    T = T0 + kk * L
    if T >= sw:
        return L, T
    L = (cl * T0 + dl) / (1.0 - cl * kk)
    return L, T0 + kk * L


@jit
def one_way_limit(p, f, scale):
    """Largest forward stick torque of a locked one-way clutch [N·m]."""
    if scale > 0.0:
        return scale * p[f + F_CAP]
    return p[f + F_AUX]


# ------------------------------------------------------------------ holders and stick torques
@jit(inline="always")
def _holds(p, y, f, e, a, b, include):
    """Is the brake-like element ``e`` (block ``f``) on nodes a..b and holding (locked, or
    ``include``)?"""
    m = int(p[f + F_IDX])
    if m < a or m > b:
        return False
    return e == include or y[int(p[f + F_YLK])] > 0.5


@jit
def _hold(p, y, a, b, include, W, rTh, rHb):
    """Share the torque that holds the cluster a..b at rest among its holders.

    Holders are the locked brake-like elements on nodes a..b plus element ``include``
    (-1: none) whatever its lock flag.  Brakes, in element order, take up to their
    static capacity; the last holder (a lossy gear if one is a holder, else the last
    brake) takes the rest.  Each holder's torque goes into row ``rHb`` of ``W`` and is
    subtracted from the node torques in row ``rTh`` at its node.  Returns (number of
    holders, node of the last holder).
    """
    nf = int(p[H_NF])
    F0 = int(p[H_FE])
    last = -1
    count = 0
    for lossy_pass in range(2):
        for e in range(nf):
            f = F0 + e * FE_W
            if p[f + F_LOC] != LOC_BRAKE:
                continue
            if (p[f + F_KIND] == FK_LOSSY) != (lossy_pass == 1):
                continue
            if not _holds(p, y, f, e, a, b, include):
                continue
            last = e
            count += 1
    if count == 0:
        return 0, -1
    S = 0.0
    for j in range(a, b + 1):
        S += W[rTh, j] * W[R_S, j]
    for e in range(nf):
        if e == last:
            continue
        f = F0 + e * FE_W
        if p[f + F_LOC] != LOC_BRAKE or p[f + F_KIND] == FK_LOSSY:
            continue
        if not _holds(p, y, f, e, a, b, include):
            continue
        m = int(p[f + F_IDX])
        cap = W[R_FS, e] * p[f + F_CAP]
        B = max(-cap, min(cap, S / W[R_S, m]))
        W[rHb, e] = B
        W[rTh, m] -= B
        S -= B * W[R_S, m]
    f = F0 + last * FE_W
    m = int(p[f + F_IDX])
    B = S / W[R_S, m]
    W[rHb, last] = B
    W[rTh, m] -= B
    return count, m


@jit(inline="always")
def _hold_rows(p, W, rT, a, b):
    """Prepare the holding scratch of a stick-torque solve: node torques of row ``rT`` on
    nodes a..b into ``R_THH``, holder torques ``R_HBH`` zeroed."""
    for i in range(int(p[H_NF])):
        W[R_HBH, i] = 0.0
    for j in range(a, b + 1):
        W[R_THH, j] = W[rT, j]


@jit
def lock_torque(p, y, e, W, rT):
    """Torque friction element ``e`` transmits if it is (or were) locked.

    Row ``rT`` of ``W`` holds the node torques of everything except locked elements and
    ``e`` itself.  For a lossy gear ``W[R_FA, e]`` receives its flange-a torque in that
    state.
    """
    f = int(p[H_FE]) + e * FE_W
    J0 = int(p[H_NODE])
    if p[f + F_LOC] == LOC_COUPLING:
        k = int(p[f + F_IDX])
        a = _left(p, y, k)
        b = _right(p, y, k + 1)
        _speed_factors(p, y, a, b, W)
        _hold_rows(p, W, rT, a, b)
        cnt, _m = _hold(p, y, a, b, -1, W, R_THH, R_HBH)
        down = 0.0
        if cnt == 0:
            sum_t = 0.0
            j_eq = 0.0
            for j in range(a, b + 1):
                sum_t += W[rT, j] * W[R_S, j]
                j_eq += p[J0 + j * NODE_W + N_J] * W[R_S, j] * W[R_S, j]
            alpha = sum_t / j_eq
            for j in range(k + 1, b + 1):
                sj = W[R_S, j]
                down += W[rT, j] * sj - p[J0 + j * NODE_W + N_J] * sj * sj * alpha
        else:
            for j in range(k + 1, b + 1):
                down += W[R_THH, j] * W[R_S, j]
        return down / W[R_S, k + 1]
    m0 = int(p[f + F_IDX])
    a = _left(p, y, m0)
    b = _right(p, y, m0)
    _speed_factors(p, y, a, b, W)
    _hold_rows(p, W, rT, a, b)
    _hold(p, y, a, b, e, W, R_THH, R_HBH)
    if p[f + F_KIND] == FK_LOSSY:
        up = 0.0
        for j in range(a, m0 + 1):
            up += W[R_THH, j] * W[R_S, j]
        W[R_FA, e] = up / W[R_S, m0] + W[R_HBH, e]
    return W[R_HBH, e]


@jit
def lossy_rolling(p, y, e, W, rT):
    """(loss torque, flange-a torque) of the rolling lossy element ``e``, given the node
    torques in row ``rT`` of ``W`` of everything else (sliding elements included, holders not)."""
    f = int(p[H_FE]) + e * FE_W
    J0 = int(p[H_NODE])
    k = int(p[f + F_IDX])
    a = _left(p, y, k)
    b = _right(p, y, k)
    _speed_factors(p, y, a, b, W)
    _hold_rows(p, W, rT, a, b)
    cnt, m = _hold(p, y, a, b, -1, W, R_THH, R_HBH)
    up = 0.0
    for j in range(a, k + 1):
        up += W[R_THH, j] * W[R_S, j]
    T0 = up / W[R_S, k]
    if cnt == 0:
        # moving cluster: T_a = T0_moving + (J_up/J_eq)·L
        S = 0.0
        j_eq = 0.0
        j_up = 0.0
        for j in range(a, b + 1):
            jj = p[J0 + j * NODE_W + N_J] * W[R_S, j] * W[R_S, j]
            S += W[rT, j] * W[R_S, j]
            j_eq += jj
            if j <= k:
                j_up += jj
        T0 -= j_up * S / (j_eq * W[R_S, k])
        kk = j_up / j_eq
    else:
        # held by another element: the loss comes back to flange a if that holder is on
        # the flange-a side
        kk = 1.0 if m <= k else 0.0
    e1, e2, b1, b2, ba = lossy_coeffs(p, f, y[k])
    return lossy_solve(y[int(p[f + F_YZ])], T0, kk, e1, e2, b1, b2, ba)


@jit(inline="always")
def rel_speed(p, y, e):
    f = int(p[H_FE]) + e * FE_W
    if p[f + F_LOC] == LOC_COUPLING:
        k = int(p[f + F_IDX])
        return y[k + 1] - y[k] / _ratio(p, y, k)
    return y[int(p[f + F_IDX])]


@jit(inline="always")
def _add_element_torque(p, y, e, tau, W, r):
    f = int(p[H_FE]) + e * FE_W
    if p[f + F_LOC] == LOC_COUPLING:
        k = int(p[f + F_IDX])
        W[r, k] += tau / _ratio(p, y, k)
        W[r, k + 1] -= tau
    else:
        W[r, int(p[f + F_IDX])] -= tau


@jit(inline="always")
def element_scale(p, y, u, e, w):
    """Capacity multiplier of element e: actuation × mu(theta) × mu(slip) (>= 0)."""
    f = int(p[H_FE]) + e * FE_W
    if p[f + F_KIND] == FK_LOSSY:
        return 1.0
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


@jit(inline="always")
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


@jit(inline="always")
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


@jit(inline="always")
def _smooth(p):
    """Are all switching elements friction models whose force ignores the stick torque?"""
    for e in range(int(p[H_NF])):
        f = int(p[H_FE]) + e * FE_W
        if p[f + F_KIND] != FK_MODEL or uses_stick_force(int(p[f + F_CODE])):
            return False
    return True


@jit
def _element_force(p, y, e, w, Fe, scale, dy):
    """Force of the friction model of element ``e`` at slip ``w`` and stick torque ``Fe``;
    writes its state derivatives into ``dy``.  Called, not inlined: the dispatch over all
    models is compiled once instead of at each of its three call sites."""
    f = int(p[H_FE]) + e * FE_W
    nz = int(p[f + F_NZ])
    yz = int(p[f + F_YZ])
    return friction_force(int(p[f + F_CODE]), p[int(p[f + F_PAR]):], y[yz:yz + nz], w, Fe,
                          scale, dy[yz:yz + nz])


@jit(inline="always")
def _model_force(p, y, e, w, Fe, scale, dy):
    """Torque of the friction-model element ``e`` plus its open drag (see
    :func:`_element_force`)."""
    f = int(p[H_FE]) + e * FE_W
    F = _element_force(p, y, e, w, Fe, scale, dy)
    drag = p[f + F_DRAG]
    if drag != 0.0:
        F += drag * math.tanh(w)
    return F


@jit
def evaluate(t, y, u, p, dy, W, complete):
    """All torques, stick torques and derivatives into ``dy`` (completely) and the
    workspace ``W`` (rows ``R_*``, from :func:`workspace`).

    ``complete`` False (the right-hand side) leaves out what only outputs, events and
    resets read: the stick torques ``fe_Fe`` where no force depends on them (a plant whose
    friction elements are all smooth models then takes one friction pass instead of two
    and no cluster solve per element), and the constraint torques of rigid gears in
    row ``R_TAU``."""
    n = int(p[H_N])
    nf = int(p[H_NF])
    J0 = int(p[H_NODE])
    C0 = int(p[H_CPL])
    F0 = int(p[H_FE])
    yen = int(p[H_YEN])
    for i in range(dy.size):
        dy[i] = 0.0
    for j in range(n):
        W[R_TN, j] = 0.0
    p_in = 0.0
    p_damp = 0.0
    p_road = 0.0
    p_grade = 0.0
    # nodes: bearing losses and load inputs
    for j in range(n):
        nb = J0 + j * NODE_W
        d = p[nb + N_D]
        if d != 0.0:
            W[R_TN, j] -= d * y[j]
            p_damp += d * y[j] * y[j]
        li = int(p[nb + N_LOAD])
        if li >= 0:
            W[R_TN, j] += u[li]
            p_in += u[li] * y[j]
    # engine
    if p[H_ENG] > 0.0:
        b = int(p[H_ENGB])
        je = int(p[b + E_NODE])
        fuel, drag, dint = engine_torque(p, y, u, y[je])
        W[R_TN, je] += fuel - drag
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
        f_roll = p[b + V_FR] * mg * p[b + V_COS] * math.tanh(v / p[b + V_EPS])
        f_aero = p[b + V_CA] * v * abs(v)
        f_grade = mg * p[b + V_SIN]
        W[R_TN, jv] -= (f_roll + f_aero + f_grade) * r
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
            W[R_TAU, k] = tau
            W[R_TN, k] += tau / r
            W[R_TN, k + 1] -= tau
            p_damp += p[c + C_D] * w * w
    # switching elements: slip speeds and capacities
    for e in range(nf):
        w = rel_speed(p, y, e)
        W[R_FW, e] = w
        W[R_FS, e] = element_scale(p, y, u, e, w)
    if not complete and _smooth(p):
        # no force reads a stick torque: one pass, F_e = 0 (reported as 0)
        for e in range(nf):
            W[R_F, e] = _model_force(p, y, e, W[R_FW, e], 0.0, W[R_FS, e], dy)
            W[R_FE, e] = 0.0
            _add_element_torque(p, y, e, W[R_F, e], W, R_TN)
    else:
        # pass 1: free (unlocked) friction elements with F_e = 0
        for j in range(n):
            W[R_T1, j] = W[R_TN, j]
        for e in range(nf):
            W[R_F1, e] = 0.0
        for e in range(nf):
            f = F0 + e * FE_W
            if y[int(p[f + F_YLK])] > 0.5 or p[f + F_KIND] == FK_LOSSY:
                continue
            # (its state derivatives land in dy and are overwritten in pass 2)
            W[R_F1, e] = _element_force(p, y, e, W[R_FW, e], 0.0, W[R_FS, e], dy)
            _add_element_torque(p, y, e, W[R_F1, e], W, R_T1)
        # rolling lossy gears: the loss follows from the torques of everything else
        for e in range(nf):
            f = F0 + e * FE_W
            if y[int(p[f + F_YLK])] > 0.5 or p[f + F_KIND] != FK_LOSSY:
                continue
            W[R_F1, e], _ta = lossy_rolling(p, y, e, W, R_T1)
            _add_element_torque(p, y, e, W[R_F1, e], W, R_T1)
        # pass 2: free elements with their stick torque
        for e in range(nf):
            f = F0 + e * FE_W
            if y[int(p[f + F_YLK])] > 0.5:
                continue
            _add_element_torque(p, y, e, -W[R_F1, e], W, R_T1)
            W[R_FE, e] = lock_torque(p, y, e, W, R_T1)
            _add_element_torque(p, y, e, W[R_F1, e], W, R_T1)
            if p[f + F_KIND] == FK_LOSSY:
                F = W[R_F1, e]
            else:
                F = _model_force(p, y, e, W[R_FW, e], W[R_FE, e], W[R_FS, e], dy)
            W[R_F, e] = F
            _add_element_torque(p, y, e, F, W, R_TN)
        # locked elements: the constraint torque
        for e in range(nf):
            f = F0 + e * FE_W
            if y[int(p[f + F_YLK])] <= 0.5:
                continue
            W[R_FE, e] = lock_torque(p, y, e, W, R_TN)
            if p[f + F_KIND] != FK_LOSSY:
                _element_force(p, y, e, W[R_FW, e], W[R_FE, e], W[R_FS, e], dy)
            W[R_F, e] = W[R_FE, e]
    p_fric = 0.0
    for e in range(nf):
        f = F0 + e * FE_W
        p_fric += W[R_F, e] * W[R_FW, e]
        if p[f + F_LOC] == LOC_COUPLING:
            W[R_TAU, int(p[f + F_IDX])] = W[R_F, e]
        # heat into the thermal nodes
        heat = abs(W[R_F, e] * W[R_FW, e])
        ta = int(p[f + F_THA])
        if ta >= 0:
            dy[int(p[H_YTH]) + ta] += p[f + F_SHA] * heat
        tb = int(p[f + F_THB])
        if tb >= 0:
            dy[int(p[H_YTH]) + tb] += p[f + F_SHB] * heat
    # thermal nodes: convection, conduction links, capacity
    nth = int(p[H_NTH])
    yth = int(p[H_YTH])
    for i in range(nth):
        tb_ = int(p[H_TH]) + i * TH_W
        iy = yth + i
        dy[iy] -= p[tb_ + T_HA] * (y[iy] - p[tb_ + T_AMB])
        li = int(p[tb_ + T_LINK])
        if li >= 0:
            q = p[tb_ + T_G] * (y[iy] - y[yth + li])
            dy[iy] -= q
            dy[yth + li] += q
    for i in range(nth):
        dy[yth + i] /= p[int(p[H_TH]) + i * TH_W + T_C]
    # accelerations, cluster by cluster
    j = 0
    while j < n:
        a = j
        b = _right(p, y, a)
        if a == b and _locked_brake_node(p, y, a, b, -1) < 0:
            dy[a] = W[R_TN, a] / p[J0 + a * NODE_W + N_J]
        else:
            _speed_factors(p, y, a, b, W)
            if _locked_brake_node(p, y, a, b, -1) >= 0:
                for i in range(a, b + 1):
                    dy[i] = 0.0
            else:
                sum_t = 0.0
                j_eq = 0.0
                for i in range(a, b + 1):
                    sum_t += W[R_TN, i] * W[R_S, i]
                    j_eq += p[J0 + i * NODE_W + N_J] * W[R_S, i] * W[R_S, i]
                alpha = sum_t / j_eq
                for i in range(a, b + 1):
                    dy[i] = alpha * W[R_S, i]
        j = b + 1
    # gear torques (constraint torques of rigid gears), for output: the torque the gear
    # passes to the part of its cluster downstream of it, referred to node k+1
    for e in range(nf):
        W[R_HB, e] = 0.0
    for k in range(n - 1 if complete else 0):
        c = C0 + k * CPL_W
        kind = p[c + C_KIND]
        if kind == GEAR or kind == SHIFT_GEAR or kind == LOSSY_GEAR:
            a = _left(p, y, k)
            b = _right(p, y, k)
            _speed_factors(p, y, a, b, W)
            down = 0.0
            if _locked_brake_node(p, y, a, b, -1) >= 0:
                for i in range(a, b + 1):
                    W[R_TH, i] = W[R_TN, i]
                _hold(p, y, a, b, -1, W, R_TH, R_HB)
                for i in range(k + 1, b + 1):
                    down += W[R_TH, i] * W[R_S, i]
            else:
                for i in range(k + 1, b + 1):
                    down += (W[R_TN, i] - p[J0 + i * NODE_W + N_J] * dy[i]) * W[R_S, i]
            W[R_TAU, k] = down / W[R_S, k + 1]
    dy[yen + EN_IN] = p_in
    dy[yen + EN_FRIC] = p_fric
    dy[yen + EN_DAMP] = p_damp
    dy[yen + EN_ROAD] = p_road
    dy[yen + EN_GRADE] = p_grade
    dy[yen + EN_SYNC] = 0.0


#: ``complete`` of :func:`evaluate`: ``_COMPLETE[RHS_ONLY]`` for the right-hand side,
#: ``_COMPLETE[FULL]`` for outputs, events and resets.  The flags live in an array so that
#: numba types them as run-time booleans: a literal True/False argument would make it
#: compile ``evaluate``, the plant's largest function, once per value.
_COMPLETE = np.array([False, True])
RHS_ONLY, FULL = 0, 1


@jit(inline="always")
def workspace(p):
    """The zeroed workspace of one plant call: ``N_ROWS`` rows (``R_*``) as wide as the
    larger of node count and element count (one allocation)."""
    return np.zeros((N_ROWS, max(int(p[H_N]), int(p[H_NF]), 1)))


@jit
def chain_rhs(t, y, u, p, dy):
    evaluate(t, y, u, p, dy, workspace(p), _COMPLETE[RHS_ONLY])


@jit
def _switching(p, f):
    """Does the plant lock and free this element (coulomb-robust, one-way, lossy)?"""
    return p[f + F_KIND] != FK_MODEL or int(p[f + F_CODE]) == CODE_ROBUST


@jit
def _shielded(p, y, e):
    """Is the locked brake-like element ``e`` a holder that another holder backs up (it
    is not the last one of its cluster, see :func:`_hold`)?  Its share is clipped at its
    capacity, so its break-away function would only touch zero, never cross it."""
    f = int(p[H_FE]) + e * FE_W
    if p[f + F_LOC] != LOC_BRAKE:
        return False
    m = int(p[f + F_IDX])
    a = _left(p, y, m)
    b = _right(p, y, m)
    last = -1
    nf = int(p[H_NF])
    for lossy_pass in range(2):
        for ee in range(nf):
            ff = int(p[H_FE]) + ee * FE_W
            if p[ff + F_LOC] != LOC_BRAKE or y[int(p[ff + F_YLK])] <= 0.5:
                continue
            if (p[ff + F_KIND] == FK_LOSSY) != (lossy_pass == 1):
                continue
            if a <= int(p[ff + F_IDX]) <= b:
                last = ee
    return last != e


@jit
def _element_events(p, y, e, W, g):
    """Event functions of element ``e`` into ``g`` (its slots)."""
    f = int(p[H_FE]) + e * FE_W
    nz = int(p[f + F_NZ])
    yz = int(p[f + F_YZ])
    kind = p[f + F_KIND]
    locked = y[int(p[f + F_YLK])] > 0.5
    if kind == FK_MODEL:
        pf = p[int(p[f + F_PAR]):]
        # a free element (scale 0) gets a vanishing capacity so that its break-away
        # function starts strictly positive and the first torque makes it cross
        sc = W[R_FS, e] if W[R_FS, e] > 0.0 else 1e-300
        friction_events(int(p[f + F_CODE]), pf, y[yz:yz + nz], W[R_FW, e], W[R_FE, e], sc, g)
        if locked and int(p[f + F_CODE]) == CODE_ROBUST and _shielded(p, y, e):
            g[1] = NO_EVENT
    elif kind == FK_ONE_WAY:
        if locked:
            g[0] = NO_EVENT
            g[1] = one_way_limit(p, f, W[R_FS, e]) - W[R_FE, e]
        else:
            g[0] = W[R_FW, e]
            g[1] = NO_EVENT
    else:
        if locked:
            lo, up = lossy_bounds(p, f, W[R_FA, e])
            g[0] = NO_EVENT
            g[1] = min(up - W[R_FE, e], W[R_FE, e] - lo) + LOSSY_TOL
        else:
            # just freed at zero speed, a round-off torque may have picked the direction:
            # the margin lets the first motion the other way register as a stop
            g[0] = y[yz] * W[R_FW, e] + 1e-300
            g[1] = NO_EVENT


@jit
def chain_events(t, y, u, p, g):
    W = workspace(p)
    nf = int(p[H_NF])
    # Only the switching elements (lock/free: robust Coulomb, one-way, lossy gear) need
    # the stick torques, i.e. a full evaluation; the events of the other models read the
    # slip speed alone.  The event functions are sampled four times per step, so this
    # saves ~40 % of the plant evaluations of a model-(6) launch.
    full = False
    for e in range(nf):
        f = int(p[H_FE]) + e * FE_W
        if int(p[f + F_NEV]) > 0 and _switching(p, f):
            full = True
    if full:
        dy = np.empty(y.size)
        evaluate(t, y, u, p, dy, W, _COMPLETE[FULL])
    else:
        for e in range(nf):
            W[R_FW, e] = rel_speed(p, y, e)
            W[R_FS, e] = element_scale(p, y, u, e, W[R_FW, e])
    for e in range(nf):
        f = int(p[H_FE]) + e * FE_W
        ne = int(p[f + F_NEV])
        if ne == 0:
            continue
        off = int(p[f + F_EV])
        _element_events(p, y, e, W, g[off:off + ne])
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
def _merge(p, y, a, b, W):
    """Give nodes a..b one common motion, conserving their momentum (or stop them)."""
    J0 = int(p[H_NODE])
    _speed_factors(p, y, a, b, W)
    if _locked_brake_node(p, y, a, b, -1) >= 0:
        for i in range(a, b + 1):
            y[i] = 0.0
        return
    num = 0.0
    den = 0.0
    for i in range(a, b + 1):
        jj = p[J0 + i * NODE_W + N_J]
        num += jj * W[R_S, i] * y[i]
        den += jj * W[R_S, i] * W[R_S, i]
    w = num / den
    for i in range(a, b + 1):
        y[i] = w * W[R_S, i]


@jit
def kinetic_energy(p, y):
    n = int(p[H_N])
    J0 = int(p[H_NODE])
    ke = 0.0
    for j in range(n):
        ke += 0.5 * p[J0 + j * NODE_W + N_J] * y[j] * y[j]
    return ke


@jit
def _element_reset(p, y, e, j, W):
    """Apply event ``j`` of element ``e`` to its own states.  Returns a
    :class:`~clutchsim.friction.base.FrictionReset` code (nothing, states changed, now
    stuck, freed)."""
    f = int(p[H_FE]) + e * FE_W
    nz = int(p[f + F_NZ])
    yz = int(p[f + F_YZ])
    kind = p[f + F_KIND]
    if kind == FK_MODEL:
        pf = p[int(p[f + F_PAR]):]
        return friction_reset(int(p[f + F_CODE]), pf, y[yz:yz + nz], W[R_FW, e], W[R_FE, e],
                              W[R_FS, e], j)
    if kind == FK_ONE_WAY:
        if j == 0:      # stop: the freewheel blocks unless the clutch is overloaded
            if W[R_FE, e] <= one_way_limit(p, f, W[R_FS, e]):
                y[yz] = 0.0
                return RESET_STUCK
            y[yz] = 1.0
            return RESET_NONE
        y[yz] = 1.0     # breakaway: slide forward
        return RESET_RELEASED
    lo, up = lossy_bounds(p, f, W[R_FA, e])
    if j == 0:          # stop: stick, or roll on in the direction of the torque
        if lo - LOSSY_TOL <= W[R_FE, e] <= up + LOSSY_TOL:
            y[yz] = 0.0
            return RESET_STUCK
        y[yz] = 1.0 if W[R_FE, e] > up else -1.0
        return RESET_CHANGED
    # breakaway: roll towards the limit that is reached (at the located event the stick
    # torque sits on it, within round-off)
    y[yz] = 1.0 if up - W[R_FE, e] <= W[R_FE, e] - lo else -1.0
    return RESET_RELEASED


@jit
def _restructure(p, y, e, action, W):
    """Lock (``RESET_STUCK``: merging the cluster and booking the lost kinetic energy) or
    free (``RESET_RELEASED``) element ``e``."""
    f = int(p[H_FE]) + e * FE_W
    if action == RESET_STUCK:
        y[int(p[f + F_YLK])] = 1.0
        ke0 = kinetic_energy(p, y)
        m = int(p[f + F_IDX])
        _merge(p, y, _left(p, y, m), _right(p, y, m), W)
        y[int(p[H_YEN]) + EN_SYNC] += ke0 - kinetic_energy(p, y)
    elif action == RESET_RELEASED:
        y[int(p[f + F_YLK])] = 0.0


@jit
def _settle(t, y, u, p, e0, W):
    """Event iteration after element ``e0`` switched (-1: after a gear shift): every other
    switching element is checked once at the same instant.  A locked one whose stick
    torque has left its limits breaks away; a sliding one that is now at (or past) zero
    slip - its stop coincided with ``e0``'s switch or was made exact by a merge - takes
    its stop decision."""
    nf = int(p[H_NF])
    any_switching = False
    for e in range(nf):
        if e != e0 and _switching(p, int(p[H_FE]) + e * FE_W):
            any_switching = True
    if not any_switching:
        return
    done = np.zeros(nf)
    if e0 >= 0:
        done[e0] = 1.0
    g = np.empty(4)
    # "zero slip": within round-off of the event location (a sliding element far from
    # zero slip, e.g. a free clutch, is left alone)
    vmax = 0.0
    for j in range(int(p[H_N])):
        vmax = max(vmax, abs(y[j]))
    w_tol = 1e-9 * (1.0 + vmax)
    for _ in range(nf + 1):
        dy = np.empty(y.size)
        evaluate(t, y, u, p, dy, W, _COMPLETE[FULL])
        hit = -1
        slot = -1
        for e in range(nf):
            f = int(p[H_FE]) + e * FE_W
            if done[e] > 0.0 or not _switching(p, f):
                continue
            mode = y[int(p[f + F_YZ])]
            if y[int(p[f + F_YLK])] > 0.5:
                _element_events(p, y, e, W, g)
                if g[1] < 0.0:
                    hit = e
                    slot = 1
                    break
            elif mode != 0.0 and mode * W[R_FW, e] <= 0.0 and abs(W[R_FW, e]) <= w_tol:
                hit = e
                slot = 0
                break
        if hit < 0:
            return
        done[hit] = 1.0
        action = _element_reset(p, y, hit, slot, W)
        if action == RESET_STUCK or action == RESET_RELEASED:
            _restructure(p, y, hit, action, W)


@jit
def chain_reset(t, y, u, p, k):
    W = workspace(p)
    dy = np.empty(y.size)
    evaluate(t, y, u, p, dy, W, _COMPLETE[FULL])
    n = int(p[H_N])
    nf = int(p[H_NF])
    yen = int(p[H_YEN])
    for e in range(nf):
        f = int(p[H_FE]) + e * FE_W
        ne = int(p[f + F_NEV])
        off = int(p[f + F_EV])
        if ne == 0 or k < off or k >= off + ne:
            continue
        action = _element_reset(p, y, e, k - off, W)
        if action == RESET_STUCK or action == RESET_RELEASED:
            _restructure(p, y, e, action, W)
        if _switching(p, f) and action != RESET_NONE:
            _settle(t, y, u, p, e, W)
        return _STATE_CHANGED if action != RESET_NONE else _CONTINUE
    if p[H_ENG] > 0.0 and k == int(p[H_EVSTALL]):
        return _FAIL
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
                _speed_factors(p, y, a, b, W)
                ref = y[b] / W[R_S, b]
                for i in range(a, b + 1):
                    y[i] = ref * W[R_S, i]
                y[yen + EN_SYNC] += ke0 - kinetic_energy(p, y)
                _settle(t, y, u, p, -1, W)
                return _STATE_CHANGED
    return _CONTINUE


@jit
def chain_outputs(t, y, u, p, out):
    """Coupling torques, element slip/scale/stick torque/power, engine, vehicle, energy."""
    n = int(p[H_N])
    nf = int(p[H_NF])
    W = workspace(p)
    dy = np.empty(y.size)
    evaluate(t, y, u, p, dy, W, _COMPLETE[FULL])
    i = 0
    for k in range(n - 1):
        out[i] = W[R_TAU, k]
        i += 1
    for e in range(nf):
        f = int(p[H_FE]) + e * FE_W
        out[i] = W[R_F, e]
        out[i + 1] = W[R_FW, e]
        if p[f + F_KIND] == FK_LOSSY:
            _lo, up = lossy_bounds(p, f, W[R_FA, e])
            out[i + 2] = up
        else:
            out[i + 2] = W[R_FS, e] * p[f + F_CAP]
        out[i + 3] = W[R_FE, e]
        out[i + 4] = W[R_F, e] * W[R_FW, e]
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
        fuel, drag, _dint = engine_torque(p, y, u, y[je])
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
