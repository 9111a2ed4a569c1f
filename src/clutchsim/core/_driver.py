"""The compiled integration loop shared by every method.

Owns step-size control (a :class:`~clutchsim.core.controllers.StepController`, packed),
the Jacobian/iteration-matrix reuse policy, declared input breakpoints (hit exactly), event
detection and location on the dense output, reset maps, output recording, and the guards
that make sure no run spins forever: ``max_steps``, a wall-time budget, a step-size floor,
and chatter detection (too many events inside a short window).  The method is data (a
tableau of :mod:`clutchsim.core.methods`, packed into arrays); the steps are in
:mod:`._engine`; the plant is reached only through ``system_*`` (see ``system.py``).

Events are checked at the end of each step.  The event functions are sampled inside a step
only where a crossing could hide between two ends: on the first step after the start, an
event or a breakpoint (no history yet; a reset may leave ``g`` exactly on zero), when ``g``
starts exactly on zero, when its ends differ in sign (three crossings may lie between them,
and the earliest is the one to locate), or when ``g`` ends the step close to zero compared
with how much it changed over this step and the previous one (:func:`_may_hide_crossing`).  A
sampled ``g`` that keeps its sign but whose samples fit a parabola that turns inside the
step at no more than half its lowest sample has its least value searched on the dense output
(:func:`_valley`); where that is past zero, it becomes a sample, so that the two crossings
of a dip far narrower than the step (a freewheel that locks for microseconds) are found.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import jit
from ._borrow import borrowed
from ._clock import now as _now
from ._engine import (
    dense_coefficients,
    dense_eval,
    erk_step,
    inputs_at,
    jacobian,
    ros_step,
    stiffly_accurate_rows,
)
from ._linalg import invert_iteration_matrix
from .controllers import C_B1, C_B2, C_B3, C_KIND, C_MAX, C_MIN, C_SAFETY
from .methods import EXPLICIT
from .signals import SignalBank
from .status import Action, Code
from .system import system_events, system_factor, system_outputs, system_reset, system_rhs

# status codes (named in status.Code; plain ints here for the compiled code)
DONE = int(Code.DONE)
EVENT_STOP = int(Code.EVENT_STOP)
EVENT_FAIL = int(Code.EVENT_FAIL)
MAX_STEPS = int(Code.MAX_STEPS)
WALL_TIME = int(Code.WALL_TIME)
STEP_COLLAPSE = int(Code.STEP_COLLAPSE)
CHATTER = int(Code.CHATTER)
NON_FINITE = int(Code.NON_FINITE)
JAC_NON_FINITE = int(Code.JAC_NON_FINITE)
_STATE_CHANGED = int(Action.STATE_CHANGED)
_PASS = int(Action.PASS)
_STOP = int(Action.STOP)
_FAIL = int(Action.FAIL)

# float options
(O_RTOL, O_ATOL, O_H0, O_HMAX, O_HMIN, O_WALL, O_CHATTER_WINDOW, O_DT_OUT, O_EVENT_TOL,
 O_LU_REUSE) = range(10)
N_FOPT = 10
# int options; ``iopt[I_STOP]`` is the one the loop reads while it runs: set to 1 (by the
# signal handler of ``simulate``), the loop stops within 256 steps (its wall-time check)
(I_MAX_STEPS, I_CHATTER_N, I_MAX_OUTPUT, I_QUADRATURES, I_EXACT_JAC, I_JAC_MAX_AGE,
 I_FACTOR_SIZE, I_STOP) = range(8)
N_IOPT = 8
# method scalars
M_FAMILY, M_GAMMA, M_Q, M_DENSE, M_W, M_FSAL = range(6)
N_MOPT = 6
# statistics
S_STEPS, S_REJECTED, S_RHS, S_JAC, S_LU, S_EVENTS, S_OUTPUT, S_EV_CALLS = range(8)
N_STATS = 8
# event functions are sampled at this many points of a step that needs it (the last one
# is the step end)
N_SAMPLES = 4
#: a step in which a function placed on zero at once leaves it in its own direction is
#: taken again at this fraction of its size, at most MAX_PROBES times (see ``probes``)
PROBE = 0.1
MAX_PROBES = 4
#: golden-section probes of a valley of a sampled event function (0.618^40 of the step)
VALLEY_PROBES = 40
#: a valley counts as a crossing when it reaches past zero by more than this fraction of
#: the largest |g| in the step (less is round-off: a slip that starts at 0 after a reset
#: and reads 4e-21 with the wrong sign a moment later)
VALLEY_DEPTH = 1e-12


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


@jit(fastmath={"reassoc"})
def _all_finite(x):
    """Is every entry of the C-contiguous ``x`` (any shape) finite?  ``Σ x_i·0`` is 0, or
    NaN as soon as one entry is inf or NaN, in whatever order it is summed: reassociation
    (and only that: NaN and inf keep their IEEE meaning) lets the compiler vectorise the
    sum.  The fast path of the checks that :func:`_first_nonfinite` then places: the
    Jacobian's 256 entries of the default launch took ~0.1 ms per launch in a scalar loop
    with an exit per entry (perf, session 14), ~45 ns per check this way."""
    v = x.ravel()
    acc = 0.0
    for i in range(v.shape[0]):
        acc += v[i] * 0.0
    return acc == 0.0


@jit
def _crossed(g_old, g_new, direction):
    """Did g cross zero from ``g_old`` to ``g_new`` in ``direction`` (+1 upward, -1
    downward, 0 either)?"""
    return ((direction >= 0 and g_old < 0.0 and g_new >= 0.0)
            or (direction <= 0 and g_old > 0.0 and g_new <= 0.0))


#: a step is sampled inside when an event function ends it within this many times its
#: change over the last two steps of zero (see _may_hide_crossing)
NEAR_ZERO = 2.0


@jit
def _may_hide_crossing(g_prev, g0, g1):
    """Could g cross zero twice between two same-sign ends?  Only if it comes near zero:
    an excursion inside a step is of the size of g's change over a step (its slope times
    h; near a turning point its curvature times h², which the previous step's change
    measures), so a function whose ends stay further from zero than ``NEAR_ZERO`` times
    the change over this and the previous step cannot have crossed."""
    change = abs(g1 - g0) + abs(g0 - g_prev)
    return min(abs(g0), abs(g1)) <= NEAR_ZERO * change


@jit(inline="always")
def _round_off(y):
    """The round-off of a function of the state ``y``: 64 ulps of its largest entry."""
    scale = 1.0
    for i in range(y.shape[0]):
        scale = max(scale, abs(y[i]))
    return 64.0 * 2.220446049250313e-16 * scale


@jit(inline="always")
def _place(g_pre, g_post, y, placed):
    """Mark the event functions a reset placed on zero (``placed``), after snapping onto
    zero those it moved to within round-off of it: a lock's projection leaves its slip at
    ~1e-14 of zero, of either sign, and a break-away later starts the slide there.  On the
    far side of zero already, the slide's stop would never cross it and never be located
    (a freewheel released forward while a stiff neighbour drives it back slid backwards
    for good)."""
    tiny = _round_off(y)
    for k in range(g_post.shape[0]):
        if g_post[k] != g_pre[k] and g_post[k] != 0.0 and abs(g_post[k]) <= tiny:
            g_post[k] = 0.0
        placed[k] = 1.0 if g_post[k] == 0.0 and g_pre[k] != 0.0 else 0.0


# Growing copies in element loops: a slice assignment compiles numba's message for
# mismatched shapes with it (~2.3 s of the integrator's first compilation, measured).
@jit
def _grow(a, cap):
    """The 1-D ``a`` at the start of a new array of ``cap`` entries."""
    b = np.empty(cap, dtype=a.dtype)
    for i in range(a.shape[0]):
        b[i] = a[i]
    return b


@jit
def _grow_rows(a, cap):
    """The 2-D ``a`` in the first rows of a new array of ``cap`` rows."""
    b = np.empty((cap, a.shape[1]), dtype=a.dtype)
    for i in range(a.shape[0]):
        for j in range(a.shape[1]):
            b[i, j] = a[i, j]
    return b


@jit(inline="always")
def _row(rows, k, t, y, u, out):
    """Write output row ``k`` (time, state, inputs, outputs) into the borrowed ``rows``."""
    ts, ys, us, outs = rows
    # element loops: a row view per array would cost atomic reference counts per row
    ts[k] = t
    for i in range(y.shape[0]):
        ys[k, i] = y[i]
    for i in range(u.shape[0]):
        us[k, i] = u[i]
    for i in range(out.shape[0]):
        outs[k, i] = out[i]


@jit
def _more_rows(owners, cap):
    """Twice the output rows: ``(cap, owners, rows)`` with ``rows`` borrowed views of the
    new ``owners`` (which the caller keeps to the end)."""
    cap *= 2
    owners = (_grow(owners[0], cap), _grow_rows(owners[1], cap), _grow_rows(owners[2], cap),
              _grow_rows(owners[3], cap))
    return cap, owners, _borrow_rows(owners)


@jit(inline="always")
def _borrow_rows(owners):
    return (borrowed(owners[0]), borrowed(owners[1]), borrowed(owners[2]),
            borrowed(owners[3]))


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
    if action == _STOP:
        return log, action, EVENT_STOP
    if action == _FAIL:
        return log, action, EVENT_FAIL
    return log, action, DONE


@jit
def _locate(tag, bank, p, dkind, dense, t, h, t_ref, k, ta, tb, ga, gb, tol, ytmp, u, uc, g,
            stats):
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
        dense_eval(dkind, dense, (tm - t) / h, ytmp)
        inputs_at(bank, tm, t_ref, u, uc)
        system_events(tag, tm, ytmp, u, p, g)
        stats[S_EV_CALLS] += 1
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
def _g_at(tag, bank, p, dkind, dense, t, h, t_ref, tq, ytmp, u, uc, g, stats):
    """The event functions at ``tq`` inside the step [t, t + h], into ``g``."""
    dense_eval(dkind, dense, (tq - t) / h, ytmp)
    inputs_at(bank, tq, t_ref, u, uc)
    system_events(tag, tq, ytmp, u, p, g)
    stats[S_EV_CALLS] += 1


@jit
def _valley(tag, bank, p, dkind, dense, t, h, t_ref, k, sigma, lo, hi, depth, ytmp, u, uc,
            g, stats):
    """``(time, sigma·g_k there)`` where ``sigma·g_k`` is least in [lo, hi] (golden section
    on the dense output; it stops at the first probe below ``-depth``)."""
    r = 0.6180339887498949
    x1 = hi - r * (hi - lo)
    x2 = lo + r * (hi - lo)
    _g_at(tag, bank, p, dkind, dense, t, h, t_ref, x1, ytmp, u, uc, g, stats)
    f1 = sigma * g[k]
    _g_at(tag, bank, p, dkind, dense, t, h, t_ref, x2, ytmp, u, uc, g, stats)
    f2 = sigma * g[k]
    for _ in range(VALLEY_PROBES):
        if f1 < -depth or f2 < -depth or math.isnan(f1) or math.isnan(f2):
            break
        if f1 < f2:
            hi = x2
            x2 = x1
            f2 = f1
            x1 = hi - r * (hi - lo)
            _g_at(tag, bank, p, dkind, dense, t, h, t_ref, x1, ytmp, u, uc, g, stats)
            f1 = sigma * g[k]
        else:
            lo = x1
            x1 = x2
            f1 = f2
            x2 = lo + r * (hi - lo)
            _g_at(tag, bank, p, dkind, dense, t, h, t_ref, x2, ytmp, u, uc, g, stats)
            f2 = sigma * g[k]
    if f1 <= f2 or math.isnan(f2):
        return x1, f1
    return x2, f2


@jit
def _vertex(x0, y0, x1, y1, x2, y2):
    """``(x, y)`` of the lowest point of the parabola through three points (``y = inf``
    where it opens downward or is a line)."""
    d1 = (y1 - y0) / (x1 - x0)
    d2 = (y2 - y1) / (x2 - x1)
    a = (d2 - d1) / (x2 - x0)
    if not a > 0.0:
        return x1, math.inf
    x = 0.5 * (x0 + x1) - d1 / (2.0 * a)
    return x, y0 + d1 * (x - x0) + a * (x - x0) * (x - x1)


@jit
def _sharpen(tag, bank, p, dkind, dense, t, h, t_ref, g_old, g_samp, ts, ns, ytmp, u, uc,
             g, stats):
    """Replace a sample by the bottom of a valley of an event function that dips past zero
    between samples of one sign (see the module docstring); once per step.  The values are
    g at t (index -1) and at the samples ``ts[0 .. ns-1]`` (the last is the step end).  The
    valley is searched when the parabola through the lowest value and its two neighbours
    (at an end of the step: its next two) turns inside their span at no more than half
    that lowest value; its bottom counts when it is past zero by more than VALLEY_DEPTH of
    the largest |g| in the step."""
    for k in range(g_old.shape[0]):
        if g_old[k] == 0.0:
            continue
        sigma = 1.0 if g_old[k] > 0.0 else -1.0
        low = -1
        big = abs(g_old[k])
        for j in range(ns):
            big = max(big, abs(g_samp[j, k]))
            if not sigma * g_samp[j, k] > 0.0:
                low = -2                # a sign change: the scan finds it
                break
            if sigma * g_samp[j, k] < sigma * (g_old[k] if low == -1 else g_samp[low, k]):
                low = j
        if low == -2:
            continue
        c = min(max(low, 0), ns - 2)    # the middle one of three neighbouring points
        x0 = t if c == 0 else ts[c - 1]
        y0 = sigma * (g_old[k] if c == 0 else g_samp[c - 1, k])
        xv, yv = _vertex(x0, y0, ts[c], sigma * g_samp[c, k], ts[c + 1],
                         sigma * g_samp[c + 1, k])
        b = sigma * (g_old[k] if low == -1 else g_samp[low, k])
        if not (x0 < xv < ts[c + 1] and yv <= 0.5 * b):
            continue
        lo = t if low <= 0 else ts[low - 1]
        hi = ts[low] if low == ns - 1 else ts[low + 1]
        depth = VALLEY_DEPTH * big
        tq, fq = _valley(tag, bank, p, dkind, dense, t, h, t_ref, k, sigma, lo, hi, depth,
                         ytmp, u, uc, g, stats)
        if fq < -depth:
            i = min(max(low, 0), ns - 2)      # an interior sample inside [lo, hi]
            ts[i] = tq
            _g_at(tag, bank, p, dkind, dense, t, h, t_ref, tq, ytmp, u, uc, g_samp[i],
                  stats)
            return


@jit
def _starting_step(tag, t, y, f0, u, p, ytmp, ftmp, atol, rtol, q, h_max, stats):
    """A first step size for the state ``y`` at ``t`` with its derivative ``f0`` (inputs
    ``u`` set): Hairer, Norsett & Wanner, Solving ODEs I, II.4 (one more right-hand side,
    at an Euler step, estimates the second derivative)."""
    n = y.shape[0]
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
        h1 = (0.01 / max(d1, d2)) ** (1.0 / (q + 1.0))
    return min(100 * h, h1, h_max)


@jit
def _controller_factor(ctrl, q, e, e_old, e_older, h, h_old, first):
    """``h_new / h`` after an accepted step with error norm ``e`` (see controllers.py)."""
    kind = ctrl[C_KIND]
    safety, fmin, fmax = ctrl[C_SAFETY], ctrl[C_MIN], ctrl[C_MAX]
    ee = max(e, 1e-10)
    fac = safety * ee ** (-1.0 / q)
    if kind == 1.0 and not first:       # predictive (Gustafsson)
        pred = safety * (h / h_old) * (e_old / (ee * ee)) ** (1.0 / q)
        fac = min(fac, pred)
    elif kind == 2.0:                   # pid filter
        fac = safety * ee ** (-ctrl[C_B1] / q)
        if not first:
            fac *= max(e_old, 1e-10) ** (-ctrl[C_B2] / q) * max(e_older, 1e-10) ** (
                -ctrl[C_B3] / q)
    if e == 0.0:
        fac = fmax
    return min(fmax, max(fmin, fac))


@jit(inline="always")
def _block(ws, o, rows, cols):
    """Rows × cols of ``ws`` from offset ``o`` as a borrowed C-contiguous matrix."""
    return borrowed(ws[o:o + rows * cols].reshape((rows, cols)))


@jit
def _release(ws, iws):
    """The owners of the loop's borrowed work arrays are used for the last time here."""


@jit
def integrate(tag, tab, mopt, ctrl, t0, t1, y0, p, bank, bps, ev_dir, n_outputs, fopt, iopt):
    """Integrate the plant ``tag`` from ``t0`` to ``t1`` with the method ``tab``/``mopt``.
    See ``simulate`` for the meaning.

    Returns (status, t_end, info_k, info_i, ts, ys, us, outs, ev_t, ev_k, ev_a, stats,
    h_smallest, wall_seconds)."""
    n = y0.shape[0]
    n_in = bank.n_channels
    n_ev = ev_dir.shape[0]
    explicit = mopt[M_FAMILY] == EXPLICIT
    gamma = mopt[M_GAMMA]
    q = mopt[M_Q]
    dkind = int(mopt[M_DENSE])
    w_method = mopt[M_W] != 0.0
    fsal = mopt[M_FSAL] != 0.0
    s_stages = tab[2].shape[0]
    rtol, atol = fopt[O_RTOL], fopt[O_ATOL]
    h_max = fopt[O_HMAX] if fopt[O_HMAX] > 0 else abs(t1 - t0)
    h_min_user = fopt[O_HMIN]
    wall = fopt[O_WALL]
    ch_window = fopt[O_CHATTER_WINDOW]
    dt_out = fopt[O_DT_OUT]
    ev_tol = fopt[O_EVENT_TOL]
    lu_band = fopt[O_LU_REUSE] if w_method else 0.0
    max_steps = iopt[I_MAX_STEPS]
    ch_n = iopt[I_CHATTER_N]
    max_output = iopt[I_MAX_OUTPUT]
    nd = n - iopt[I_QUADRATURES]    # states in the implicit solve (the rest: quadratures)
    exact_jac = iopt[I_EXACT_JAC] != 0
    jac_max_age = iopt[I_JAC_MAX_AGE] if w_method else 0
    n_factor = iopt[I_FACTOR_SIZE]  # floats of the plant's own factors (0: none)

    stats = np.zeros(N_STATS, dtype=np.int64)
    # Output rows: written through borrowed views (a row written through the owning arrays
    # cost ~35 ns in reference counts and growth copies, ~0.07 ms of the default launch),
    # sized for the output grid and 256 more rows (events), doubled when full.
    cap = 256
    if dt_out > 0:
        cap += int(min((t1 - t0) / dt_out + 2.0, 1e6, max(max_output, 0)))
    owners = (np.empty(cap), np.empty((cap, n)), np.empty((cap, n_in)),
              np.empty((cap, n_outputs)))
    rows = _borrow_rows(owners)
    ecap = 16
    ev_t = np.empty(ecap)
    ev_k = np.empty(ecap, dtype=np.int64)
    ev_a = np.empty(ecap, dtype=np.int64)

    # The arguments and the work arrays as borrowed views (_borrow.py): the loop passes
    # them to the plant and to its helpers a few hundred times per step, and counting
    # their references was a quarter of its time.  The owners of the work arrays (`ws`,
    # `iws`) live until the end (see the last lines).
    p = borrowed(p)
    bank = SignalBank(borrowed(bank.data), bank.n_channels)
    bps = borrowed(bps)
    ev_dir = borrowed(ev_dir)
    tab = (borrowed(tab[0]), borrowed(tab[1]), borrowed(tab[2]), borrowed(tab[3]),
           borrowed(tab[4]), borrowed(tab[5]), borrowed(tab[6]))
    n_k = max(s_stages, 1)
    n_ring = max(ch_n, 1)
    ws = np.zeros(9 * n + n_k * n + 5 * n + 2 * n * n + n_in + 2 + n_outputs
                  + (7 + N_SAMPLES) * n_ev + N_SAMPLES + n_ring + max(n_factor, 1))
    iws = np.zeros(n + n_k + 1, dtype=np.int64)
    vec = _block(ws, 0, 9, n)
    y, y_new, ytmp, ftmp, f1, err, f0, dfdt, y_ev = (vec[0], vec[1], vec[2], vec[3], vec[4],
                                                     vec[5], vec[6], vec[7], vec[8])
    for i in range(n):     # (an element loop, as in _grow)
        y[i] = y0[i]
    o = 9 * n
    K = _block(ws, o, n_k, n)
    o += n_k * n
    dense = _block(ws, o, 5, n)
    o += 5 * n
    J = _block(ws, o, n, n)     # quadrature columns stay zero
    o += n * n
    M = _block(ws, o, n, n)
    o += n * n
    gv = _block(ws, o, 7, n_ev)
    g_old, g_new, g_prev, g_tmp, g_seg, g_pre = gv[0], gv[1], gv[2], gv[3], gv[4], gv[5]
    # 1.0 where the last reset placed an event function on zero (it was elsewhere before
    # the reset), 0.0 where it is on zero because it crossed there or not on zero at all
    placed = gv[6]
    o += 7 * n_ev
    g_samp = _block(ws, o, N_SAMPLES, n_ev)
    o += N_SAMPLES * n_ev
    ts = borrowed(ws[o:o + N_SAMPLES])     # the times of the samples of g in a step
    o += N_SAMPLES
    u = borrowed(ws[o:o + n_in])
    o += n_in
    uc = borrowed(ws[o:o + 2])     # (t, t_ref) of the inputs held in u
    uc[:] = np.nan
    o += 2
    out = borrowed(ws[o:o + n_outputs])
    o += n_outputs
    ring = borrowed(ws[o:o + n_ring])
    ring[:] = -np.inf
    o += n_ring
    F = borrowed(ws[o:o + max(n_factor, 1)])    # the plant's factors of I/(γh) − J
    structured = False      # the stages solve with F (else with the inverse in M)
    piv = borrowed(iws[:n])     # pivot rows: scratch of the inversion
    ext = borrowed(iws[n:])     # the tableau's stiffly accurate rows, once per run
    if not explicit:
        stiffly_accurate_rows(tab[0], tab[4], ext)

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
    t_right = t + 1e-300 + 1e-12 * abs(t)
    inputs_at(bank, t, t_right, u, uc)
    system_rhs(tag, t, y, u, p, f0)
    stats[S_RHS] += 1
    system_events(tag, t, y, u, p, g_old)
    system_outputs(tag, t, y, u, p, out)
    _row(rows, 0, t, y, u, out)
    n_out = 1
    log = (ev_t, ev_k, ev_a)
    next_out = t0 + dt_out
    bad = _first_nonfinite(f0)
    if _first_nonfinite(y) >= 0 or bad >= 0:
        i_bad = _first_nonfinite(y)
        ts, ys, us, outs = owners
        return (NON_FINITE, t, -1, i_bad if i_bad >= 0 else bad, ts[:n_out], ys[:n_out],
                us[:n_out], outs[:n_out], ev_t[:0], ev_k[:0], ev_a[:0], stats, h_smallest,
                _now() - t_wall0)

    # initial step (Hairer, Norsett & Wanner, Solving ODEs I, II.4)
    h = fopt[O_H0]
    if h <= 0:
        h = _starting_step(tag, t, y, f0, u, p, ytmp, ftmp, atol, rtol, q, h_max, stats)

    f0_valid = True
    jac_valid = False
    jac_age = 0           # accepted steps since the Jacobian was formed (W-method reuse)
    lu_h = 0.0            # step size the inverse in M was formed for (0: none)
    rejected_last = False
    err_old = 1.0
    err_older = 1.0
    h_old = h
    first = True
    last_nonfinite = -1
    have_history = False  # g_prev at t_prev is a valid step end before g_old at t
    restart = False       # a step ended at an event: cap the next by a starting step
    # A step that finds an event inside it is taken again, ending where the event was
    # located (counted as a rejected step).  Its state then has the method's accuracy;
    # the dense output that located the event is an order less accurate and not stiffly
    # accurate, and restarting from it put that error into the state at every event that
    # ends a step (1,443 times the tolerance on a stiff Prothero-Robinson problem:
    # tests/core/test_event_state_accuracy.py).  The event itself is then found at the
    # end of the shorter step or just after it.  Once per event: ``may_retry`` comes back
    # when an event is applied.  Not for an event whose last reset passed (Action.PASS:
    # the step goes on past it and keeps its own state; model (6)'s velocity zero
    # crossings), which ``passes`` remembers, nor within 1e3 step-size floors of the
    # step's start (a chatter's events: the chatter guard ends those).
    may_retry = True
    t_event_stop = np.inf
    # A function a reset placed on zero whose first sample lies past it in its own
    # direction is due at once (below), unless the step hid a first move the other way:
    # a freewheel broken away at its limit beside a stiff neighbour slides forward for a
    # microsecond before the neighbour turns its slip back.  Due at once, the stop locks
    # it at the same instant, at the limit, and the two alternate there.  The step is
    # first taken again at a tenth of its size, up to MAX_PROBES times.
    probes = 0
    passes = np.zeros(max(n_ev, 1), dtype=np.bool_)
    # A directional event whose function starts on its post-crossing side fires once at t0
    # (e.g. a stuck friction element loaded beyond its capacity from the start).
    check_jump = False
    for k in range(n_ev):
        if (ev_dir[k] == -1 and g_old[k] < 0.0) or (ev_dir[k] == 1 and g_old[k] > 0.0):
            g_old[k] = -g_old[k]
            check_jump = True
        # one that starts exactly on zero was placed there by the initial state, as by a
        # reset: if it leaves in its own direction at once, it is due at the start (a dog
        # clutch pushed in at t = 0 with its slip exactly at the window's edge, moving in,
        # never engaged: taken as starting from the next sign, it never crossed)
        placed[k] = 1.0 if g_old[k] == 0.0 else 0.0

    while True:
        # ---- events caused by a jump of the inputs at a breakpoint (or by a reset) ----
        if check_jump:
            check_jump = False
            have_history = False
            t_right = t + 1e-300 + 1e-12 * abs(t)
            inputs_at(bank, t, t_right, u, uc)
            system_events(tag, t, y, u, p, g_new)
            stats[S_EV_CALLS] += 1
            kk = -1
            for k in range(n_ev):
                if _crossed(g_old[k], g_new[k], ev_dir[k]):
                    kk = k
                    break
            if kk < 0:
                tiny = _round_off(y)
                for k in range(n_ev):
                    # a function a reset placed on zero stays there (_place)
                    if not (placed[k] != 0.0 and g_old[k] == 0.0 and abs(g_new[k]) <= tiny):
                        g_old[k] = g_new[k]
            else:
                log, action, ended = _apply_event(tag, t, y, u, p, kk, log, ring, ch_n,
                                                  ch_window, stats)
                if ended != DONE:
                    status = ended
                    info_k = kk
                    break
                if action == _STATE_CHANGED:
                    f0_valid = False
                    jac_valid = False
                    lu_h = 0.0
                    system_events(tag, t, y, u, p, g_tmp)
                    _place(g_new, g_tmp, y, placed)
                    system_outputs(tag, t, y, u, p, out)
                    if n_out == cap:
                        cap, owners, rows = _more_rows(owners, cap)
                    _row(rows, n_out, t, y, u, out)
                    n_out += 1
                else:
                    for k in range(n_ev):
                        g_tmp[k] = g_new[k]
                        placed[k] = 0.0
                # Several events may be due at one instant (at t0, or at an input jump):
                # each fires in turn.  One that crossed with the others and is still on its
                # far side after this reset keeps its old value, so that the next pass
                # fires it; the rest start from the values the reset left.
                for k in range(n_ev):
                    if (k != kk and _crossed(g_old[k], g_new[k], ev_dir[k])
                            and _crossed(g_old[k], g_tmp[k], ev_dir[k])):
                        check_jump = True
                    else:
                        g_old[k] = g_tmp[k]
                if action == _STATE_CHANGED:
                    check_jump = True  # a reset may itself arm another event
                continue

        if t >= t1:
            break
        if stats[S_STEPS] + stats[S_REJECTED] >= max_steps:
            status = MAX_STEPS
            break
        if ((stats[S_STEPS] + stats[S_REJECTED]) & 255) == 0 and (
                iopt[I_STOP] != 0 or (wall > 0 and _now() - t_wall0 > wall)):
            # a stop request (an interrupt) ends the run as the wall-time budget does;
            # its caller discards the run and delivers the signal
            status = WALL_TIME
            break

        t_stop = t1
        if ib < bps.shape[0] and bps[ib] < t1:
            t_stop = bps[ib]
        h_floor = max(h_min_user, 1e-14 * max(1.0, abs(t)))
        if t_event_stop - t <= h_floor:
            t_event_stop = np.inf       # reached (or passed by an event before it)
        stop_at_event = t_event_stop < t_stop
        if stop_at_event:
            t_stop = t_event_stop
        if t_stop - t <= h_floor:
            # a breakpoint within round-off of the current time: we are on it
            t = t_stop
            if t_stop < t1:
                ib += 1
                while ib < bps.shape[0] and bps[ib] <= t:
                    ib += 1
                f0_valid = False
                jac_valid = False
                lu_h = 0.0
                check_jump = True
            continue
        if restart:
            # after a reset the dynamics may be other ones (a contact closed, an element
            # locked): the step size the old dynamics allowed is capped by a starting
            # step for the new state, as at t0; else a step past a stiff contact's whole
            # bounce damps it out and locates its release far too late
            restart = False
            inputs_at(bank, t, t + 0.5 * min(h, t_stop - t), u, uc)
            system_rhs(tag, t, y, u, p, f0)
            stats[S_RHS] += 1
            f0_valid = _first_nonfinite(f0) < 0
            if f0_valid:
                h = min(h, _starting_step(tag, t, y, f0, u, p, ytmp, ftmp, atol, rtol, q,
                                          h_max, stats))
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
            inputs_at(bank, t, t_ref, u, uc)
            system_rhs(tag, t, y, u, p, f0)
            stats[S_RHS] += 1
            f0_valid = True
            bad = _first_nonfinite(f0)
            if bad >= 0:
                status = NON_FINITE
                info_i = bad
                break

        ok = True
        if explicit:
            for i in range(n):
                K[0, i] = f0[i]
            stats[S_RHS] += erk_step(tag, bank, p, t, y, h, t_ref, K, u, uc, ytmp, y_new,
                                     err, tab)
        else:
            if not jac_valid:
                stats[S_RHS] += jacobian(tag, bank, p, t, y, t_ref, f0, atol / rtol, u, uc,
                                         ytmp, ftmp, J, dfdt, nd, exact_jac)
                stats[S_JAC] += 1
                jac_valid = True
                jac_age = 0
                lu_h = 0.0
                if exact_jac and not _all_finite(J):
                    for i in range(n):
                        bad = _first_nonfinite(J[i])
                        if bad >= 0:
                            last_nonfinite = bad
                            break
                    if last_nonfinite >= 0:
                        status = JAC_NON_FINITE
                        info_i = last_nonfinite
                        break
            if lu_h == 0.0 or abs(h / lu_h - 1.0) > lu_band:
                c = 1.0 / (gamma * h)
                structured = n_factor > 0 and system_factor(tag, c, J, F) != 0
                ok = structured or invert_iteration_matrix(J, c, M, piv, nd)
                stats[S_LU] += 1
                lu_h = h if ok else 0.0
            if ok:
                # with a reused inverse (W-methods only) the stages solve with
                # I/(γ·lu_h) − J, i.e. with W = J + (1/(γh) − 1/(γ·lu_h))·I: a W-method
                # keeps its order with any W
                stats[S_RHS] += ros_step(tag, bank, p, t, y, h, t_ref, f0, dfdt, M, F,
                                         structured, K, u, uc, ytmp, ftmp, y_new, err, nd,
                                         tab, ext)
        if ok:
            bad = -1
            if not (_all_finite(y_new) and _all_finite(err)):
                bad = _first_nonfinite(y_new)
                if bad < 0:
                    bad = _first_nonfinite(err)
            if bad >= 0:
                # name the state whose derivative went bad (a linear solve spreads a NaN
                # over every component, so the first bad entry of y_new may be innocent)
                inputs_at(bank, t + h, t_ref, u, uc)
                system_rhs(tag, t + h, y, u, p, ftmp)
                stats[S_RHS] += 1
                culprit = _first_nonfinite(ftmp)
                if culprit < 0 and not explicit:
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
            lu_h = 0.0
            continue
        e = _norm(err, y, y_new, rtol, atol)
        if e > 1.0:
            stats[S_REJECTED] += 1
            h *= max(ctrl[C_MIN], ctrl[C_SAFETY] * e ** (-1.0 / q))
            rejected_last = True
            if jac_age > 0:
                jac_valid = False   # a W-method step failed with an aged Jacobian: refresh
            lu_h = 0.0
            continue

        t_new = t_stop if hit else t + h
        # f at the new point: the next step's first stage, the Hermite end slope.  A
        # non-finite value there rejects the step like a non-finite stage would.
        if explicit and fsal:
            for i in range(n):
                f1[i] = K[s_stages - 1, i]
        else:
            inputs_at(bank, t_new, t_ref, u, uc)
            system_rhs(tag, t_new, y_new, u, p, f1)
            stats[S_RHS] += 1
            bad = -1 if _all_finite(f1) else _first_nonfinite(f1)
            if bad >= 0:
                last_nonfinite = bad
                stats[S_REJECTED] += 1
                h *= 0.25
                rejected_last = True
                lu_h = 0.0
                continue

        # ---- accepted ----
        last_nonfinite = -1
        stats[S_STEPS] += 1
        h_smallest = min(h_smallest, h)
        if w_method:
            jac_age += 1
        # next step size
        fac = _controller_factor(ctrl, q, e, err_old, err_older, h, h_old, first)
        h_next = h * fac
        if rejected_last:
            h_next = min(h_next, h)
        h_old = h
        err_older = err_old
        err_old = max(0.01, e) if ctrl[C_KIND] == 1.0 else max(e, 1e-10)
        first = False
        rejected_last = False

        # ---- events inside the step ----
        sample = False
        if n_ev > 0:
            inputs_at(bank, t_new, t_ref, u, uc)
            system_events(tag, t_new, y_new, u, p, g_new)
            stats[S_EV_CALLS] += 1
            sample = not have_history
            for k in range(n_ev):
                if sample:
                    break
                # g on zero (a reset left it there), ends of other signs (three crossings
                # may lie between them, and the earliest is the one to locate), or near
                # zero for its rate of change
                sample = g_old[k] == 0.0 or (g_old[k] > 0.0) != (g_new[k] > 0.0) or \
                    _may_hide_crossing(g_prev[k], g_old[k], g_new[k])
        # The continuous extension, at one place for all that reads it (it is inlined:
        # four copies cost 7.6 s more of the first compilation, measured): the event
        # samples, and the location of a crossing and the rows before it, which only a
        # sampled step can have (unsampled, every g kept its non-zero sign); the output
        # rows of the step.
        if sample or (dt_out > 0 and next_out <= t_new + 1e-12 * abs(t_new)
                      and n_out < max_output):
            dense_coefficients(dkind, tab, K, y, y_new, f0, f1, h, dense)
        if n_ev > 0:
            ns = N_SAMPLES if sample else 1
            if sample:
                for j in range(ns - 1):
                    s = (j + 1.0) / ns
                    ts[j] = t + s * h
                    dense_eval(dkind, dense, s, ytmp)
                    inputs_at(bank, t + s * h, t_ref, u, uc)
                    system_events(tag, t + s * h, ytmp, u, p, g_samp[j])
                    stats[S_EV_CALLS] += 1
            ts[ns - 1] = t_new
            for k in range(n_ev):
                g_samp[ns - 1, k] = g_new[k]
                g_seg[k] = g_old[k]
            if sample:
                _sharpen(tag, bank, p, dkind, dense, t, h, t_ref, g_old, g_samp, ts, ns, ytmp,
                         u, uc, g_tmp, stats)
            # Scan [t_seg, t_new] for the earliest crossing.  An event whose reset passes
            # (Action.PASS: nothing changed and the right-hand side is smooth there) is
            # logged and the scan goes on past it in the same step; any other action
            # ends the step at the event.
            t_seg = t
            ended = DONE
            action = _PASS
            retry = False
            pending = False
            te = t_new
            while True:
                k_first = -1
                t_first = t_new
                for k in range(n_ev):
                    ga = g_seg[k]
                    ta = t_seg
                    for j in range(ns):
                        tb = ts[j]
                        if tb <= t_seg:
                            continue
                        gb = g_samp[j, k]
                        if ga == 0.0:   # on the surface (a crossing or a reset left it there)
                            if placed[k] != 0.0 and ev_dir[k] * gb > 0.0:
                                # a reset placed it there, and it leaves in its own
                                # direction: it is already past it (a freewheel released
                                # forward whose slip turns backwards at once, pushed by a
                                # stiffer neighbour, must lock again), so the event is due
                                # where the scan starts.  (One that crossed and landed on
                                # zero goes on from the next sign.)
                                if k_first < 0 or ta < t_first:
                                    t_first = ta
                                    k_first = k
                                break
                            ga = gb     # otherwise it starts from the next sign
                            ta = tb
                            continue
                        if _crossed(ga, gb, ev_dir[k]):
                            # a bracket that starts after the earliest crossing found so
                            # far cannot hold an earlier one (one that ends after it can)
                            if ta >= t_first and k_first >= 0:
                                break
                            te = _locate(tag, bank, p, dkind, dense, t, h, t_ref, k, ta, tb,
                                         ga, gb, ev_tol, ytmp, u, uc, g_tmp, stats)
                            if k_first < 0 or te < t_first:
                                t_first = te
                                k_first = k
                            break
                        if gb != 0.0:
                            ga = gb
                            ta = tb
                if k_first < 0:
                    break
                te = t_first
                if (te == t and t_seg == t and placed[k_first] != 0.0 and probes < MAX_PROBES
                        and PROBE * h > 1e3 * h_floor):
                    retry = True                # a shorter probe of the same step
                    break
                if may_retry and not passes[k_first] and t_seg == t and te < t_new and \
                        te - t > max(1e-3 * h, 1e3 * h_floor):
                    retry = True                # the step is taken again (may_retry)
                    break
                if te < t_new:
                    dense_eval(dkind, dense, (te - t) / h, y_ev)
                else:
                    for i in range(n):
                        y_ev[i] = y_new[i]
                if dt_out > 0:
                    while next_out < te and n_out < max_output:
                        dense_eval(dkind, dense, (next_out - t) / h, ytmp)
                        inputs_at(bank, next_out, t_ref, u, uc)
                        system_outputs(tag, next_out, ytmp, u, p, out)
                        if n_out == cap:
                            cap, owners, rows = _more_rows(owners, cap)
                        _row(rows, n_out, next_out, ytmp, u, out)
                        n_out += 1
                        next_out = t0 + (round((next_out - t0) / dt_out) + 1) * dt_out
                inputs_at(bank, te, t_ref, u, uc)
                system_outputs(tag, te, y_ev, u, p, out)
                if n_out == cap:
                    cap, owners, rows = _more_rows(owners, cap)
                _row(rows, n_out, te, y_ev, u, out)
                n_out += 1
                # g before the reset: an event that crossed together with this one (two
                # twin clutches slipping through zero at one instant, within the location
                # tolerance) and is still past zero after the reset keeps its value from
                # before the crossing, so that it fires next, at te (the scan below when
                # the reset passes, else the check of events due at one instant)
                system_events(tag, te, y_ev, u, p, g_pre)
                log, action, ended = _apply_event(tag, te, y_ev, u, p, k_first, log, ring,
                                                  ch_n, ch_window, stats)
                passes[k_first] = action == _PASS
                for k in range(n_ev):
                    g_tmp[k] = g_seg[k]
                system_events(tag, te, y_ev, u, p, g_seg)
                stats[S_EV_CALLS] += 2
                _place(g_pre, g_seg, y_ev, placed)
                pending = False
                for k in range(n_ev):
                    if (k != k_first and g_tmp[k] != 0.0
                            and _crossed(g_tmp[k], g_pre[k], ev_dir[k])
                            and _crossed(g_tmp[k], g_seg[k], ev_dir[k])):
                        g_seg[k] = g_tmp[k]
                        pending = True
                if ended != DONE or action != _PASS:
                    break
                t_seg = te
            if retry:
                # take the step again, to the located time (or, for a probe, a tenth of it)
                stats[S_STEPS] -= 1
                stats[S_REJECTED] += 1
                if te == t:
                    probes += 1
                    h = PROBE * h
                    continue
                may_retry = False
                t_event_stop = te
                h = te - t
                continue
            probes = 0
            if k_first >= 0:
                may_retry = True
                t_event_stop = np.inf
            if k_first >= 0 and ended != DONE:
                status = ended
                info_k = k_first
                break
            if k_first >= 0:
                # the step ends at the event: restart from the state the reset left
                t = te
                for i in range(n):
                    y[i] = y_ev[i]
                for k in range(n_ev):
                    g_old[k] = g_seg[k]
                have_history = False
                f0_valid = False
                restart = True
                if not w_method:
                    jac_valid = False
                if action == _STATE_CHANGED:
                    system_outputs(tag, t, y, u, p, out)
                    if n_out == cap:
                        cap, owners, rows = _more_rows(owners, cap)
                    _row(rows, n_out, t, y, u, out)
                    n_out += 1
                    check_jump = True
                if pending:
                    check_jump = True
                h = h_next
                continue

        # ---- no event: advance ----
        if dt_out > 0:
            while next_out <= t_new + 1e-12 * abs(t_new) and n_out < max_output:
                tq = min(next_out, t_new)
                dense_eval(dkind, dense, (tq - t) / h, ytmp)
                inputs_at(bank, tq, t_ref, u, uc)
                system_outputs(tag, tq, ytmp, u, p, out)
                if n_out == cap:
                    cap, owners, rows = _more_rows(owners, cap)
                _row(rows, n_out, tq, ytmp, u, out)
                n_out += 1
                next_out = t0 + (round((next_out - t0) / dt_out) + 1) * dt_out
        elif n_out < max_output:
            inputs_at(bank, t_new, t_ref, u, uc)
            system_outputs(tag, t_new, y_new, u, p, out)
            if n_out == cap:
                cap, owners, rows = _more_rows(owners, cap)
            _row(rows, n_out, t_new, y_new, u, out)
            n_out += 1
        t = t_new
        for i in range(n):
            y[i] = y_new[i]
            f0[i] = f1[i]
        for k in range(n_ev):
            g_prev[k] = g_old[k]
            g_old[k] = g_new[k]
            placed[k] = 0.0
        have_history = True
        if not w_method or jac_age >= jac_max_age:
            jac_valid = False
        h = h_next
        if hit and t_stop < t1 and not stop_at_event:
            ib += 1
            while ib < bps.shape[0] and bps[ib] <= t:
                ib += 1
            f0_valid = False
            jac_valid = False
            lu_h = 0.0
            check_jump = True

    if dt_out > 0 and status == DONE and n_out < max_output and rows[0][n_out - 1] < t:
        inputs_at(bank, t, t, u, uc)
        system_outputs(tag, t, y, u, p, out)
        if n_out == cap:
            cap, owners, rows = _more_rows(owners, cap)
        _row(rows, n_out, t, y, u, out)
        n_out += 1
    stats[S_OUTPUT] = n_out
    ne = stats[S_EVENTS]
    ts, ys, us, outs = owners
    ev_t, ev_k, ev_a = log
    _release(ws, iws)
    return (status, t, info_k, info_i, ts[:n_out], ys[:n_out], us[:n_out], outs[:n_out],
            ev_t[:ne], ev_k[:ne], ev_a[:ne], stats, h_smallest, _now() - t_wall0)
