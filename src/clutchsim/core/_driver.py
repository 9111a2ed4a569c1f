"""The compiled integration loop shared by every method.

Owns step-size control, declared input breakpoints (hit exactly), event detection and
location on the dense output, reset maps, output recording, and the guards that make sure
no run spins forever: ``max_steps``, a wall-time budget, a step-size floor, and chatter
detection (too many events inside a short window).  Method-specific work is done by the
stepper modules; the plant is reached only through ``system_*`` (see ``system.py``).
"""

from __future__ import annotations

import math
import time

import numba
import numpy as np

from .._jit import jit
from ._dopri5 import dopri5_dense, dopri5_step
from ._rodas4 import jacobian, rodas4_dense, rodas4_step
from ._ros34pw2 import JAC_MAX_AGE, hermite_dense, ros34pw2_step
from .signals import eval_inputs
from .system import system_events, system_outputs, system_reset, system_rhs

# method codes
DOPRI5 = 0
RODAS4 = 1
ROS34PW2 = 2

# status codes (turned into words by result.py)
DONE = 0
EVENT_STOP = 1
EVENT_FAIL = 2
MAX_STEPS = 3
WALL_TIME = 4
STEP_COLLAPSE = 5
CHATTER = 6
NON_FINITE = 7

# float options
O_RTOL, O_ATOL, O_H0, O_HMAX, O_HMIN, O_WALL, O_CHATTER_WINDOW, O_DT_OUT, O_EVENT_TOL = range(9)
N_FOPT = 9
# int options
I_MAX_STEPS, I_CHATTER_N, I_MAX_OUTPUT, I_QUADRATURES = range(4)
N_IOPT = 3
# statistics
S_STEPS, S_REJECTED, S_RHS, S_JAC, S_LU, S_EVENTS, S_OUTPUT = range(7)
N_STATS = 7
# event functions are sampled at this many points per step (the last one is the step end)
N_SAMPLES = 4


@jit(nogil=False)
def _now():
    with numba.objmode(t="float64"):
        t = time.perf_counter()
    return t


@jit
def _norm(err, y, y_new, rtol, atol):
    n = err.shape[0]
    s = 0.0
    for i in range(n):
        sc = atol + rtol * max(abs(y[i]), abs(y_new[i]))
        e = err[i] / sc
        s += e * e
    return math.sqrt(s / max(n, 1))


@jit
def _first_nonfinite(x):
    for i in range(x.shape[0]):
        if not math.isfinite(x[i]):
            return i
    return -1


@jit
def dense_eval(method, dense, h, s, out):
    """State at fraction ``s`` in [0, 1] of the last accepted step of length ``h``."""
    n = out.shape[0]
    if method == DOPRI5:
        for i in range(n):
            out[i] = dense[0, i] + s * (dense[1, i] + s * (dense[2, i] + s * (
                dense[3, i] + s * dense[4, i])))
    else:
        s1 = 1.0 - s
        for i in range(n):
            out[i] = dense[0, i] * s1 + s * (dense[1, i] + s1 * (dense[2, i] + s * dense[3, i]))


@jit
def _crossed(g_old, g_new, direction):
    """Did g cross zero from ``g_old`` to ``g_new`` in ``direction`` (+1 upward, -1
    downward, 0 either)?"""
    return ((direction >= 0 and g_old < 0.0 and g_new >= 0.0)
            or (direction <= 0 and g_old > 0.0 and g_new <= 0.0))


@jit
def _grow(a, cap):
    b = np.empty((cap,) + a.shape[1:], dtype=a.dtype)
    b[:a.shape[0]] = a
    return b


@jit
def _push(buf, n_out, t, y, u, out):
    """Append one output row (time, state, inputs, outputs), growing the buffers."""
    ts, ys, us, outs = buf
    if n_out >= ts.shape[0]:
        cap = 2 * ts.shape[0]
        ts = _grow(ts, cap)
        ys = _grow(ys, cap)
        us = _grow(us, cap)
        outs = _grow(outs, cap)
    ts[n_out] = t
    ys[n_out] = y
    us[n_out] = u
    outs[n_out] = out
    return (ts, ys, us, outs), n_out + 1


@jit
def _log_event(log, ring, ch_n, ch_window, ne, t, k, action):
    """Append an event to the log; True when the last ``ch_n`` events fell inside
    ``ch_window`` seconds (chatter)."""
    ev_t, ev_k, ev_a = log
    if ne >= ev_t.shape[0]:
        ev_t = _grow(ev_t, 2 * ev_t.shape[0])
        ev_k = _grow(ev_k, 2 * ev_k.shape[0])
        ev_a = _grow(ev_a, 2 * ev_a.shape[0])
    ev_t[ne] = t
    ev_k[ne] = k
    ev_a[ne] = action
    chatter = False
    if ch_n > 0:
        slot = ne % ch_n
        if ne >= ch_n and t - ring[slot] <= ch_window:
            chatter = True
        ring[slot] = t
    return (ev_t, ev_k, ev_a), chatter


@jit
def _apply_event(tag, t, y, u, p, k, log, ring, ch_n, ch_window, stats):
    """Apply the reset map of event ``k`` at (t, y), log it and check for chatter.

    Returns (log, action, status): ``status`` is DONE when integration goes on, else the
    code that ends the run (CHATTER, EVENT_STOP or EVENT_FAIL)."""
    action = system_reset(tag, t, y, u, p, k)
    log, chatter = _log_event(log, ring, ch_n, ch_window, stats[S_EVENTS], t, k, action)
    stats[S_EVENTS] += 1
    if chatter:
        return log, action, CHATTER
    if action == 2:
        return log, action, EVENT_STOP
    if action == 3:
        return log, action, EVENT_FAIL
    return log, action, DONE


@jit
def _locate(tag, bank, p, method, dense, t, h, t_ref, k, ta, tb, ga, gb, tol, ytmp, u, g):
    """Time at which event ``k`` crosses zero inside [ta, tb] (Illinois regula falsi on the
    dense output).  Returns the right end of the final bracket, where g already has its new
    sign, so that integration restarts past the root and does not fire it again."""
    sign_a = ga > 0.0
    side = 0
    tol = max(tol, 4.0 * 2.220446049250313e-16 * abs(tb))
    for _ in range(200):
        if tb - ta <= tol:
            break
        tm = tb - gb * (tb - ta) / (gb - ga)
        if not (ta < tm < tb):      # also true for a NaN probe
            tm = 0.5 * (ta + tb)
        # keep the probe off the ends so that the bracket always shrinks
        tm = min(max(tm, ta + 0.01 * (tb - ta)), tb - 0.01 * (tb - ta))
        dense_eval(method, dense, h, (tm - t) / h, ytmp)
        eval_inputs(bank, tm, t_ref, u)
        system_events(tag, tm, ytmp, u, p, g)
        gm = g[k]
        if gm == 0.0 or (gm > 0.0) != sign_a:
            tb = tm
            gb = gm
            if side == 1:
                ga *= 0.5
            side = 1
        else:
            ta = tm
            ga = gm
            if side == -1:
                gb *= 0.5
            side = -1
    return tb


@jit
def integrate(tag, method, t0, t1, y0, p, bank, bps, ev_dir, n_outputs, fopt, iopt):
    """Integrate the plant ``tag`` from ``t0`` to ``t1``.  See ``simulate`` for the meaning.

    Returns (status, t_end, info_k, info_i, ts, ys, us, outs, ev_t, ev_k, ev_a, stats,
    h_smallest, wall_seconds)."""
    n = y0.shape[0]
    n_in = bank.n_channels
    n_ev = ev_dir.shape[0]
    rtol, atol = fopt[O_RTOL], fopt[O_ATOL]
    h_max = fopt[O_HMAX] if fopt[O_HMAX] > 0 else abs(t1 - t0)
    h_min_user = fopt[O_HMIN]
    wall = fopt[O_WALL]
    ch_window = fopt[O_CHATTER_WINDOW]
    dt_out = fopt[O_DT_OUT]
    ev_tol = fopt[O_EVENT_TOL]
    max_steps = iopt[I_MAX_STEPS]
    ch_n = iopt[I_CHATTER_N]
    max_output = iopt[I_MAX_OUTPUT]
    nd = n - iopt[I_QUADRATURES]    # states in the implicit solve (the rest: quadratures)
    order = 5 if method == DOPRI5 else (4 if method == RODAS4 else 3)
    inv_q = 1.0 / order     # exponent of the Rosenbrock step-size controller

    stats = np.zeros(N_STATS, dtype=np.int64)
    cap = 256
    ts = np.empty(cap)
    ys = np.empty((cap, n))
    us = np.empty((cap, n_in))
    outs = np.empty((cap, n_outputs))
    n_out = 0
    ecap = 16
    ev_t = np.empty(ecap)
    ev_k = np.empty(ecap, dtype=np.int64)
    ev_a = np.empty(ecap, dtype=np.int64)
    ring = np.full(max(ch_n, 1), -np.inf)

    y = y0.copy()
    y_new = np.empty(n)
    ytmp = np.empty(n)
    ftmp = np.empty(n)
    err = np.empty(n)
    f0 = np.empty(n)
    K = np.empty((7, n))
    dense = np.empty((5, n))
    J = np.zeros((n, n))     # quadrature columns stay zero
    M = np.empty((n, n))
    piv = np.empty(n, dtype=np.int64)
    dfdt = np.empty(n)
    u = np.zeros(n_in)
    out = np.zeros(n_outputs)
    g_old = np.empty(n_ev)
    g_new = np.empty(n_ev)
    g_tmp = np.empty(n_ev)
    g_samp = np.empty((N_SAMPLES, n_ev))

    t = t0
    status = DONE
    info_k = -1
    info_i = -1
    h_smallest = np.inf
    t_wall0 = _now()

    ib = 0
    while ib < bps.shape[0] and bps[ib] <= t0:
        ib += 1

    # initial point (inputs on the right of t0)
    eval_inputs(bank, t, t + 1e-300 + 1e-12 * abs(t), u)
    system_rhs(tag, t, y, u, p, f0)
    stats[S_RHS] += 1
    system_events(tag, t, y, u, p, g_old)
    system_outputs(tag, t, y, u, p, out)
    buf = (ts, ys, us, outs)
    buf, n_out = _push(buf, 0, t, y, u, out)
    log = (ev_t, ev_k, ev_a)
    next_out = t0 + dt_out
    bad = _first_nonfinite(f0)
    if _first_nonfinite(y) >= 0 or bad >= 0:
        i_bad = _first_nonfinite(y)
        ts, ys, us, outs = buf
        return (NON_FINITE, t, -1, i_bad if i_bad >= 0 else bad, ts[:n_out], ys[:n_out],
                us[:n_out], outs[:n_out], ev_t[:0], ev_k[:0], ev_a[:0], stats, h_smallest,
                _now() - t_wall0)

    # initial step (Hairer, Norsett & Wanner, Solving ODEs I, II.4)
    h = fopt[O_H0]
    if h <= 0:
        d0 = 0.0
        d1 = 0.0
        for i in range(n):
            sc = atol + rtol * abs(y[i])
            d0 += (y[i] / sc) ** 2
            d1 += (f0[i] / sc) ** 2
        d0 = math.sqrt(d0 / n)
        d1 = math.sqrt(d1 / n)
        h = 1e-6 if (d0 < 1e-5 or d1 < 1e-5) else 0.01 * d0 / d1
        h = min(h, h_max)
        for i in range(n):
            ytmp[i] = y[i] + h * f0[i]
        system_rhs(tag, t + h, ytmp, u, p, ftmp)
        stats[S_RHS] += 1
        d2 = 0.0
        for i in range(n):
            sc = atol + rtol * abs(y[i])
            d2 += ((ftmp[i] - f0[i]) / sc) ** 2
        d2 = math.sqrt(d2 / n) / h
        if max(d1, d2) <= 1e-15:
            h1 = max(1e-6, h * 1e-3)
        else:
            h1 = (0.01 / max(d1, d2)) ** (1.0 / (order + 1))
        h = min(100 * h, h1, h_max)

    f0_valid = True
    jac_valid = False
    jac_age = 0           # accepted steps since the Jacobian was formed (W-method reuse)
    rejected_last = False
    err_old = 1.0
    h_old = h
    first = True
    last_nonfinite = -1
    # A directional event whose function starts on its post-crossing side fires once at t0
    # (e.g. a stuck friction element loaded beyond its capacity from the start).
    check_jump = False
    for k in range(n_ev):
        if (ev_dir[k] == -1 and g_old[k] < 0.0) or (ev_dir[k] == 1 and g_old[k] > 0.0):
            g_old[k] = -g_old[k]
            check_jump = True

    while True:
        # ---- events caused by a jump of the inputs at a breakpoint (or by a reset) ----
        if check_jump:
            check_jump = False
            eval_inputs(bank, t, t + 1e-300 + 1e-12 * abs(t), u)
            system_events(tag, t, y, u, p, g_new)
            kk = -1
            for k in range(n_ev):
                if _crossed(g_old[k], g_new[k], ev_dir[k]):
                    kk = k
                    break
            for k in range(n_ev):
                g_old[k] = g_new[k]
            if kk >= 0:
                log, action, ended = _apply_event(tag, t, y, u, p, kk, log, ring, ch_n,
                                                  ch_window, stats)
                if ended != DONE:
                    status = ended
                    info_k = kk
                    break
                if action == 1:
                    f0_valid = False
                    jac_valid = False
                    system_events(tag, t, y, u, p, g_old)
                    check_jump = True  # a reset may itself arm another event
                    system_outputs(tag, t, y, u, p, out)
                    buf, n_out = _push(buf, n_out, t, y, u, out)
                continue

        if t >= t1:
            break
        if stats[S_STEPS] + stats[S_REJECTED] >= max_steps:
            status = MAX_STEPS
            break
        if (wall > 0 and ((stats[S_STEPS] + stats[S_REJECTED]) & 255) == 0
                and _now() - t_wall0 > wall):
            status = WALL_TIME
            break

        t_stop = t1
        if ib < bps.shape[0] and bps[ib] < t1:
            t_stop = bps[ib]
        h_floor = max(h_min_user, 1e-14 * max(1.0, abs(t)))
        if t_stop - t <= h_floor:
            # a breakpoint within round-off of the current time: we are on it
            t = t_stop
            if t_stop < t1:
                ib += 1
                while ib < bps.shape[0] and bps[ib] <= t:
                    ib += 1
                f0_valid = False
                jac_valid = False
                check_jump = True
            continue
        hit = False
        h = min(h, h_max)
        if t + h >= t_stop - h_floor:
            h = t_stop - t
            hit = True
        elif t + 2.0 * h > t_stop:
            h = 0.5 * (t_stop - t)  # avoid a sliver before the stop
        if h < h_floor:
            status = NON_FINITE if last_nonfinite >= 0 else STEP_COLLAPSE
            info_i = last_nonfinite
            break
        t_ref = t + 0.5 * h

        if not f0_valid:
            eval_inputs(bank, t, t_ref, u)
            system_rhs(tag, t, y, u, p, f0)
            stats[S_RHS] += 1
            f0_valid = True
            bad = _first_nonfinite(f0)
            if bad >= 0:
                status = NON_FINITE
                info_i = bad
                break

        ok = True
        if method == DOPRI5:
            for i in range(n):
                K[0, i] = f0[i]
            dopri5_step(tag, bank, p, t, y, h, t_ref, K, u, ytmp, y_new, err)
            stats[S_RHS] += 6
        else:
            if not jac_valid:
                stats[S_RHS] += jacobian(tag, bank, p, t, y, t_ref, f0, atol / rtol, u, ytmp,
                                         ftmp, J, dfdt, nd)
                stats[S_JAC] += 1
                jac_valid = True
                jac_age = 0
            if method == RODAS4:
                ok = rodas4_step(tag, bank, p, t, y, h, t_ref, f0, J, dfdt, M, piv, K, u,
                                 ytmp, ftmp, y_new, err, nd)
                stats[S_RHS] += 5
            else:
                ok = ros34pw2_step(tag, bank, p, t, y, h, t_ref, f0, J, dfdt, M, piv, K, u,
                                   ytmp, ftmp, y_new, err, nd)
                stats[S_RHS] += 3
            stats[S_LU] += 1
        if ok:
            bad = _first_nonfinite(y_new)
            if bad < 0:
                bad = _first_nonfinite(err)
            if bad >= 0:
                # name the state whose derivative went bad (a linear solve spreads a NaN
                # over every component, so the first bad entry of y_new may be innocent)
                eval_inputs(bank, t + h, t_ref, u)
                system_rhs(tag, t + h, y, u, p, ftmp)
                stats[S_RHS] += 1
                culprit = _first_nonfinite(ftmp)
                if culprit < 0 and method != DOPRI5:
                    culprit = _first_nonfinite(dfdt)
                    for i in range(n):
                        if culprit >= 0:
                            break
                        if _first_nonfinite(J[i]) >= 0:
                            culprit = i
                last_nonfinite = culprit if culprit >= 0 else bad
                ok = False
        if not ok:
            stats[S_REJECTED] += 1
            h *= 0.25
            rejected_last = True
            if jac_age > 0:
                jac_valid = False
            continue
        e = _norm(err, y, y_new, rtol, atol)
        if e > 1.0:
            stats[S_REJECTED] += 1
            if method == DOPRI5:
                h *= max(0.2, 0.9 * e ** (-0.2))
            else:
                h /= max(1.0 / 6.0, min(5.0, e ** inv_q / 0.9))
            rejected_last = True
            if jac_age > 0:
                jac_valid = False   # a W-method step failed with an aged Jacobian: refresh
            continue

        t_new = t_stop if hit else t + h
        if method == ROS34PW2:
            # f at the new point: the Hermite end slope and the next step's first stage.
            # A non-finite value there rejects the step like a non-finite stage would.
            eval_inputs(bank, t_new, t_ref, u)
            system_rhs(tag, t_new, y_new, u, p, K[5])
            stats[S_RHS] += 1
            bad = _first_nonfinite(K[5])
            if bad >= 0:
                last_nonfinite = bad
                stats[S_REJECTED] += 1
                h *= 0.25
                rejected_last = True
                continue

        # ---- accepted ----
        last_nonfinite = -1
        stats[S_STEPS] += 1
        h_smallest = min(h_smallest, h)
        if method == DOPRI5:
            dopri5_dense(K, y, h, dense)
        elif method == RODAS4:
            rodas4_dense(K, y, y_new, dense)
        else:
            hermite_dense(y, y_new, f0, K[5], h, dense)
            jac_age += 1
        # next step size
        if method == DOPRI5:
            fac = 10.0 if e == 0.0 else min(10.0, max(0.2, 0.9 * e ** (-0.2)))
            if rejected_last:
                fac = min(fac, 1.0)
            h_next = h * fac
        else:
            fac = max(1.0 / 6.0, min(5.0, e ** inv_q / 0.9))
            if not first:
                facpred = (h_old / h) * (e * e / err_old) ** inv_q / 0.9
                fac = max(fac, max(1.0 / 6.0, min(5.0, facpred)))
            h_next = h / fac
            if rejected_last:
                h_next = min(h_next, h)
            h_old = h
            err_old = max(0.01, e)
        first = False
        rejected_last = False

        # ---- events inside the step ----
        # g is sampled at interior points of the dense output as well as at the ends, so
        # that two crossings inside one step, or a crossing right after a reset that left
        # g exactly on zero, are not stepped over.
        eval_inputs(bank, t_new, t_ref, u)
        system_events(tag, t_new, y_new, u, p, g_new)
        k_first = -1
        t_first = t_new
        if n_ev > 0:
            for j in range(N_SAMPLES - 1):
                s = (j + 1.0) / N_SAMPLES
                dense_eval(method, dense, h, s, ytmp)
                eval_inputs(bank, t + s * h, t_ref, u)
                system_events(tag, t + s * h, ytmp, u, p, g_samp[j])
            for k in range(n_ev):
                g_samp[N_SAMPLES - 1, k] = g_new[k]
            for k in range(n_ev):
                ga = g_old[k]
                ta = t
                for j in range(N_SAMPLES):
                    gb = g_samp[j, k]
                    tb = t_new if j == N_SAMPLES - 1 else t + (j + 1.0) / N_SAMPLES * h
                    if ga == 0.0:       # on the surface (just reset): start from the next sign
                        ga = gb
                        ta = tb
                        continue
                    if _crossed(ga, gb, ev_dir[k]):
                        if tb > t_first and k_first >= 0:
                            break
                        te = _locate(tag, bank, p, method, dense, t, h, t_ref, k, ta, tb, ga,
                                     gb, ev_tol, ytmp, u, g_tmp)
                        if k_first < 0 or te < t_first:
                            t_first = te
                            k_first = k
                        break
                    if gb != 0.0:
                        ga = gb
                        ta = tb

        if k_first >= 0:
            te = t_first
            if te < t_new:
                dense_eval(method, dense, h, (te - t) / h, y)
            else:
                for i in range(n):
                    y[i] = y_new[i]
            if dt_out > 0:
                while next_out < te and n_out < max_output:
                    dense_eval(method, dense, h, (next_out - t) / h, ytmp)
                    eval_inputs(bank, next_out, t_ref, u)
                    system_outputs(tag, next_out, ytmp, u, p, out)
                    buf, n_out = _push(buf, n_out, next_out, ytmp, u, out)
                    next_out = t0 + (round((next_out - t0) / dt_out) + 1) * dt_out
            t = te
            eval_inputs(bank, t, t_ref, u)
            system_outputs(tag, t, y, u, p, out)
            buf, n_out = _push(buf, n_out, t, y, u, out)
            log, action, ended = _apply_event(tag, t, y, u, p, k_first, log, ring, ch_n,
                                              ch_window, stats)
            if ended != DONE:
                status = ended
                info_k = k_first
                break
            system_events(tag, t, y, u, p, g_old)
            f0_valid = False
            if method != ROS34PW2:
                jac_valid = False
            if action == 1:
                system_outputs(tag, t, y, u, p, out)
                buf, n_out = _push(buf, n_out, t, y, u, out)
                check_jump = True
            h = h_next
            continue

        # ---- no event: advance ----
        if dt_out > 0:
            while next_out <= t_new + 1e-12 * abs(t_new) and n_out < max_output:
                tq = min(next_out, t_new)
                dense_eval(method, dense, h, (tq - t) / h, ytmp)
                eval_inputs(bank, tq, t_ref, u)
                system_outputs(tag, tq, ytmp, u, p, out)
                buf, n_out = _push(buf, n_out, tq, ytmp, u, out)
                next_out = t0 + (round((next_out - t0) / dt_out) + 1) * dt_out
        elif n_out < max_output:
            eval_inputs(bank, t_new, t_ref, u)
            system_outputs(tag, t_new, y_new, u, p, out)
            buf, n_out = _push(buf, n_out, t_new, y_new, u, out)
        t = t_new
        for i in range(n):
            y[i] = y_new[i]
        for k in range(n_ev):
            g_old[k] = g_new[k]
        if method == DOPRI5:
            for i in range(n):
                f0[i] = K[6, i]
        elif method == RODAS4:
            eval_inputs(bank, t, t_ref, u)
            system_rhs(tag, t, y, u, p, f0)
            stats[S_RHS] += 1
            jac_valid = False
        else:
            for i in range(n):
                f0[i] = K[5, i]
            if jac_age >= JAC_MAX_AGE:
                jac_valid = False
        h = h_next
        if hit and t_stop < t1:
            ib += 1
            while ib < bps.shape[0] and bps[ib] <= t:
                ib += 1
            f0_valid = False
            jac_valid = False
            check_jump = True

    if dt_out > 0 and status == DONE and n_out < max_output and buf[0][n_out - 1] < t:
        eval_inputs(bank, t, t, u)
        system_outputs(tag, t, y, u, p, out)
        buf, n_out = _push(buf, n_out, t, y, u, out)
    stats[S_OUTPUT] = n_out
    ne = stats[S_EVENTS]
    ts, ys, us, outs = buf
    ev_t, ev_k, ev_a = log
    return (status, t, info_k, info_i, ts[:n_out], ys[:n_out], us[:n_out], outs[:n_out],
            ev_t[:ne], ev_k[:ne], ev_a[:ne], stats, h_smallest, _now() - t_wall0)
