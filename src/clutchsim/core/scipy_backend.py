"""Reference backend: the same system integrated by scipy's ``solve_ivp``.

Slow (a Python call per right-hand-side evaluation) but independent of the compiled
integrators, so tests cross-check the two.  Breakpoints split the run into pieces; events
are scipy terminal events followed by the plant's reset map and a restart.

Event hysteresis: scipy's solutions carry noise of the size of ``atol`` (LSODA in
particular), and a restart next to a root of a function that stays near zero - the slip of
a clutch that has just stuck - finds a new "crossing" in that noise every few
microseconds; the default launch was stopped by chatter detection after 185 such no-op
events in 0.4 ms.  Once event ``k`` has fired, its next crossing is therefore located
where its function has moved ``atol`` beyond zero on the other side (a dead band of width
``atol``, in the event function's own unit).  The compiled integrators do not need it:
their event functions are sampled on the dense output of accepted steps, whose noise is far
below the tolerance.
"""

from __future__ import annotations

import itertools
import time

import numpy as np
from scipy.integrate import solve_ivp

from .result import Event, Stats, assemble
from .signals import eval_inputs
from .status import ACTION_WORDS, Action, Outcome
from .system import call_events, call_outputs, call_reset, call_rhs

_METHOD = {"scipy-radau": "Radau", "scipy-lsoda": "LSODA", "scipy-rk45": "RK45"}


def _crossed(a: float, b: float, direction: float) -> bool:
    """Did a function cross zero from ``a`` to ``b`` in ``direction`` (+1 upward, -1
    downward, 0 either; a root reached counts, as for scipy's events)?"""
    return bool((direction >= 0 and a < 0.0 <= b) or (direction <= 0 and a > 0.0 >= b))


def simulate_scipy(system, t0, t1, y0, signals, bank, bps, solver, opts):
    # a copy: a plant may switch its values at scheduled events (a gear shift)
    tag, p = system.tag, system.params.copy()
    n_in, n_ev, n_outp = len(system.input_names), system.n_events, len(system.output_names)
    u = np.zeros(n_in)
    g = np.zeros(n_ev)
    nfev = [0]

    def inputs_at(t, t_ref):
        eval_inputs(bank, t, t_ref, u)
        return u

    def record(t, y, t_ref, rows):
        out = np.zeros(n_outp)
        uu = inputs_at(t, t_ref).copy()
        call_outputs(tag, t, y, uu, p, out)
        rows.append((t, y.copy(), uu, out))

    edges = np.concatenate([[t0], bps, [t1]])
    rows: list = []
    events: list[Event] = []
    y = y0.copy()
    t = t0
    status, message = Outcome.COMPLETED, f"completed to t = {t1:.9g} s"
    ended_by = source = ""
    steps = 0
    wall0 = time.perf_counter()
    record(t, y, t + 1e-12 * max(1.0, abs(t)), rows)
    last_event_times: list[float] = []
    mute_until = -np.inf
    # side (+1/-1) each event function was left on at its last firing: the next crossing
    # is located at -side·atol (see the module docstring)
    side = np.zeros(n_ev)
    band = opts.atol

    # the right-hand side and the event functions of one piece (``t_ref`` picks the side
    # of the breakpoints its inputs are evaluated on)
    def make_rhs(t_ref):
        def rhs(tt, yy):
            nfev[0] += 1
            dy = np.empty_like(yy)
            call_rhs(tag, tt, yy, inputs_at(tt, t_ref), p, dy)
            return dy
        return rhs

    def make_event(k, t_ref):
        def ev(tt, yy):
            call_events(tag, tt, yy, inputs_at(tt, t_ref), p, g)
            return g[k] + side[k] * band
        ev.terminal = True
        ev.direction = system.event_directions[k]
        return ev

    def fire_due(k, t, y, t_ref, ref, before):
        """Fire event ``k`` at ``t`` (``y`` is reset in place), then every other event due
        at this instant, in turn: one whose (banded) function crossed from ``ref`` to
        ``before`` (its value before the first reset) and is still past zero after the
        resets.  Scipy stops at the first root, and the restart, which begins past the
        other one, would never see it (twin clutches slipping through zero at once).
        Returns the banded values after the last reset and, when the run ends here,
        ``(status, message, event, source)``."""
        u_t = inputs_at(t, t_ref)
        done: set[int] = set()
        while True:
            done.add(k)
            # the side the function is left on: opposite to where it came from
            if ref[k] != 0.0:
                side[k] = -np.sign(ref[k])
            action = int(call_reset(tag, t, y, u_t, p, k))
            name, source = system.event_names[k], system.event_sources[k]
            events.append(Event(t, name, ACTION_WORDS[action], source))
            record(t, y, t_ref, rows)
            last_event_times.append(t)
            n_ch, window = opts.chatter_events, opts.chatter_window_for(t1 - t0)
            if n_ch and len(last_event_times) > n_ch and \
                    t - last_event_times[-n_ch - 1] <= window:
                message = (f"chatter detected: {n_ch} events within {window:g} s, "
                           f"the last of them '{name}' at t = {t:.9g} s")
                return None, (Outcome.CHATTER, message, name, source)
            if action in (Action.STOP, Action.FAIL):
                if action == Action.STOP:
                    return None, (Outcome.STOPPED,
                                  f"stopped by event '{name}' at t = {t:.9g} s", name, source)
                return None, (Outcome.EVENT_FAILED, f"{name} at t = {t:.9g} s", name, source)
            call_events(tag, t, y, u_t, p, g)
            after = g + side * band
            k = next((j for j in range(n_ev) if j not in done and ref[j] != 0.0
                      and _crossed(ref[j], before[j], system.event_directions[j])
                      and _crossed(ref[j], after[j], system.event_directions[j])), -1)
            if k < 0:
                return after, None

    def fire_at_start(t, y, t_ref, left_ref):
        """Fire what is due where a piece starts (``fire_due``'s return): at the initial
        time a directional event whose function starts on its post-crossing side (as if it
        had come from the mirror image), at a breakpoint an event whose function the
        inputs' jump crossed (its values on the left, with ``left_ref``'s inputs)."""
        call_events(tag, t, y, inputs_at(t, t_ref), p, g)
        now = g + side * band
        if left_ref is None:
            before = now.copy()
            for j in range(n_ev):
                d = system.event_directions[j]
                if (d == -1 and now[j] < 0.0) or (d == 1 and now[j] > 0.0):
                    before[j] = -now[j]
        else:
            call_events(tag, t, y, inputs_at(t, left_ref), p, g)
            before = g + side * band
        k = next((j for j in range(n_ev)
                  if _crossed(before[j], now[j], system.event_directions[j])), -1)
        return fire_due(k, t, y, t_ref, before, now) if k >= 0 else (None, None)

    armed_after = None      # the banded event values the last reset left (see fire_due)
    left_ref = None         # the inputs' side left of the piece's start (None at t0)
    for a, b in itertools.pairwise(edges):
        t_ref = 0.5 * (a + b)
        if t >= b:
            left_ref = t_ref
            continue
        rhs = make_rhs(t_ref)
        if t == a and n_ev:
            armed, end = fire_at_start(t, y, t_ref, left_ref)
            if end is not None:
                status, message, ended_by, source = end
                break
            if armed is not None:
                armed_after = armed
                mute_until = t + 1e-10 * max(1.0, abs(t))
        left_ref = t_ref
        while t < b:
            if armed_after is not None and t >= mute_until:
                # an event that crossed while the events were muted, just after the one
                # fired (twins crossing within scipy's root tolerance): it fires now
                call_events(tag, t, y, inputs_at(t, t_ref), p, g)
                now = g + side * band
                ref, armed_after = armed_after, None
                k = next((j for j in range(n_ev) if _crossed(
                    ref[j], now[j], system.event_directions[j])), -1)
                if k >= 0:
                    armed_after, end = fire_due(k, t, y, t_ref, ref, now)
                    if end is not None:
                        status, message, ended_by, source = end
                        break
                    mute_until = t + 1e-10 * max(1.0, abs(t))
                    continue
            t_stop = b
            evs = [make_event(k, t_ref) for k in range(n_ev)] if t >= mute_until else []
            if t < mute_until:
                t_stop = min(b, mute_until)
            t_eval = None
            if opts.dt_out > 0:
                k0 = np.floor((t - t0) / opts.dt_out) + 1
                k1 = np.floor((t_stop - t0) / opts.dt_out + 1e-9)
                t_eval = np.append(t0 + np.arange(k0, k1 + 1) * opts.dt_out, t_stop)
                t_eval = np.unique(np.clip(t_eval, t, t_stop))
            # event values at the start, with their bands (one evaluation of all of them)
            call_events(tag, t, y, inputs_at(t, t_ref), p, g)
            start = g + side * band
            sol = solve_ivp(rhs, (t, t_stop), y, method=_METHOD[solver], rtol=opts.rtol,
                            atol=opts.atol, events=evs or None, t_eval=t_eval)
            steps += max(len(sol.t) - 1, 0)
            # with t_eval, an event before the first output time leaves scipy's y an empty
            # list rather than an (n, 0) array
            sol_t = np.atleast_1d(np.asarray(sol.t, dtype=float))
            sol_y = np.asarray(sol.y, dtype=float).reshape(len(y), sol_t.size)
            for tt, yy in zip(sol_t, sol_y.T):
                if tt > t:
                    record(tt, yy, t_ref, rows)
            if sol.status == -1:
                status, message = Outcome.SOLVER_ERROR, f"scipy {_METHOD[solver]}: {sol.message}"
                break
            if time.perf_counter() - wall0 > opts.wall_time > 0:
                status = Outcome.WALL_TIME
                message = f"wall-time budget of {opts.wall_time:g} s exhausted at t = {t:.9g} s"
                break
            fired = [k for k in range(len(evs)) if sol.t_events[k].size]
            if not fired:
                t, y = float(sol_t[-1]), sol_y[:, -1].copy()
                continue
            k = min(fired, key=lambda kk: sol.t_events[kk][0])
            t, y = float(sol.t_events[k][0]), sol.y_events[k][0].copy()
            call_events(tag, t, y, inputs_at(t, t_ref), p, g)
            armed_after, end = fire_due(k, t, y, t_ref, start, g + side * band)
            if end is not None:
                status, message, ended_by, source = end
                break
            # step off the root before events are armed again (scipy would re-detect it)
            mute_until = t + 1e-10 * max(1.0, abs(t))
        if status != Outcome.COMPLETED:
            break
    ts = np.array([r[0] for r in rows])
    ys = np.array([r[1] for r in rows]).reshape(len(rows), -1)
    us = np.array([r[2] for r in rows]).reshape(len(rows), n_in)
    outs = np.array([r[3] for r in rows]).reshape(len(rows), n_outp)
    dts = np.diff(ts)
    stats = Stats(steps=steps, rejected=0, rhs_evals=nfev[0], jacobians=0, lu_decompositions=0,
                  events=len(events), min_step_s=float(dts[dts > 0].min()) if np.any(dts > 0)
                  else 0.0, wall_s=time.perf_counter() - wall0)
    return assemble(system, ts, ys, us, outs, status, message, stats, tuple(events), solver,
                    event=ended_by, event_source=source, tolerances=(opts.rtol, opts.atol))
