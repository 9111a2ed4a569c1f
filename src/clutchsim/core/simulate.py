"""``simulate``: one entry point for the compiled integrators and the scipy reference."""

from __future__ import annotations

import contextlib
import math
import os
import signal
import threading
from collections.abc import Mapping
from typing import ClassVar, NamedTuple

import numpy as np

from . import cengine as ce
from ._cfunctions import c_functions
from .compile_notice import compile_notice
from .controllers import StepController
from .methods import EXPLICIT, get_method
from .options import DEFAULT_METHOD, SolverOptions, check_solver
from .result import Events, Result, Stats, assemble
from .signals import Signal, as_signal, build_bank
from .status import ACTION_WORDS, OUTCOME_OF_CODE, Code, Outcome
from .system import System, call_jac, closest, factor_size, has_jacobian

__all__ = ["RunEnd", "interrupts_deferred", "prepare_runs", "resolve_inputs", "run_end", "run_stats", "simulate"]

def _check_span(t_span) -> tuple[float, float]:
    try:
        t0, t1 = (float(x) for x in t_span)
    except (TypeError, ValueError):
        raise TypeError(f"t_span = {t_span!r} must be a pair of numbers (t_start, t_end) "
                        "in seconds") from None
    if not (math.isfinite(t0) and math.isfinite(t1)):
        raise ValueError(f"t_span = {t_span!r} must be finite")
    if t1 <= t0:
        raise ValueError(f"t_span = {t_span!r}: t_end = {t1} s must be > t_start = {t0} s")
    return t0, t1


def resolve_inputs(system: System, inputs) -> list[Signal]:
    """One signal per input channel of ``system``, from a mapping name -> signal/number."""
    names = system.input_names
    if inputs is None:
        inputs = {}
    if not isinstance(inputs, Mapping):
        raise TypeError(f"inputs must be a mapping of input name to signal, got "
                        f"{type(inputs).__name__}")
    for key in inputs:
        if key not in names:
            raise ValueError(f"{system.name}: unknown input {key!r}{closest(key, names)}; "
                             f"inputs: {', '.join(names) or '(none)'}")
    missing = [n for n in names if n not in inputs]
    if missing:
        raise ValueError(f"{system.name}: no signal given for input(s) {', '.join(missing)}")
    return [as_signal(inputs[n]) for n in names]


def _breakpoints(signals: list[Signal], t0: float, t1: float) -> np.ndarray:
    if not signals:
        return np.empty(0)
    bps = np.unique(np.concatenate([s.breakpoints() for s in signals] + [np.empty(0)]))
    return bps[(bps > t0) & (bps < t1)].astype(np.float64)


def _failure_message(code: int, t: float, k: int, i: int, system: System, opts: SolverOptions,
                     solver: str, window: float, event_names=None) -> tuple[Outcome, str, str]:
    """(outcome, message, name of the event that ended the run or "") for an integrator
    code (``event_names``: the run's, default the system's)."""
    code = Code(code)
    names = system.event_names if event_names is None else event_names
    ev = names[k] if 0 <= k < len(names) else "?"
    state = (f"'{system.state_names[i]} [{system.state_units[i]}]'"
             if 0 <= i < system.n_states else "(unknown)")
    outcome = OUTCOME_OF_CODE[code]
    ended_by = ev if code in (Code.EVENT_STOP, Code.EVENT_FAIL, Code.CHATTER) else ""
    if code == Code.DONE:
        message = f"completed to t = {t:.9g} s"
    elif code == Code.EVENT_STOP:
        message = f"stopped by event '{ev}' at t = {t:.9g} s"
    elif code == Code.EVENT_FAIL:
        message = f"{ev} at t = {t:.9g} s"
    elif code == Code.MAX_STEPS:
        message = (f"step budget exhausted: {opts.max_steps} steps reached at "
                   f"t = {t:.9g} s; raise SolverOptions.max_steps, or if the system is "
                   "stiff use solver='rodas4'")
    elif code == Code.WALL_TIME:
        message = (f"wall-time budget of {opts.wall_time:g} s exhausted at t = {t:.9g} s;"
                   " raise SolverOptions.wall_time, or use solver='rodas4' if the "
                   "system is stiff")
    elif code == Code.STEP_COLLAPSE:
        message = (f"step size collapsed at t = {t:.9g} s ({solver}): the right-hand "
                   "side is discontinuous (or violently stiff) there. A switching law "
                   "acting at this point, e.g. a naive stick/slip friction model at "
                   "lock-up, must be declared as an event, or replaced by a hybrid "
                   "(coulomb-robust) or dynamic friction model (e.g. mykhailevych2020)")
    elif code == Code.JAC_NON_FINITE:
        message = (f"non-finite value (NaN or inf) in the plant's Jacobian, column of state "
                   f"{state}, at t = {t:.9g} s: the registered jac produced it")
    elif code == Code.CHATTER:
        message = (f"chatter detected: {opts.chatter_events} events within "
                   f"{window:g} s, the last of them '{ev}' at t = {t:.9g} s."
                   " The event re-fires as soon as it is crossed (a sliding mode): "
                   "typically a discontinuous switching law at zero slip, such as a "
                   "naive stick/slip friction model at lock-up: replace such a model by a "
                   "hybrid stick/slip or a dynamic friction model (`clutchsim models` "
                   "lists them). If the element already has one, the events are dense "
                   "but may be genuine (a slow oscillation through zero slip): raise "
                   "solver.chatter_events or lower solver.chatter_window")
    else:
        message = (f"non-finite value (NaN or inf) in state {state} at t = {t:.9g} s: "
                   "the right-hand side produced it; check parameters and inputs")
    return outcome, message, ended_by


_METHOD_DATA: dict = {}
#: the packed default controller of each family (explicit or not), built once
_DEFAULT_CONTROLLERS = {explicit: StepController.default_for(explicit).packed()
                        for explicit in (False, True)}


def _method_data(solver: str, opts: SolverOptions):
    """The packed tableau, method scalars and controller of ``solver`` for the loop."""
    m = get_method(solver)
    data = _METHOD_DATA.get(solver)
    if data is None:
        tab = tuple(np.ascontiguousarray(x, dtype=np.float64) for x in m.packed())
        mopt = np.zeros(ce.N_MOPT)
        mopt[ce.M_FAMILY] = m.family
        mopt[ce.M_GAMMA] = getattr(m, "gamma", 0.0)
        mopt[ce.M_Q] = m.embedded_order + 1
        mopt[ce.M_DENSE] = m.dense
        mopt[ce.M_W] = m.w_method
        mopt[ce.M_FSAL] = getattr(m, "fsal", False)
        data = _METHOD_DATA[solver] = (tab, mopt)
    if opts.controller is not None:
        return data[0], data[1], opts.controller.packed()
    return data[0], data[1], _DEFAULT_CONTROLLERS[m.family == EXPLICIT]


#: tags whose registered Jacobian passed :func:`check_jacobian` in this process
_CHECKED_JACOBIANS: set = set()


def check_jacobian(system: System, y, signals, t0: float = 0.0) -> None:
    """Call the plant's exact Jacobian once at ``y`` (the inputs at the start) and refuse
    one that writes outside its ``(n, n)`` matrix or returns a non-finite entry, naming the
    entry and its states."""
    n = system.n_states
    guard = np.full((n + 2, n), 1.2345e300)
    J = guard[1:n + 1]
    J[:] = 0.0
    u = np.array([float(np.asarray(s(t0)).ravel()[0]) for s in signals], dtype=float)
    call_jac(system.tag, t0, np.ascontiguousarray(y, dtype=float), u, system.params, J)
    if np.any(guard[0] != 1.2345e300) or np.any(guard[n + 1] != 1.2345e300):
        raise ValueError(f"{system.name}: the registered Jacobian writes outside its "
                         f"({n}, {n}) matrix (one row per state: "
                         f"{', '.join(system.state_names)})")
    bad = np.argwhere(~np.isfinite(J))
    if bad.size:
        i, j = bad[0]
        raise ValueError(f"{system.name}: the registered Jacobian is not finite at the "
                         f"initial state: d({system.state_names[i]})'/d"
                         f"({system.state_names[j]}) = {J[i, j]}")
    _CHECKED_JACOBIANS.add(system.tag)


class _Prepared:
    """The arguments of the C engine that depend only on the plant type, the input
    signals, the span, the solver and the options, built once for runs that share them (a
    sweep's variants: one plant type, the scenario's own signal and option objects): the
    plant's C functions, the signal bank and breakpoints, the method's tableau and
    controller, the option vectors.  The engine only reads them."""

    __slots__ = ("_engine", "args", "chatter_window", "n_states", "refs")

    def __init__(self, system: System, signals, t0: float, t1: float, solver: str,
                 opts: SolverOptions, refs: tuple):
        tab, mopt, ctrl = _method_data(solver, opts)
        fopt = np.zeros(ce.N_FOPT)
        fopt[ce.O_RTOL], fopt[ce.O_ATOL] = opts.rtol, opts.atol
        fopt[ce.O_H0], fopt[ce.O_HMAX], fopt[ce.O_HMIN] = opts.h0, opts.h_max, opts.h_min
        fopt[ce.O_WALL] = opts.wall_time
        fopt[ce.O_CHATTER_WINDOW] = opts.chatter_window_for(t1 - t0)
        fopt[ce.O_DT_OUT] = opts.dt_out
        fopt[ce.O_EVENT_TOL] = opts.event_tol
        fopt[ce.O_LU_REUSE] = opts.jacobian.lu_reuse
        iopt = np.zeros(ce.N_IOPT, dtype=np.int64)
        iopt[ce.I_MAX_STEPS], iopt[ce.I_CHATTER_N] = opts.max_steps, opts.chatter_events
        iopt[ce.I_MAX_OUTPUT], iopt[ce.I_QUADRATURES] = opts.max_output, system.quadratures
        iopt[ce.I_EXACT_JAC] = has_jacobian(system.tag)
        iopt[ce.I_JAC_MAX_AGE] = opts.jacobian.max_age
        iopt[ce.I_FACTOR_SIZE] = factor_size(system.tag)
        ev_dir = np.array(system.event_directions, dtype=np.int64)
        #: the engine's arguments with None for the initial state and the parameters; the
        #: plant's C functions None where there is no engine to call them
        self.args = (c_functions(system) if ce.available() else None, tab, mopt, ctrl, t0,
                     t1, None, None, build_bank(signals), _breakpoints(signals, t0, t1),
                     ev_dir, len(system.output_names), fopt, iopt)
        self.n_states = system.n_states
        self.chatter_window = float(fopt[ce.O_CHATTER_WINDOW])
        self.refs = refs        # what the key names by identity, kept alive with it
        self._engine = False    # not looked for yet

    def engine(self):
        """The C engine for these runs (:mod:`clutchsim.core.cengine`), or None where they
        cannot take it (:meth:`why_not`)."""
        if self._engine is False:
            self._engine = ce.engine_for(self.args, self.n_states)
        return self._engine

    def why_not(self) -> str:
        """Why these runs cannot take the C engine ("" where they can)."""
        if self.args[0] is None:
            return "the C engine is not available here (see the log: no C compiler?)"
        return ce.beyond_bounds(self.args, self.n_states)

    @property
    def options(self) -> SolverOptions:
        """The options the arguments were built for."""
        return self.refs[0]


#: (plant type, its layout, solver, span, ids of the options and signals) -> _Prepared
_PREPARED: dict = {}
_PREPARED_MAX = 32
_PREPARED_LOCK = threading.Lock()


def _prepare(system: System, signals, t0: float, t1: float, solver: str,
             opts: SolverOptions) -> _Prepared:
    """The :class:`_Prepared` arguments for this run, from the cache when the options and
    the signals are the very objects of an earlier run (identity, so nothing is
    compared or hashed by value; the entry keeps them alive, so an id is never reused
    while it is cached)."""
    key = (type(system.tag), system.n_states, system.params.size, system.quadratures,
           system.event_directions, len(system.output_names), solver, t0, t1, id(opts), *map(id, signals))
    hit = _PREPARED.get(key)
    if hit is not None:
        return hit
    prep = _Prepared(system, signals, t0, t1, solver, opts, (opts, *signals))
    with _PREPARED_LOCK:    # a sweep's threads share the cache
        while len(_PREPARED) >= _PREPARED_MAX:
            _PREPARED.pop(next(iter(_PREPARED)))
        _PREPARED[key] = prep
    return prep


def _checked(system, t_span, solver: str, options) -> tuple[SolverOptions, float, float]:
    """``(options, t0, t1)`` after the checks of the system, the solver, the options and
    the span that :func:`simulate` and :func:`prepare_runs` make."""
    if not isinstance(system, System):
        raise TypeError(f"system must be a clutchsim System, got {type(system).__name__}")
    check_solver(solver)
    opts = options if options is not None else SolverOptions()
    if not isinstance(opts, SolverOptions):
        raise TypeError(f"options must be SolverOptions, got {type(opts).__name__}")
    return (opts, *_check_span(t_span))


def _prepared(system: System, signals, t0: float, t1: float, solver: str,
              opts: SolverOptions, y) -> _Prepared:
    """:func:`_prepare`, with the plant's registered Jacobian checked at ``y`` the first
    time the plant type runs."""
    prep = _prepare(system, signals, t0, t1, solver, opts)
    if prep.args[13][ce.I_EXACT_JAC] and system.tag not in _CHECKED_JACOBIANS:
        check_jacobian(system, y, signals, t0)
    return prep


def simulate(system: System, t_span, inputs: Mapping | None = None, *, y0=None,
             solver: str = DEFAULT_METHOD, options: SolverOptions | None = None) -> Result:
    """Integrate a plant over ``t_span`` and return a :class:`Result`.

    Parameters
    ----------
    system : System
        The plant (see :mod:`clutchsim.core.system`).
    t_span : (float, float)
        Start and end time [s]; the end must be later than the start.
    inputs : mapping of str to Signal or float, optional
        One signal per input of the system, by input name.
    y0 : array_like, optional
        Initial state; defaults to ``system.y0``.
    solver : str
        A compiled method of :mod:`clutchsim.core.methods`: ``"rodas4"`` (stiff;
        default), ``"rodas5p"`` (stiff, fifth order, for tight tolerances),
        ``"ros34pw2"`` (stiff, a W-method that reuses its Jacobian over many steps:
        cheaper per step for larger plants), ``"dopri5"`` (explicit); or a scipy reference
        backend: ``"scipy-radau"``, ``"scipy-lsoda"``, ``"scipy-rk45"``.
    options : SolverOptions, optional
        Tolerances, budgets, chatter detection, output grid.

    Returns
    -------
    Result
        States, inputs and outputs by name with units; ``status`` and ``message`` say how
        the run ended.  A failed run is returned, not raised.
    """
    opts, t0, t1 = _checked(system, t_span, solver, options)
    y_init = system.y0 if y0 is None else np.asarray(y0, dtype=float).ravel()
    if y_init.size != system.n_states:
        raise ValueError(f"{system.name}: y0 has {y_init.size} entries, the system has "
                         f"{system.n_states} states ({', '.join(system.state_names)})")
    bad = np.flatnonzero(~np.isfinite(y_init))
    if bad.size:
        i = bad[0]
        raise ValueError(f"{system.name}: initial state {system.state_names[i]} = "
                         f"{float(y_init[i])} must be finite")
    bad = np.flatnonzero(~np.isfinite(system.params))
    if bad.size:
        raise ValueError(f"{system.name}: parameter vector entry {bad[0]} = "
                         f"{float(system.params[bad[0]])} must be finite")
    signals = resolve_inputs(system, inputs)
    if solver.startswith("scipy-"):
        return _reference_run(system, t0, t1, y_init, signals, solver, opts)
    with compile_notice(type(system.tag), system.name, subject="the plant and the integrator",
                        takes="a few seconds"):
        prep = _prepared(system, signals, t0, t1, solver, opts, y_init)
        engine = prep.engine()
    if engine is None:
        return _without_engine(system, t0, t1, y_init, signals, solver, opts, prep.why_not())
    # a copy: a plant may switch its values at scheduled events (a gear shift)
    # and its own int options: their stop flag is this run's (interrupts_deferred)
    iopt = prep.args[13].copy()
    args = prep.args[:6] + (y_init, system.params.copy()) + prep.args[8:13] + (iopt,)
    with interrupts_deferred(iopt):
        (code, t_end, k, i, ts, ys, us, outs, ev_t, ev_k, ev_a, st, h_small,
         wall) = engine(args)
    end = run_end(system, opts, solver, prep.chatter_window, int(code), float(t_end), int(k),
                  int(i), ts.shape[0], float(ts[-1]))
    events = Events(ev_t, ev_k, ev_a, system.event_names, system.event_sources, ACTION_WORDS)
    return assemble(system, ts, ys, us, outs, end.outcome, end.message,
                    run_stats(st, h_small, wall), events, solver, event=end.event,
                    warnings=end.warnings, event_source=end.event_source,
                    tolerances=(opts.rtol, opts.atol))


def _reference_run(system, t0, t1, y_init, signals, solver: str, opts) -> Result:
    from .scipy_backend import simulate_scipy
    return simulate_scipy(system, t0, t1, y_init, signals, build_bank(signals),
                          _breakpoints(signals, t0, t1), solver, opts)


#: the reference method that stands in for a compiled one without the engine
_STAND_IN = {True: "scipy-rk45", False: "scipy-radau"}


def _without_engine(system, t0, t1, y_init, signals, solver: str, opts, why: str) -> Result:
    """A run of ``solver`` that cannot take the C engine (``why``), on scipy's reference
    backend (RK45 for an explicit method, Radau for the others), saying so."""
    stand_in = _STAND_IN[get_method(solver).family == EXPLICIT]
    result = _reference_run(system, t0, t1, y_init, signals, stand_in, opts)
    return result.with_warnings(
        f"integrated by scipy's {stand_in.removeprefix('scipy-').upper()} (the reference "
        f"backend: slower, and within the tolerances of {solver}, not its numbers), not "
        f"by {solver}: {why}")


#: the signals a run of the compiled loop defers (:func:`interrupts_deferred`)
_DEFERRED = (signal.SIGINT, signal.SIGTERM)


def _stops(handler) -> bool:
    """Does ``handler`` stop the program (so that a run it interrupts may be cut short)?
    Python's ``KeyboardInterrupt``, the default action, or a handler marked
    ``interrupts = True`` (the command line's SIGTERM handler)."""
    return (handler is signal.default_int_handler or handler == signal.SIG_DFL
            or getattr(handler, "interrupts", False))


class _Watcher:
    """A thread that sets the stop flag of the loop now running when a signal arrives.

    A Python signal handler runs only between two bytecodes of the main thread, so not
    while the compiled loop runs (for seconds, without the GIL); the C-level handler writes
    the signal's number to the wake-up file descriptor (:func:`signal.set_wakeup_fd`) at
    once, and this thread, reading it, sets ``iopt[I_STOP]``.  One per process."""

    def __init__(self):
        self.pid = os.getpid()
        self.r, self.w = os.pipe()
        os.set_blocking(self.w, False)
        self.iopt = None            # the int options of the loop now running, or None
        self.stops: tuple = ()      # the numbers of the signals that stop it
        threading.Thread(target=self._watch, name="clutchsim-interrupts", daemon=True).start()

    def _watch(self) -> None:
        while True:
            data = os.read(self.r, 64)
            iopt = self.iopt
            if iopt is not None and any(b in self.stops for b in data):
                iopt[ce.I_STOP] = 1


_WATCHER: list = []


def _watcher() -> _Watcher | None:
    """This process's watcher; None where a pipe cannot be a wake-up descriptor (Windows
    wants a socket): there the signals are still deferred, the run is not cut short."""
    if not _WATCHER or (_WATCHER[0] is not None and _WATCHER[0].pid != os.getpid()):
        try:                                        # (a forked child: its own)
            _WATCHER[:] = [_Watcher() if os.name == "posix" else None]
        except OSError:
            _WATCHER[:] = [None]
    return _WATCHER[0]


class _Deferral:
    """The state of :func:`interrupts_deferred` (main thread only): the int options of the
    loop now running (None when none runs) and the signals that arrived meanwhile."""

    running = None
    caught: ClassVar[list] = []


def _front(handler):
    """A handler that stands in front of ``handler``: while the compiled loop runs it only
    takes note of the signal; otherwise it passes it on.  Each carries its own
    ``behind``, so one put back by whoever saved it still passes on to the right one."""

    def front(signum, frame):
        if _Deferral.running is not None:
            _Deferral.caught.append(signum)
            return
        _deliver(handler, signum)
    front.behind = handler
    return front


def _deliver(handler, signum) -> None:
    if handler == signal.SIG_DFL:
        signal.signal(signum, signal.SIG_DFL)
        os.kill(os.getpid(), signum)
    elif handler != signal.SIG_IGN:
        handler(signum, None)


@contextlib.contextmanager
def interrupts_deferred(iopt):
    """Deliver SIGINT and SIGTERM after the compiled loop returns, not inside it, and stop
    the loop when they arrive.

    Python runs a signal's handler between two bytecodes of the main thread: not while the
    engine runs (its call does not return to Python), and inside a sweep's compiled batch
    loop a ``KeyboardInterrupt`` is lost inside numba and comes out as ``SystemError: ...
    returned a result with an exception set``, or as an unrelated ``TypeError``.  So each of the two signals' handlers gets a front
    (:func:`_front`, installed once and again whenever someone has set another handler;
    it stays and passes signals on, so that a run costs no system call) that only takes
    note while the block runs; the loop's stop flag ``iopt[I_STOP]`` is set at once (by
    :class:`_Watcher`) where the signal's own handler stops the program (:func:`_stops`;
    another handler is only called late, the run is not cut short), and the loop ends
    within 256 steps.  When the block ends the first signal is delivered to its own
    handler.  The run that stopped is never returned: the delivered signal raises (or
    ends the process).  Only the main thread receives signals; elsewhere this does
    nothing, and a handler set outside Python (``getsignal`` gives None) is left alone."""
    if threading.current_thread() is not threading.main_thread() or \
            _Deferral.running is not None:
        yield
        return
    behind = {}
    for s in _DEFERRED:
        handler = signal.getsignal(s)
        if handler is None:
            continue
        if not hasattr(handler, "behind"):
            handler = _front(handler)
            signal.signal(s, handler)
        behind[s] = handler.behind
    watcher = _watcher()
    old_fd = None
    _Deferral.caught = []
    _Deferral.running = iopt
    try:
        if watcher is not None:
            watcher.stops = tuple(int(s) for s, h in behind.items() if _stops(h))
            watcher.iopt = iopt
            old_fd = signal.set_wakeup_fd(watcher.w, warn_on_full_buffer=False)
        yield
    finally:
        if old_fd is not None:
            signal.set_wakeup_fd(old_fd)
        if watcher is not None:
            watcher.iopt = None
        _Deferral.running = None
        iopt[ce.I_STOP] = 0
        if _Deferral.caught:
            s = _Deferral.caught[0]
            _deliver(behind[s], s)


class RunEnd(NamedTuple):
    """How a run of the compiled loop ended: its outcome, message, the event that ended
    it (its name and source, "" when none did) and the warnings about the run itself."""

    outcome: Outcome
    message: str
    event: str
    event_source: str
    warnings: tuple


def run_end(system: System, opts: SolverOptions, solver: str, chatter_window: float,
            code: int, t_end: float, k: int, i: int, n_rows: int, t_last: float,
            event_names=None) -> RunEnd:
    """The :class:`RunEnd` of a run of the compiled loop from what the loop returned: its
    code, end time, event and state index, and the number of output rows and the last
    one's time (the output cap's warning).  ``event_names``: the run's (a variant's),
    default ``system``'s.  Shared by :func:`simulate` and the loops that run many
    variants in one compiled call (:func:`prepare_runs`)."""
    outcome, message, ended_by = _failure_message(code, t_end, k, i, system, opts, solver,
                                                  chatter_window, event_names)
    warnings: tuple = ()
    if n_rows >= opts.max_output and t_last < t_end:
        warnings = ((f"output stopped after {opts.max_output} rows at t = {t_last:.9g} s "
                     f"of a run that went on to {t_end:.9g} s (raise "
                     "SolverOptions.max_output or set dt_out)"),)
        message += "; " + warnings[-1]
    return RunEnd(outcome, message, ended_by,
                  system.event_sources[k] if ended_by else "", warnings)


def run_stats(st, h_small: float, wall: float) -> Stats:
    """The :class:`Stats` of a run from the engine's counters (``st``, indexed by
    ``cengine.S_*``), its smallest step and its wall time."""
    return Stats(steps=int(st[ce.S_STEPS]), rejected=int(st[ce.S_REJECTED]),
                 rhs_evals=int(st[ce.S_RHS]), jacobians=int(st[ce.S_JAC]),
                 lu_decompositions=int(st[ce.S_LU]), events=int(st[ce.S_EVENTS]),
                 min_step_s=float(h_small) if math.isfinite(h_small) else 0.0,
                 wall_s=float(wall), event_evals=int(st[ce.S_EV_CALLS]))


def prepare_runs(system: System, t_span, inputs: Mapping | None = None, *,
                 solver: str = DEFAULT_METHOD, options: SolverOptions | None = None):
    """The arguments of the C engine (:func:`clutchsim.core.cengine.integrate_nb`) for
    runs of ``system`` and of its variants (other parameter vectors and initial states of
    the same layout: :meth:`System.with_values`) over ``t_span`` with ``inputs``: for a
    caller that runs many variants from its own compiled loop (a sweep's chunk,
    :func:`clutchsim.analysis.launch_batch.launch_batch`).  ``.args`` holds None for the
    initial state and the parameter vector (``args[6]``, ``args[7]``);
    ``.chatter_window`` is what :func:`run_end` needs.  The system, span, solver and
    options are checked as :func:`simulate` checks them (compiled methods only), and the
    plant's C functions are compiled or loaded (``.args[0]``; None where there is no
    engine here).  ``.engine()`` is None where the runs cannot take the engine, and
    ``.why_not()`` says why."""
    opts, t0, t1 = _checked(system, t_span, solver, options)
    if solver.startswith("scipy-"):
        raise ValueError(f"solver {solver!r}: a batch of runs needs a compiled method")
    return _prepared(system, resolve_inputs(system, inputs), t0, t1, solver, opts, system.y0)
