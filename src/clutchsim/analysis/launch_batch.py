"""Many variants of one driveline system in one compiled call, reduced to launch metrics.

A sweep runs one system hundreds of times with other parameter vectors and initial
states.  :func:`launch_batch` runs a chunk of them in one call of a compiled loop: for
each variant the integrator (the C engine, :func:`clutchsim.core.cengine.integrate_nb`:
the one :func:`clutchsim.core.simulate` runs, with the same bits) and then the launch kernel
(:func:`clutchsim.analysis._kernels.launch_kernel`, the one :func:`~clutchsim.analysis.
launch_metrics.analyse_run` calls) on the run's own output arrays, keeping only the numbers a
sweep's table row needs: the integrator's end code and counters, the kernel's values and
the energy balance.  Python then builds each row from those numbers with the functions
the single run uses (:func:`clutchsim.core.simulate.run_end`,
:func:`~clutchsim.analysis.launch_metrics.warnings_of`, :func:`~clutchsim.analysis.launch_metrics.
metrics_of`), so a batch gives the rows a run-by-run sweep gives, to the bit
(``tests/sweep/test_batch.py``), without a :class:`~clutchsim.core.Result`, its
columns, or one interpreter round trip per variant.

What a batch cannot give is the time series: a sweep that keeps traces runs variant by
variant.  The filters of the launch kernel are designed (by scipy) for one grid step;
a batch needs that step to be the same for every run of the span, which holds when the
span has at most ``FILTER_MAX_SAMPLES`` steps of ``FILTER_DT_S``
(:func:`batch_supported` says why not otherwise).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numba
import numpy as np

from .._jit import jit
from ..core import System
from ..core._clock import now
from ..core.cengine import N_STATS, batch_engine_for, first_rows, integrate_nb
from ..core.compile_notice import compile_notice
from ..core.result import apply_violations
from ..core.simulate import prepare_runs, run_end, run_stats
from ..network.invariants import N_CHECKS, N_R, scan
from . import _kernels as _k
from . import launch_quality as lq
from .judder_band import JUDDER_BAND_HZ, JUDDER_SLIP_RAD_S
from .launch_metrics import ENERGY_STATES, LOCK_HOLD, LOCK_SLIP, RunSummary, metrics_of, warnings_of

__all__ = ["batch_supported", "kernel_signature_example", "launch_batch"]

#: the signals the batch reads, in the order of its column table: the launch kernel's
#: (see :class:`clutchsim.analysis.launch_metrics._Run`), then the energy accounts
_KERNEL_SIGNALS = ("a_vehicle", "T_friction_{c}", "w_slip_{c}", "capacity_{c}", "{c}.locked",
                   "P_{c}", "omega_engine", "T_{c}", "theta")
_ENERGY_SIGNALS = (*ENERGY_STATES, "E_kinetic", "E_spring")
#: slots of a run's integer results (after the engine's counters, ``cengine.S_*``)
I_CODE, I_K, I_I, I_ROWS = N_STATS, N_STATS + 1, N_STATS + 2, N_STATS + 3
N_I = N_STATS + 4
#: slots of a run's float results
F_T_END, F_H_SMALL, F_WALL, F_T_FIRST, F_T_LAST, F_ENERGY, F_LOOP = range(7)
N_F = 7


@jit
def _column(ys, us, outs, n, src, j, empty):
    """Column ``j`` of the run's states (``src`` 0), inputs (1) or outputs (2), its first
    ``n`` rows; ``empty`` (a 0-length column) where the run has no such signal."""
    if src == 0:
        return ys[:n, j]
    if src == 1:
        return us[:n, j]
    if src == 2:
        return outs[:n, j]
    return empty


@jit
def _run_batch(tab, mopt, ctrl, t0, t1, Y0, P, bank, bps, ev_dir, n_outputs, fopt, iopt,
               cols, mine, empty2, wd_sos, wd_zi, lp_sos, lp_zi, dt_s, max_samples, lock_slip,
               hold, window, engage_rel, area, band_lo, band_hi, judder_slip, inv_el,
               inv_speeds, inv_wf, inv_passive, rtol, atol, K, I, F, V, c_eng, c_free, c_plant,
               c_rows):
    """Run each row of ``Y0``/``P`` and write its kernel values to ``K``, its counters and
    end to ``I``, its times, energy balance and compiled wall time to ``F``, its physics
    checks' table to ``V`` (see :func:`launch_batch`).  ``P`` is overwritten (a plant may switch its values at
    scheduled events).  ``c_eng``, ``c_free``, ``c_plant``: the C engine
    (:class:`clutchsim.core.cengine.BatchEngine`); ``c_rows``: the engine's first rows
    per run."""
    empty = empty2[:, 0]
    n_losses = len(ENERGY_STATES) - 1
    losses = np.empty(n_losses)
    for r in range(Y0.shape[0]):
        start = now()
        (code, t_end, kk, ii, ts, ys, us, outs, ev_t, ev_k, _ev_a, st, h_small,
         wall) = integrate_nb(c_eng, c_free, c_plant, tab, mopt, ctrl, t0, t1, Y0[r], P[r],
                              bank, bps, ev_dir, n_outputs, fopt, iopt, c_rows)
        n = ts.shape[0]
        # the plant's physics checks on the run's rows (network/invariants.py)
        scan(ts, ys, outs, inv_el, inv_speeds, inv_wf, inv_passive, rtol, atol, V[r])
        n_mine = 0
        for e in range(ev_t.shape[0]):
            if mine[ev_k[e]]:
                n_mine += 1
        ev = np.empty(n_mine)
        n_mine = 0
        for e in range(ev_t.shape[0]):
            if mine[ev_k[e]]:
                ev[n_mine] = ev_t[e]
                n_mine += 1
        c = cols
        # contiguous copies of the columns: the single run's specialisation of the kernel
        # (launch_metrics._kernel_entry)
        k, _aw = _k.launch_kernel(
            ts, np.ascontiguousarray(_column(ys, us, outs, n, c[0, 0], c[0, 1], empty)),
            np.ascontiguousarray(_column(ys, us, outs, n, c[1, 0], c[1, 1], empty)),
            np.ascontiguousarray(_column(ys, us, outs, n, c[2, 0], c[2, 1], empty)),
            np.ascontiguousarray(_column(ys, us, outs, n, c[3, 0], c[3, 1], empty)),
            np.ascontiguousarray(_column(ys, us, outs, n, c[4, 0], c[4, 1], empty)),
            np.ascontiguousarray(_column(ys, us, outs, n, c[5, 0], c[5, 1], empty)),
            np.ascontiguousarray(_column(ys, us, outs, n, c[6, 0], c[6, 1], empty)),
            np.ascontiguousarray(_column(ys, us, outs, n, c[7, 0], c[7, 1], empty)),
            np.ascontiguousarray(_column(ys, us, outs, n, c[8, 0], c[8, 1], empty)), ev,
            wd_sos, wd_zi, lp_sos, lp_zi, dt_s, max_samples, lock_slip, hold, window,
            engage_rel, area, band_lo, band_hi, judder_slip)
        b = 9       # the energy accounts' columns
        w_in = _column(ys, us, outs, n, c[b, 0], c[b, 1], empty)[n - 1]
        for j in range(n_losses):
            losses[j] = _column(ys, us, outs, n, c[b + 1 + j, 0], c[b + 1 + j, 1], empty)[n - 1]
        ke = _column(ys, us, outs, n, c[b + 1 + n_losses, 0], c[b + 1 + n_losses, 1], empty)
        pe = _column(ys, us, outs, n, c[b + 2 + n_losses, 0], c[b + 2 + n_losses, 1], empty)
        _d_ke, _d_pe, resid, scale = _k.energy_balance(w_in, losses, ke, pe)
        # element loops: a slice assignment compiles numba's message for mismatched
        # shapes (~1.8 s of the batch's first compilation, measured)
        for j in range(k.shape[0]):
            K[r, j] = k[j]
        for j in range(N_STATS):
            I[r, j] = st[j]
        I[r, I_CODE] = code
        I[r, I_K] = kk
        I[r, I_I] = ii
        I[r, I_ROWS] = n
        F[r, F_T_END] = t_end
        F[r, F_H_SMALL] = h_small
        F[r, F_WALL] = wall
        F[r, F_T_FIRST] = ts[0]
        F[r, F_T_LAST] = ts[n - 1]
        F[r, F_ENERGY] = abs(resid) / scale
        F[r, F_LOOP] = now() - start


def _entry(args):
    """The compiled batch loop for the types of ``args`` (compiled, or loaded from numba's
    cache, the first time), to call directly: the batch's arguments are typed once per
    call here, not by numba's dispatcher on top."""
    sig = tuple(numba.typeof(x) for x in args)
    cres = _run_batch.overloads.get(sig)
    if cres is None:
        with compile_notice(("launch_batch", sig), "a sweep's batch of launches"):
            _run_batch.compile(sig)
        cres = _run_batch.overloads[sig]
    return cres.entry_point


def _columns(system: System, clutch: str) -> np.ndarray | None:
    """``(source, index)`` of each signal of the batch (source -1: the run has none);
    None when an energy account is missing (the batch needs every one)."""
    where = {}
    for src, names in enumerate((system.state_names, system.input_names,
                                 system.output_names)):
        for j, name in enumerate(names):
            where.setdefault(name, (src, j))
    temps = [n for n in (*system.state_names, *system.input_names, *system.output_names)
             if n.startswith("theta_")]
    rows = []
    for tmpl in _KERNEL_SIGNALS:
        name = (temps[0] if temps else "") if tmpl == "theta" else tmpl.format(c=clutch)
        rows.append(where.get(name, (-1, 0)))
    for name in _ENERGY_SIGNALS:
        if name not in where:
            return None
        rows.append(where[name])
    return np.array(rows, dtype=np.int64)


def kernel_signature_example() -> tuple:
    """Values of the types :func:`_run_batch` calls the launch kernel with (the
    integrator's output rows and their columns, the filters, the constants): compiling
    the kernel for them in a second process puts the batch's specialisation in numba's
    cache (:mod:`clutchsim.scenario.warmup`).  ``tests/sweep`` checks that a batch uses
    this very signature."""
    column = np.zeros(2)         # a column of the rows, copied contiguous
    return (np.zeros(2), *([column] * 9), np.zeros(0), *_kernel_constants(math.nan))


def _kernel_constants(area: float) -> tuple:
    """The launch kernel's arguments after the run's own (filters, thresholds, the lining
    area), as the batch passes them on."""
    wd_sos, wd_zi = lq._wd_sos(lq.FILTER_DT_S)
    lp_sos, lp_zi = lq._lowpass_sos(lq.JERK_CUTOFF_HZ, lq.FILTER_DT_S)
    lo, hi = JUDDER_BAND_HZ
    return (wd_sos, wd_zi, lp_sos, lp_zi, lq.FILTER_DT_S, lq.FILTER_MAX_SAMPLES, LOCK_SLIP,
            LOCK_HOLD, lq.SHOCK_WINDOW_S, lq.ENGAGE_THRESHOLD_REL, area, lo, hi,
            JUDDER_SLIP_RAD_S)


def batch_supported(system: System, t_span, clutch: str) -> str:
    """Why runs of ``system`` over ``t_span`` cannot be batched ("" when they can): the
    energy accounts the batch reads, and one filter step for every span a run may end
    with (a run that stops early has a shorter one).  Whether the runs can take the C
    engine, which the batch calls, is the prepared runs' to say
    (``prepare_runs(...).why_not()``; :func:`launch_batch` raises with it)."""
    return _unsupported(_columns(system, clutch), t_span)


def _unsupported(cols, t_span) -> str:
    """:func:`batch_supported` for the batch's column table ``cols`` (:func:`_columns`)."""
    if cols is None:
        return "the system lacks an energy account (" + ", ".join(_ENERGY_SIGNALS) + ")"
    t0, t1 = (float(x) for x in t_span)
    full = lq.filter_step_s(np.array([t0, t1]))
    if full != lq.FILTER_DT_S or (t0 + lq.FILTER_DT_S) - t0 != full:
        return (f"the span {t1 - t0:g} s is longer than {lq.FILTER_MAX_SAMPLES} filter steps "
                f"of {lq.FILTER_DT_S:g} s: the filter step depends on where a run ends")
    return ""


def launch_batch(system: System, t_span, inputs, params: np.ndarray, y0: np.ndarray, *,
                 clutch: str, solver: str, options, expect_lockup: bool = True,
                 friction: bool = True, lining: tuple | None = None,
                 engine_max_radps: float | None = None,
                 event_names: Sequence | None = None) -> list[tuple[str, dict]]:
    """Run the variants ``params[r]``, ``y0[r]`` of ``system`` over ``t_span`` with
    ``inputs`` in one compiled call and return ``(status, metrics)`` per variant: the
    status of its run and the metrics dict that
    :func:`~clutchsim.analysis.launch_metrics.analyse_run` gives for it (warnings included).

    ``params`` (n, len(system.params)) and ``y0`` (n, system.n_states): float arrays, one
    row per variant, checked finite.  ``event_names``: per variant its event names where
    they differ from ``system``'s (an entry or the whole argument None: the system's), for
    the messages.  Raises
    ValueError when the runs cannot be batched (:func:`batch_supported`).

    The compiled loop's own wall time per variant (the integrator and the kernel) is in
    each metrics dict as ``loop_wall_s``.
    """
    cols = _columns(system, clutch)
    why = _unsupported(cols, t_span)
    if why:
        raise ValueError(f"{system.name}: cannot run a batch: {why}")
    P = np.array(params, dtype=np.float64, order="C", copy=True)
    Y0 = np.ascontiguousarray(y0, dtype=np.float64)
    n = P.shape[0]
    if P.ndim != 2 or P.shape[1] != system.params.size or Y0.shape != (n, system.n_states):
        raise ValueError(f"{system.name}: a batch needs params of shape (n, "
                         f"{system.params.size}) and y0 of shape (n, {system.n_states}), got "
                         f"{P.shape} and {Y0.shape}")
    for arr, what in ((P, "parameter vector"), (Y0, "initial state")):
        bad = np.argwhere(~np.isfinite(arr))
        if bad.size:
            r, j = bad[0]
            raise ValueError(f"{system.name}: variant {r}: {what} entry {j} = "
                             f"{float(arr[r, j])} must be finite")
    prep = prepare_runs(system, t_span, inputs, solver=solver, options=options)
    opts = prep.options
    a = prep.args
    mine = np.array([s == clutch for s in system.event_sources], dtype=np.bool_)
    t0, t1 = a[4], a[5]
    area = lq.lining_area_mm2(*lining) if lining is not None else math.nan
    K = np.empty((n, _k.N_K))
    iv = np.empty((n, N_I), dtype=np.int64)
    fv = np.empty((n, N_F))
    checks = system.invariants
    if checks is not None:
        inv_el, inv_speeds, inv_wf, inv_passive, inv_rows = checks.arrays
    else:
        inv_el, inv_speeds, inv_wf, inv_passive, inv_rows = (
            np.zeros((0, 7), dtype=np.int64), np.zeros(0, dtype=np.int64), -1, False, N_CHECKS)
    V = np.empty((n, inv_rows, N_R))
    eng = batch_engine_for(a, system.n_states)
    if eng is None:
        raise ValueError(f"{system.name}: cannot run a batch: {prep.why_not()}")
    c_rows = first_rows(t0, t1, float(opts.dt_out), int(opts.max_output))
    args = (a[1], a[2], a[3], t0, t1, Y0, P, a[8], a[9], a[10], a[11], a[12], a[13],
            cols, mine, np.empty((0, 1)), *_kernel_constants(float(area)), inv_el, inv_speeds,
            inv_wf, inv_passive, float(opts.rtol), float(opts.atol), K, iv, fv, V, *eng,
            c_rows)
    _entry(args)(*args)
    kinds = system.metadata.get("kinds", {})
    has_slip = f"w_slip_{clutch}" in (*system.state_names, *system.input_names,
                                       *system.output_names)
    out = []
    for r in range(n):
        i, f = iv[r], fv[r]
        names = event_names[r] if event_names is not None else None
        end = run_end(system, opts, solver, prep.chatter_window, int(i[I_CODE]),
                      float(f[F_T_END]), int(i[I_K]), int(i[I_I]), int(i[I_ROWS]),
                      float(f[F_T_LAST]), names)
        if checks is not None:
            outcome, message, warns, source = apply_violations(
                checks.violations(V[r]), end.outcome, end.message, end.warnings)
            end = end._replace(outcome=outcome, message=message, warnings=warns,
                               **({"event": "", "event_source": source} if source else {}))
        sm = RunSummary.of(end, run_stats(i[:N_STATS], float(f[F_H_SMALL]),
                                          float(f[F_WALL])),
                           kinds, int(i[I_ROWS]), float(f[F_T_LAST] - f[F_T_FIRST]), has_slip,
                           K[r], float(f[F_ENERGY]))
        extra = tuple(warnings_of(sm, clutch, expect_lockup=expect_lockup, friction=friction,
                                  engine_max_radps=engine_max_radps))
        m = metrics_of(sm._replace(warnings=sm.warnings + extra), clutch)
        m["loop_wall_s"] = float(f[F_LOOP])
        out.append((sm.status, m))
    return out

