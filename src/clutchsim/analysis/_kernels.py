"""Compiled launch metrics: the formulas of :mod:`clutchsim.analysis.launch_quality` and
:func:`clutchsim.analysis.judder.judder_amplitude` as numba functions over sampled arrays,
and :func:`launch_kernel`, which computes every metric and warning test of a driveline run
in one call (:mod:`clutchsim.analysis.launch_metrics`).

The arithmetic is numpy's and scipy's, operation for operation, so the values are the
same to the last bit where the operations are the same:

* sums are numpy's pairwise summation (:func:`pairwise_sum`: blocks of 8 partial sums up
  to 128 elements, halves above), so ``np.sum``, ``np.mean`` and ``np.trapezoid`` give the
  same bits;
* :func:`interp` is ``np.interp`` (the interval is the last sample at or before the point,
  so a repeated time takes the sample after it; the same slope and NaN fall-back);
* :func:`sosfilt` is ``scipy.signal.sosfilt`` written out: each second-order section in
  transposed direct form II, ``y = b0 x + z0; z0 = b1 x - a1 y + z1; z1 = b2 x - a2 y``.
  The coefficients are designed once per filter step by scipy
  (``launch_quality._wd_sos``: ISO 2631-1 W_d by the bilinear transform;
  ``launch_quality._lowpass_sos``: the jerk's 2nd-order Butterworth) and passed in;
* the judder amplitude's band power is summed from a direct DFT of the bins in the band
  (Parseval) instead of numpy's FFT and its inverse: the same quantity, rounded
  differently (about 1e-15 relative), as are its trend's two dot products (numpy calls
  BLAS ``ddot``).

A value that does not exist (no lock-up, no engagement) is NaN here; the Python wrappers
turn it into None.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import jit

#: slots of the array :func:`launch_kernel` returns
(K_ENGAGE, K_LOCKUP, K_VDV, K_AW_RMS, K_JERK_PEAK, K_JERK_RMS, K_SHOCK, K_E_DENS, K_P_DENS,
 K_DIP, K_FLARE, K_SLIP_ENERGY, K_OMEGA_MIN, K_JUDDER, K_HELD, K_RING, K_RING_T0,
 K_RING_AMP, K_RING_CAP, K_RING_WMAX, K_CAP_MAX, K_ENGAGED, K_W_MIN_ENG, K_W_MAX_ENG,
 K_THETA_MAX, K_RING_N_EV, K_RING_EV_FIRST, K_RING_EV_LAST, K_OMEGA_MAX, N_K) = range(30)

#: coarsest step of the filters' uniform grid [s] (``launch_quality.FILTER_DT_MAX_S``)
FILTER_DT_MAX_S = 2.5e-3
#: the acceleration's level before lock-up is its mean over this time before it [s]
SHOCK_REF_S = 0.02


@jit
def _block_sum(a, lo, n):
    """numpy's pairwise summation of ``a[lo:lo + n]`` for ``n <= 128``."""
    if n < 8:
        res = 0.0
        for i in range(lo, lo + n):
            res += a[i]
        return res
    r0, r1, r2, r3 = a[lo], a[lo + 1], a[lo + 2], a[lo + 3]
    r4, r5, r6, r7 = a[lo + 4], a[lo + 5], a[lo + 6], a[lo + 7]
    i = 8
    m = n - n % 8
    while i < m:
        j = lo + i
        r0 += a[j]
        r1 += a[j + 1]
        r2 += a[j + 2]
        r3 += a[j + 3]
        r4 += a[j + 4]
        r5 += a[j + 5]
        r6 += a[j + 6]
        r7 += a[j + 7]
        i += 8
    res = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    while i < n:
        res += a[lo + i]
        i += 1
    return res


@jit
def extreme(x, largest):
    """``np.max(x)`` (``largest``) or ``np.min(x)`` of a non-empty ``x``, as numba computes
    them: the first NaN, else the first of the largest (smallest) values."""
    m = x[0]
    if math.isnan(m):
        return m
    for i in range(1, x.size):
        v = x[i]
        if math.isnan(v):
            return v
        if (v > m) if largest else (v < m):
            m = v
    return m


@jit
def amax_abs_dev(x, ref):
    """``np.max(np.abs(x - ref))`` of a non-empty ``x``."""
    d = np.empty(x.size)
    for i in range(x.size):
        d[i] = abs(x[i] - ref)
    return extreme(d, True)


@jit
def fill(n, v):
    """``np.full(n, v)``."""
    out = np.empty(n)
    for i in range(n):
        out[i] = v
    return out


@jit
def pairwise_sum(a, lo, n):
    """``np.sum(a[lo:lo + n])`` with numpy's pairwise summation (same bits): blocks of at
    most 128, above that the sum of the two halves (the first a multiple of 8 long),
    evaluated with an explicit stack (numba's cache cannot hold a recursive function)."""
    s_lo = np.empty(64, dtype=np.int64)
    s_n = np.empty(64, dtype=np.int64)
    s_state = np.empty(64, dtype=np.int64)
    s_val = np.empty(64)
    s_lo[0], s_n[0], s_state[0] = lo, n, 0
    top = 1
    ret = 0.0
    while top > 0:
        f = top - 1
        m = s_n[f]
        if m <= 128:
            ret = _block_sum(a, s_lo[f], m)
            top -= 1
            continue
        n2 = m // 2
        n2 -= n2 % 8
        if s_state[f] == 0:             # the first half
            s_state[f] = 1
            s_lo[top], s_n[top], s_state[top] = s_lo[f], n2, 0
            top += 1
        elif s_state[f] == 1:           # its sum is in ret: now the second half
            s_val[f] = ret
            s_state[f] = 2
            s_lo[top], s_n[top], s_state[top] = s_lo[f] + n2, m - n2, 0
            top += 1
        else:
            ret = s_val[f] + ret
            top -= 1
    return ret


@jit
def trapezoid(y, x):
    """``np.trapezoid(y, x)`` (same bits)."""
    n = x.size
    if n < 2:
        return 0.0
    buf = np.empty(n - 1)
    for i in range(n - 1):
        buf[i] = (x[i + 1] - x[i]) * (y[i + 1] + y[i]) / 2.0
    return pairwise_sum(buf, 0, n - 1)


@jit
def interp(x, xp, fp):
    """``np.interp(x, xp, fp)`` for ``x`` not decreasing (same bits)."""
    n, m = x.size, xp.size
    out = np.empty(n)
    j = 0
    js = -1             # the interval whose slope is in `slope` (one division per interval:
    slope = 0.0         # the filter grid has ~4 points per output row)
    for i in range(n):
        xv = x[i]
        if math.isnan(xv):
            out[i] = xv
            continue
        if xv < xp[0]:
            out[i] = fp[0]
            continue
        if xv > xp[m - 1]:
            out[i] = fp[m - 1]
            continue
        if j > 0 and xp[j] > xv:    # x decreased: search again
            j = 0
        while j < m - 1 and xp[j + 1] <= xv:
            j += 1
        if j == m - 1 or xp[j] == xv:
            out[i] = fp[j]
        else:
            if j != js:
                slope = (fp[j + 1] - fp[j]) / (xp[j + 1] - xp[j])
                js = j
            r = slope * (xv - xp[j]) + fp[j]
            if math.isnan(r):
                r = slope * (xv - xp[j + 1]) + fp[j + 1]
                if math.isnan(r) and fp[j] == fp[j + 1]:
                    r = fp[j]
            out[i] = r
    return out


@jit
def grid_index(t, last):
    """Indices of ``t`` with repeated times collapsed onto the last sample at each time
    (``last``; the value after a reset) or the first (the value before it)."""
    n = t.size
    keep = np.empty(n, dtype=np.int64)
    c = 0
    for i in range(n):
        if last:
            ok = i == n - 1 or t[i + 1] > t[i]
        else:
            ok = i == 0 or t[i] > t[i - 1]
        if ok:
            keep[c] = i
            c += 1
    return keep[:c]


@jit
def take(x, idx):
    out = np.empty(idx.size)
    for i in range(idx.size):
        out[i] = x[idx[i]]
    return out


@jit
def uniform_grid(t, x, dt_s, max_samples):
    """``launch_quality.uniform_grid`` on a collapsed grid ``t`` (no repeated times)."""
    span = t[-1] - t[0] if t.size else 0.0
    dt = max(dt_s, min(span / max_samples, FILTER_DT_MAX_S))
    n = math.floor(span / dt + 1e-9) + 1
    tu = np.empty(n)
    for i in range(n):
        tu[i] = t[0] + dt * float(i)
    return tu, interp(tu, t, x)


@jit(inline="always")
def _section(b0, b1, b2, a1, a2, x, z0, z1):
    """One second-order section in transposed direct form II: ``(y, z0', z1')``."""
    y = b0 * x + z0
    return y, b1 * x - a1 * y + z1, b2 * x - a2 * y


@jit
def sosfilt(sos, zi, x0, x):
    """``scipy.signal.sosfilt(sos, x, zi=zi * x0)[0]``.  One and three sections (the jerk
    low-pass, W_d) keep their state in registers: the recursion is latency-bound, and a
    state kept in memory adds a store and a load to every step's chain; the operations,
    and so the bits, are the same."""
    ns = sos.shape[0]
    y = np.empty(x.size)
    if ns == 1:
        b0, b1, b2, a1, a2 = sos[0, 0], sos[0, 1], sos[0, 2], sos[0, 4], sos[0, 5]
        z0, z1 = zi[0, 0] * x0, zi[0, 1] * x0
        for i in range(x.size):
            y[i], z0, z1 = _section(b0, b1, b2, a1, a2, x[i], z0, z1)
        return y
    if ns == 3:
        p0, p1, p2, pa1, pa2 = sos[0, 0], sos[0, 1], sos[0, 2], sos[0, 4], sos[0, 5]
        q0, q1, q2, qa1, qa2 = sos[1, 0], sos[1, 1], sos[1, 2], sos[1, 4], sos[1, 5]
        r0, r1, r2, ra1, ra2 = sos[2, 0], sos[2, 1], sos[2, 2], sos[2, 4], sos[2, 5]
        u0, u1 = zi[0, 0] * x0, zi[0, 1] * x0
        v0, v1 = zi[1, 0] * x0, zi[1, 1] * x0
        w0, w1 = zi[2, 0] * x0, zi[2, 1] * x0
        for i in range(x.size):
            xc, u0, u1 = _section(p0, p1, p2, pa1, pa2, x[i], u0, u1)
            xc, v0, v1 = _section(q0, q1, q2, qa1, qa2, xc, v0, v1)
            y[i], w0, w1 = _section(r0, r1, r2, ra1, ra2, xc, w0, w1)
        return y
    z = np.empty((ns, 2))
    for s in range(ns):
        z[s, 0] = zi[s, 0] * x0
        z[s, 1] = zi[s, 1] * x0
    for i in range(x.size):
        xc = x[i]
        for s in range(ns):
            xn = sos[s, 0] * xc + z[s, 0]
            z[s, 0] = sos[s, 1] * xc - sos[s, 4] * xn + z[s, 1]
            z[s, 1] = sos[s, 2] * xc - sos[s, 5] * xn
            xc = xn
        y[i] = xc
    return y


@jit
def _odd_extension(sos, x):
    """``(ext, edge)``: ``x`` with scipy's odd extension of its default length at both
    ends (``scipy.signal.sosfiltfilt``)."""
    ns = sos.shape[0]
    zb = 0
    za = 0
    for s in range(ns):
        if sos[s, 2] == 0:
            zb += 1
        if sos[s, 5] == 0:
            za += 1
    edge = 3 * (2 * ns + 1 - min(zb, za))
    n = x.size
    ext = np.empty(n + 2 * edge)
    for i in range(edge):
        ext[i] = 2 * x[0] - x[edge - i]
        ext[edge + n + i] = 2 * x[n - 1] - x[n - 2 - i]
    for i in range(n):     # (a slice assignment compiles numba's shape-mismatch message)
        ext[edge + i] = x[i]
    return ext, edge


@jit
def _reversed(x):
    """``x[::-1]`` as a new contiguous array: :func:`sosfilt` then has one specialisation
    (a reversed view compiled it a second time, ~1.2 s)."""
    n = x.size
    out = np.empty(n)
    for i in range(n):
        out[i] = x[n - 1 - i]
    return out


@jit
def filtfilt(sos, zi, x):
    """``launch_quality._filtfilt``: ``scipy.signal.sosfiltfilt`` (odd extension of its
    default length, each pass started from the steady state of its first sample)."""
    ext, edge = _odd_extension(sos, x)
    n = x.size
    y = sosfilt(sos, zi, ext[0], ext)
    y = sosfilt(sos, zi, y[-1], _reversed(y))
    return y[::-1][edge:edge + n]


@jit
def _wd_and_lowpass(wd, wzi, lp, lzi, x):
    """``(sosfilt(wd, wzi, x[0], x), filtfilt(lp, lzi, x))`` with the W_d pass and the
    low-pass's forward pass in one loop when W_d has three sections and the low-pass one
    (the default filters; ``x`` longer than the low-pass's edge): both recursions are
    latency-bound, and side by side the CPU overlaps them (~26 µs of the launch kernel's
    ~240).  The operations of each filter are those of :func:`sosfilt`, so the bits are
    the same."""
    n = x.size
    if not (wd.shape[0] == 3 and lp.shape[0] == 1 and n > 9):
        return sosfilt(wd, wzi, x[0], x), filtfilt(lp, lzi, x)
    ext, edge = _odd_extension(lp, x)
    m = ext.size
    b0, b1, b2, a1, a2 = lp[0, 0], lp[0, 1], lp[0, 2], lp[0, 4], lp[0, 5]
    z0, z1 = lzi[0, 0] * ext[0], lzi[0, 1] * ext[0]
    p0, p1, p2, pa1, pa2 = wd[0, 0], wd[0, 1], wd[0, 2], wd[0, 4], wd[0, 5]
    q0, q1, q2, qa1, qa2 = wd[1, 0], wd[1, 1], wd[1, 2], wd[1, 4], wd[1, 5]
    r0, r1, r2, ra1, ra2 = wd[2, 0], wd[2, 1], wd[2, 2], wd[2, 4], wd[2, 5]
    u0, u1 = wzi[0, 0] * x[0], wzi[0, 1] * x[0]
    v0, v1 = wzi[1, 0] * x[0], wzi[1, 1] * x[0]
    w0, w1 = wzi[2, 0] * x[0], wzi[2, 1] * x[0]
    yw = np.empty(n)
    yl = np.empty(m)
    for i in range(edge):
        yl[i], z0, z1 = _section(b0, b1, b2, a1, a2, ext[i], z0, z1)
    for i in range(n):
        xi = x[i]                   # == ext[edge + i]
        yl[edge + i], z0, z1 = _section(b0, b1, b2, a1, a2, xi, z0, z1)
        xc, u0, u1 = _section(p0, p1, p2, pa1, pa2, xi, u0, u1)
        xc, v0, v1 = _section(q0, q1, q2, qa1, qa2, xc, v0, v1)
        yw[i], w0, w1 = _section(r0, r1, r2, ra1, ra2, xc, w0, w1)
    for i in range(edge + n, m):
        yl[i], z0, z1 = _section(b0, b1, b2, a1, a2, ext[i], z0, z1)
    back = sosfilt(lp, lzi, yl[-1], _reversed(yl))
    return yw, back[::-1][edge:edge + n]


@jit
def _filter_grid(t, a, dt_s, max_samples):
    """``a`` on the uniform filter grid: ``(tu, au)`` (repeated times: the last sample)."""
    idx = grid_index(t, True)
    return uniform_grid(take(t, idx), take(a, idx), dt_s, max_samples)


@jit
def _weighted_on(t, tu, au, sos, zi):
    return interp(t, tu, sosfilt(sos, zi, au[0], au))


@jit
def weighted(t, a, dt_s, max_samples, sos, zi):
    """``launch_quality.weighted_acceleration_mps2`` (``sos``, ``zi``: W_d for the grid's
    step ``tu[1] - tu[0]``)."""
    if t.size < 2 or t[-1] <= t[0]:
        return fill(t.size, 0.0)
    tu, au = _filter_grid(t, a, dt_s, max_samples)
    return _weighted_on(t, tu, au, sos, zi)


@jit
def _gradient(tu, af):
    """``np.gradient(af, dt)`` on the uniform grid ``tu`` (at least 3 points)."""
    n = tu.size
    dt = tu[1] - tu[0]
    g = np.empty(n)
    g[0] = (af[1] - af[0]) / dt
    g[n - 1] = (af[n - 1] - af[n - 2]) / dt
    for i in range(1, n - 1):
        g[i] = (af[i + 1] - af[i - 1]) / (2.0 * dt)
    return g


@jit
def _jerk_on(tu, au, sos, zi):
    n = tu.size
    if n < 3:
        return fill(n, 0.0)
    af = filtfilt(sos, zi, au) if n > 3 * (2 * sos.shape[0] + 1) else au
    return _gradient(tu, af)


@jit
def jerk(t, a, dt_s, max_samples, sos, zi):
    """``launch_quality.jerk_mps3``: ``(tu, jerk)`` (``sos``, ``zi``: the low-pass for the
    grid's step)."""
    tu, au = _filter_grid(t, a, dt_s, max_samples)
    return tu, _jerk_on(tu, au, sos, zi)


@jit
def rms(t, x):
    """``launch_quality.rms``."""
    span = t[-1] - t[0] if t.size > 1 else 0.0
    if span <= 0:
        return 0.0
    x2 = np.empty(x.size)
    for i in range(x.size):
        x2[i] = x[i] * x[i]
    return math.sqrt(trapezoid(x2, t) / span)


@jit
def vdv(t, aw):
    """``launch_quality.vdv_mps175``."""
    if t.size < 2:
        return 0.0
    a4 = np.empty(aw.size)
    for i in range(aw.size):
        a2 = aw[i] * aw[i]
        a4[i] = a2 * a2
    return trapezoid(a4, t) ** 0.25


@jit
def engagement_start(t, torque, threshold, rel):
    """``launch_quality.engagement_start_s`` (``threshold`` NaN: the share ``rel`` of the
    largest magnitude); NaN when it never engages."""
    idx = grid_index(t, True)
    n = idx.size
    if n == 0:
        return np.nan
    tg = take(t, idx)
    tq = np.empty(n)
    top = -np.inf
    for i in range(n):
        tq[i] = abs(torque[idx[i]])
        top = max(top, tq[i])
    if not top > 0:
        return np.nan
    thr = rel * top if math.isnan(threshold) else threshold
    for i in range(n):
        if tq[i] > thr:
            if i == 0:
                return tg[0]
            return tg[i - 1] + (tg[i] - tg[i - 1]) * (thr - tq[i - 1]) / (tq[i] - tq[i - 1])
    return np.nan


@jit
def _event_in(ev, lo, hi):
    out = np.nan
    for e in ev:
        if e > lo and e <= hi:
            out = e
    return out


@jit
def _sign(x):
    if x > 0:
        return 1.0
    if x < 0:
        return -1.0
    if x == 0:
        return 0.0
    return np.nan


@jit
def _searchsorted(a, v):
    """``np.searchsorted(a, v)`` (side 'left', NaN sorted last) on a sorted ``a``."""
    lo, hi = 0, a.size
    v_nan = math.isnan(v)
    while lo < hi:
        mid = lo + ((hi - lo) >> 1)
        m = a[mid]
        if m < v or (v_nan and not math.isnan(m)):
            lo = mid + 1
        else:
            hi = mid
    return lo


@jit
def lockup_time(t_s, slip, engaged, locked, ev, lock_slip):
    """``launch_quality.lockup_time_s`` (``engaged`` 0/1, ``locked`` empty when the model
    has no flag); NaN without lock-up."""
    idx = grid_index(t_s, True)
    n = idx.size
    if n < 2:
        return np.nan
    t, w = take(t_s, idx), take(slip, idx)
    if locked.size:
        for i in range(1, n):
            if locked[idx[i]] > 0.5 and not locked[idx[i - 1]] > 0.5:
                e = _event_in(ev, t[i - 1], t[i])
                return t[i] if math.isnan(e) else e
        if locked[idx[0]] > 0.5 and locked[idx[n - 1]] > 0.5:
            return t[0]
    a = np.empty(n)
    for i in range(n):
        a[i] = abs(w[i])
    if not engaged[idx[n - 1]] > 0.5 or a[n - 1] >= lock_slip:
        return np.nan
    start = -1
    first = -1                      # np.argmax of the engaged flags: the first set
    for i in range(n):
        if engaged[idx[i]] > 0.5:
            if first < 0:
                first = i
            if a[i] >= lock_slip:
                start = i
    slipped = start >= 0
    if not slipped:
        start = max(first, 0)
    if w[start] == 0:
        return t[start]
    s0 = _sign(w[start])
    for j in range(start, n - 1):
        s = _sign(w[j + 1])
        if s != s0 or math.isnan(s0):
            tz = t[j] + (t[j + 1] - t[j]) * w[j] / (w[j] - w[j + 1])
            k = _searchsorted(t, tz)
            e = _event_in(ev, t[max(k - 1, 0)], t[min(k, n - 1)])
            return tz if math.isnan(e) else e
    if not slipped:
        return t[start]
    j = start + 1
    return t[start] + (t[j] - t[start]) * (a[start] - lock_slip) / (a[start] - a[j])


@jit
def _window(t, lo, hi):
    """``[lo, t inside (lo, hi), hi]``."""
    m = 2
    for v in t:
        if v > lo and v < hi:
            m += 1
    tw = np.empty(m)
    tw[0] = lo
    c = 1
    for v in t:
        if v > lo and v < hi:
            tw[c] = v
            c += 1
    tw[m - 1] = hi
    return tw


@jit
def _window_mean(t, x, lo, hi):
    tw = _window(t, lo, hi)
    return trapezoid(interp(tw, t, x), tw) / (hi - lo)


@jit
def lockup_shock(t_s, a, t_lock, window):
    """``launch_quality.lockup_shock_mps2``: the largest deviation ``|a(t) − a_ref|`` for
    ``t`` in ``[t_lock, t_lock + window]`` (the linear interpolant: its samples and the
    window's ends), ``a_ref`` the mean of ``a`` over the :data:`SHOCK_REF_S` before lock-up
    (the value before the event at the lock-up sample); NaN without lock-up."""
    if math.isnan(t_lock):
        return np.nan
    il, ib = grid_index(t_s, True), grid_index(t_s, False)
    t, al = take(t_s, il), take(a, il)
    tb, ab = take(t_s, ib), take(a, ib)
    lo, hi = max(t_lock - SHOCK_REF_S, t[0]), min(t_lock + window, t[-1])
    if not (lo < t_lock < hi):
        return np.nan
    ref = _window_mean(tb, ab, lo, t_lock)
    aw = interp(_window(t, t_lock, hi), t, al)
    return amax_abs_dev(aw, ref)


@jit
def dip_flare(t_s, omega, t_start, t_end):
    """``launch_quality.engine_dip_flare_rpm``: ``(dip, flare)``, both from the engine
    speed at engagement start ``t_start``; NaN without an engagement start (``t_end`` NaN:
    to the end of the run)."""
    if math.isnan(t_start):
        return np.nan, np.nan
    idx = grid_index(t_s, True)
    t = take(t_s, idx)
    n = np.empty(idx.size)
    for i in range(idx.size):
        n[i] = omega[idx[i]] * 30.0 / math.pi
    hi = t[-1] if math.isnan(t_end) else min(t_end, t[-1])
    nw = interp(_window(t, t_start, hi), t, n)
    return nw[0] - extreme(nw, False), extreme(nw, True) - nw[0]


@jit
def _band_power(x, d, lo, hi):
    """``mean(irfft(rfft(x) with the bins outside [lo, hi] set to 0) ** 2)`` by Parseval,
    from the DFT of the bins inside (``d``: the sampling step); the band excludes 0 Hz."""
    n = x.size
    val = 1.0 / (n * d)
    c = np.empty(n)
    s = np.empty(n)
    for m in range(n):
        ang = 2.0 * math.pi * m / n
        c[m] = math.cos(ang)
        s[m] = math.sin(ang)
    total = 0.0
    for k in range(1, n // 2 + 1):
        f = k * val
        if f < lo or f > hi:
            continue
        re = 0.0
        im = 0.0
        m = 0
        for j in range(n):
            re += x[j] * c[m]
            im -= x[j] * s[m]
            m += k
            if m >= n:
                m -= n
        if 2 * k == n:
            total += re * re
        else:
            total += 2.0 * (re * re + im * im)
    return total / (n * n)


@jit
def judder(t_s, torque, cap, w, lo, hi, slip):
    """``judder.judder_amplitude`` on the arrays of a run; NaN where it is None."""
    n0 = t_s.size
    if n0 < 3:
        return np.nan
    cmax = extreme(cap, True)
    if cmax <= 0:
        return np.nan
    first, last, count = -1, -1, 0
    for i in range(n0):
        if cap[i] > 0.05 * cmax and abs(w[i]) >= slip:
            if first < 0:
                first = i
            last = i
            count += 1
    if count < 2:
        return np.nan
    t0, t1 = t_s[first], t_s[last]
    span = t1 - t0
    if span < 1.0 / lo:
        return np.nan
    n = max(math.ceil(span * 20.0 * hi), 8)
    tl = np.empty(n)
    step = span / (n - 1)
    for i in range(n):
        tl[i] = float(i) * step + t0
    tl[n - 1] = t1
    x = interp(tl, t_s, torque)
    tmean = pairwise_sum(tl, 0, n) / n
    xmean = pairwise_sum(x, 0, n) / n
    tc = np.empty(n)
    for i in range(n):
        tc[i] = tl[i] - tmean
    cx = 0.0
    cc = 0.0
    for i in range(n):
        cx += tc[i] * x[i]
        cc += tc[i] * tc[i]
    beta = cx / cc
    for i in range(n):
        x[i] = x[i] - xmean - tc[i] * beta
    return math.sqrt(2.0) * math.sqrt(_band_power(x, tl[1] - tl[0], lo, hi))


@jit
def held(t, w, cap, locked, lock_slip, hold):
    """``launch_metrics._held``: the locked flag set after the start, or a slip below
    ``lock_slip`` for ``hold`` seconds on end while engaged."""
    n = t.size
    for i in range(locked.size):
        if locked[i] > 0.5 and t[i] > t[0]:
            return True
    if w.size == 0 or cap.size == 0 or n < 2:
        return False
    cmax = extreme(cap, True)
    if not cmax > 0:
        return False
    start = -1
    for i in range(n):
        if cap[i] > 0.5 * cmax and abs(w[i]) < lock_slip:
            if start < 0:
                start = i
            if t[i] - t[start] >= hold:
                return True
        else:
            start = -1
    return False


@jit
def launch_kernel(t, a, tf, w, cap, locked, p, omega, tj, theta, ev, wd_sos, wd_zi,
                  lp_sos, lp_zi, dt_s, max_samples, lock_slip, hold, window, engage_rel,
                  area, band_lo, band_hi, judder_slip):
    """Every launch metric and warning test of a run, and the W_d-weighted acceleration.

    Arrays (empty when the run has no such signal): ``a`` the vehicle's acceleration,
    ``tf`` the clutch's transmitted torque ``T_friction_<c>``, ``w`` its slip, ``cap`` its
    capacity, ``locked`` its locked flag, ``p`` its friction power, ``omega`` the engine
    speed, ``tj`` its torque ``T_<c>`` (judder), ``theta`` the first thermal node's temperature;
    scalars: the filter grid's step and sample limit, the lock-up hold test's slip and
    time, the shock window, the engagement threshold's share, the lining area (NaN: none), the judder band and slip;
    ``ev`` the times of the clutch's events.  Returns ``(k, aw)``: ``k`` the values at
    the ``K_*`` slots (NaN where none), ``aw`` the weighted acceleration (empty without
    ``a``)."""
    k = np.empty(N_K)
    for i in range(N_K):
        k[i] = np.nan
    n = t.size
    aw = np.empty(0)
    if theta.size:
        k[K_THETA_MAX] = extreme(theta, True)
    if omega.size:
        k[K_OMEGA_MIN] = extreme(omega, False) * 30 / math.pi
        k[K_OMEGA_MAX] = extreme(omega, True) * 30 / math.pi
    if n < 2:
        return k, aw
    has_wc = w.size > 0 and cap.size > 0
    cmax = extreme(cap, True) if cap.size else 0.0
    # lock-up (launch_metrics._lockup_time), only for a clutch that held (else the
    # last sample of a slip that just fell through lock_slip at the run's end would count)
    k[K_HELD] = 1.0 if held(t, w, cap, locked, lock_slip, hold) else 0.0
    if has_wc and cmax > 0 and k[K_HELD] == 1.0:
        eng = np.empty(n)
        for i in range(n):
            eng[i] = 1.0 if cap[i] > 0.5 * cmax else 0.0
        k[K_LOCKUP] = lockup_time(t, w, eng, locked, ev, lock_slip)
    t_lock = k[K_LOCKUP]
    if tf.size:
        k[K_ENGAGE] = engagement_start(t, tf, np.nan, engage_rel)
    if a.size:
        tu, au = _filter_grid(t, a, dt_s, max_samples)     # one grid for both filters
        nu = tu.size
        if t[-1] > t[0] and nu > 3 * (2 * lp_sos.shape[0] + 1):
            # both filters in one pass (_weighted_on and _jerk_on, side by side)
            wg, af = _wd_and_lowpass(wd_sos, wd_zi, lp_sos, lp_zi, au)
            aw = interp(t, tu, wg)
            jk = _gradient(tu, af)
        else:
            aw = _weighted_on(t, tu, au, wd_sos, wd_zi) if t[-1] > t[0] else fill(n, 0.0)
            jk = _jerk_on(tu, au, lp_sos, lp_zi)
        k[K_VDV] = vdv(t, aw)
        k[K_AW_RMS] = rms(t, aw)
        k[K_JERK_PEAK] = amax_abs_dev(jk, 0.0)
        k[K_JERK_RMS] = rms(tu, jk)
        k[K_SHOCK] = lockup_shock(t, a, t_lock, window)
    if p.size:
        pa = np.empty(p.size)
        for i in range(p.size):
            pa[i] = abs(p[i])
        e = trapezoid(pa, t)
        k[K_SLIP_ENERGY] = e
        if not math.isnan(area):
            k[K_E_DENS] = e / area
            k[K_P_DENS] = extreme(pa, True) / area
    if omega.size:
        dip, flare = dip_flare(t, omega, k[K_ENGAGE], t_lock)
        k[K_DIP] = dip
        k[K_FLARE] = flare
    if tj.size and has_wc:
        k[K_JUDDER] = judder(t, tj, cap, w, band_lo, band_hi, judder_slip)
    # the warnings' tests (launch_metrics._ringing, launch_warnings; K_HELD above)
    k[K_RING] = 0.0
    if has_wc:
        k[K_CAP_MAX] = cmax
        n_eng = 0
        wmin, wmax = np.inf, -np.inf
        touch = -1
        for i in range(n):
            if cmax > 0 and cap[i] > 0.5 * cmax:
                n_eng += 1
                aw_i = abs(w[i])
                wmin = min(wmin, aw_i)
                wmax = max(wmax, aw_i)
                if touch < 0 and aw_i < lock_slip:
                    touch = i
        k[K_ENGAGED] = n_eng
        if n_eng:
            k[K_W_MIN_ENG] = wmin
            k[K_W_MAX_ENG] = wmax
        if tf.size and touch >= 0:
            tmax, tmin, cwin, wwin = -np.inf, np.inf, -np.inf, -np.inf
            for i in range(touch, n):
                if cap[i] > 0.5 * cmax:
                    tmax = max(tmax, tf[i])
                    tmin = min(tmin, tf[i])
                    cwin = max(cwin, cap[i])
                    wwin = max(wwin, abs(w[i]))
            amp = 0.5 * (tmax - tmin)
            if amp > cwin:
                k[K_RING] = 1.0
                k[K_RING_T0] = t[touch]
                k[K_RING_AMP] = amp
                k[K_RING_CAP] = cwin
                k[K_RING_WMAX] = wwin
                # the clutch's events from the first touch on (the warning's rate)
                n_after = 0
                for e in range(ev.size):
                    if ev[e] >= t[touch]:
                        if n_after == 0:
                            k[K_RING_EV_FIRST] = ev[e]
                        k[K_RING_EV_LAST] = ev[e]
                        n_after += 1
                k[K_RING_N_EV] = n_after
    return k, aw


@jit
def energy_balance(w_in, losses, ke, pe):
    """``(ΔE_kinetic, ΔE_spring, residual, scale)`` of a run [J]: ``w_in`` the work put
    in, ``losses`` the final values of the other energy accounts (in their order), ``ke``
    and ``pe`` the kinetic and spring energies over the run; ``residual = w_in -
    ΔE_kinetic - ΔE_spring - Σ losses``, ``scale = max(|w_in|, max ke, 1e-30)``
    (:func:`clutchsim.analysis.launch_metrics.energy_balance`)."""
    d_ke = ke[ke.size - 1] - ke[0]
    d_pe = pe[pe.size - 1] - pe[0]
    total = 0.0
    for x in losses:
        total += x
    resid = w_in - d_ke - d_pe - total
    return d_ke, d_pe, resid, max(abs(w_in), np.max(ke), 1e-30)
