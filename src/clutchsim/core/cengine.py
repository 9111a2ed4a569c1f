"""The C engine: the integration loop (``engine.c``), called through :mod:`ctypes`.

Every run of a compiled method goes through ``engine.c``: the plant's functions reach it
as C functions (:func:`clutchsim.core._cfunctions.c_functions`: a printed plant's own, a
numba plant's adapters).  The engine owns step-size control, the Jacobian and
iteration-matrix reuse, breakpoints, event location on the dense output, reset maps,
output rows, and the guards that end every run (steps, wall time, step floor, chatter);
the method is data (the packed tableau of :mod:`clutchsim.core.methods`).  Its call does
not hold the GIL, so threads run engines side by side; a sweep's batch calls it from
numba (:func:`integrate_nb`).  Its evaluation of the input signals also serves
:meth:`clutchsim.core.signals.Signal.__call__` (:func:`eval_series`).

The engine is compiled once per machine (3–4 s) into clutchsim's cache directory,
under the hash of its source and the compiler flags; a second process loads it.  Where it
cannot be compiled or loaded (no C compiler), that is said once (logger ``clutchsim``)
and runs take scipy's reference backend (:mod:`clutchsim.core.scipy_backend`), each
result saying so; so does a plant beyond the engine's bounds (:data:`MAX_STATES` and the
others below).
"""

from __future__ import annotations

import ctypes
import hashlib
import logging
import os
import shutil
import tempfile
import threading
import warnings
import weakref
from pathlib import Path
from typing import NamedTuple

import numba.experimental.function_type  # noqa: F401  (typeof of function values)
import numpy as np
from numba import types
from numba.core.errors import NumbaExperimentalFeatureWarning
from numba.core.types import WrapperAddressProtocol

from .. import _cc
from .._jit import cache_dir, jit

__all__ = ["BatchEngine", "available", "batch_engine_for", "beyond_bounds", "dense_linalg",
           "engine_for", "eval_series", "first_rows", "integrate_nb"]

# The slots of the engine's packed arguments, as engine.c numbers them (its enums).
#: float options
(O_RTOL, O_ATOL, O_H0, O_HMAX, O_HMIN, O_WALL, O_CHATTER_WINDOW, O_DT_OUT, O_EVENT_TOL,
 O_LU_REUSE) = range(10)
N_FOPT = 10
#: int options; ``iopt[I_STOP]`` is the one the engine reads while it runs: set to 1 (by
#: the signal watcher of ``simulate``), the run stops within 256 steps
(I_MAX_STEPS, I_CHATTER_N, I_MAX_OUTPUT, I_QUADRATURES, I_EXACT_JAC, I_JAC_MAX_AGE,
 I_FACTOR_SIZE, I_STOP) = range(8)
N_IOPT = 8
#: method scalars
M_FAMILY, M_GAMMA, M_Q, M_DENSE, M_W, M_FSAL = range(6)
N_MOPT = 6
#: statistics
S_STEPS, S_REJECTED, S_RHS, S_JAC, S_LU, S_EVENTS, S_OUTPUT, S_EV_CALLS = range(8)
N_STATS = 8

log = logging.getLogger("clutchsim")

# numba marks first-class function types experimental and warns at each use; clutchsim
# relies on them on purpose (the engine called from a sweep's batch: BatchEngine) and
# covers them with its own tests.
warnings.filterwarnings("ignore", category=NumbaExperimentalFeatureWarning,
                        message="First-class function type")

SOURCE = Path(__file__).with_name("engine.c")
#: cl_integrate's statuses beyond clutchsim.core.status.Code
UNSUPPORTED, NO_MEMORY = -1, -2
_P, _I, _I64, _D = ctypes.c_void_p, ctypes.c_int, ctypes.c_int64, ctypes.c_double
#: cl_integrate's argument types (engine.c): 7 plant functions; the tableau (7 arrays, s,
#: nh); mopt, ctrl, t0, t1, y0, n, p, bank, n_in, bps, n_bps, ev_dir, n_ev, n_outputs,
#: fopt, iopt; the rows (4 arrays, cap), the log (3 arrays, cap), stats, res, mem
_ARGTYPES = ([_P] * 7 + [_P] * 7 + [_I, _I] + [_P, _P, _D, _D, _P, _I, _P, _P, _I, _P, _I,
             _P, _I, _I, _P, _P] + [_P] * 4 + [_I64] + [_P] * 3 + [_I64] + [_P] * 3)
_EVENT_CAP = 256
#: engine.c's bounds on a plant (MAXN, MAXS, MAXEV, MAXOUT, MAXF, MAXRING): beyond them a
#: run takes scipy's reference backend
MAX_STATES, MAX_STAGES, MAX_EVENTS, MAX_OUTPUTS, MAX_FACTOR, MAX_CHATTER = (
    64, 16, 128, 512, 8192, 4096)

_lock = threading.Lock()
_state: dict = {}


def _build() -> Path:
    """The engine's shared library in the cache directory, compiled if it is not there
    (atomically: a reader never sees half a library; two processes both succeed)."""
    text = SOURCE.read_bytes()
    key = hashlib.sha256(text + repr(_cc.CFLAGS).encode()).hexdigest()[:16]
    base = Path(cache_dir) if cache_dir else Path(tempfile.gettempdir()) / "clutchsim-net"
    d = base / "engine"
    d.mkdir(parents=True, exist_ok=True)
    lib = d / f"clutchsim-engine-{key}.so"
    if not lib.exists():
        tmp = Path(tempfile.mkdtemp(prefix=".build-", dir=d))
        try:
            _cc.compile_shared([SOURCE], tmp / lib.name)
            os.replace(tmp / lib.name, lib)
        finally:
            shutil.rmtree(tmp, ignore_errors=True)
    return lib


def _library():
    """The loaded engine (its ``cl_integrate`` with argument types set), or None where it
    cannot be built or loaded here (said once per process)."""
    with _lock:
        if "lib" not in _state:
            try:
                lib = ctypes.CDLL(str(_build()))
                lib.cl_integrate.argtypes = _ARGTYPES
                lib.cl_integrate.restype = ctypes.c_int
                lib.cl_free.argtypes = [_P]
                lib.cl_free.restype = None
                lib.cl_eval_series.argtypes = [_P, _I, _P, _P, _P]
                lib.cl_eval_series.restype = None
                lib.cl_invert_nb.argtypes = [_I64, _D, _I64, _I64, _I64, _I64]
                lib.cl_invert_nb.restype = _I64
                lib.cl_solve_into_row_nb.argtypes = [_I64] * 6
                lib.cl_solve_into_row_nb.restype = None
                _state["lib"] = lib
            except (_cc.CompilerError, OSError) as exc:
                _state["lib"] = None
                log.warning("the C integration engine is not available here, runs take "
                            "scipy's reference backend (slower, and its own numbers): %s", exc)
        return _state["lib"]


def available() -> bool:
    """Can this process run the C engine (compiled or loaded from the cache)?"""
    return _library() is not None


def eval_series(bank: np.ndarray, n_channels: int, t: np.ndarray, out: np.ndarray) -> bool:
    """The first channel of the signal bank ``bank`` (``n_channels`` channels) at each of
    the contiguous float64 times ``t`` into ``out`` (:meth:`clutchsim.core.signals.Signal.
    __call__`), by the engine's own input evaluation; False where the engine is not
    available (the caller evaluates with numba's, the same bits)."""
    lib = _library()
    if lib is None:
        return False
    u = np.zeros(max(n_channels, 1))
    lib.cl_eval_series(bank.ctypes.data, t.size, t.ctypes.data, u.ctypes.data,
                       out.ctypes.data)
    return True


def beyond_bounds(args, n_states: int) -> str:
    """Why the engine cannot run a plant of ``n_states`` states with the loop arguments
    ``args`` (its bounds: :data:`MAX_STATES` and the others), or "" where it can."""
    tab, bank, ev_dir, n_outputs, iopt = args[1], args[8], args[10], args[11], args[13]
    over = [(what, got, most) for what, got, most in (
        ("states", n_states, MAX_STATES), ("stages of the method", tab[2].shape[0], MAX_STAGES),
        ("event functions", ev_dir.shape[0], MAX_EVENTS), ("outputs", n_outputs, MAX_OUTPUTS),
        ("inputs", bank.n_channels, MAX_STATES),
        ("floats of the plant's factors", int(iopt[I_FACTOR_SIZE]), MAX_FACTOR),
        ("chatter_events", int(iopt[I_CHATTER_N]), MAX_CHATTER)) if got > most]
    return "; ".join(f"{got} {what}, beyond the C engine's {most}" for what, got, most in over)


def first_rows(t0: float, t1: float, dt_out: float, max_output: int) -> int:
    """The rows a run's first buffers hold: the output grid and 256 more (events); with
    every step a row, 4,096.  The engine grows them where a run needs more."""
    if dt_out > 0:
        return 256 + int(min((t1 - t0) / dt_out + 2.0, 1e6, max(max_output, 0)))
    return 4096


def _ready(args, n_states: int):
    """The engine's library for runs with the loop arguments ``args`` (``args[0]``: the
    plant's C functions) of a plant of ``n_states`` states, or None where they cannot
    take it: no engine on this machine, or a plant beyond its bounds."""
    if args[0] is None or beyond_bounds(args, n_states):
        return None
    return _library()


def _ptr(a: np.ndarray) -> int:
    return a.__array_interface__["data"][0]


def _adopt(lib, address: int, count: int, dtype, shape) -> np.ndarray:
    """``count`` items at ``address`` (memory the engine handed over) as an array that
    frees it when it is gone."""
    dtype = np.dtype(dtype)
    buf = (ctypes.c_char * max(count * dtype.itemsize, 1)).from_address(address)
    weakref.finalize(buf, lib.cl_free, address)
    return np.frombuffer(buf, dtype=dtype, count=count).reshape(shape)


class _Engine:
    """The C engine for one prepared run (the loop's arguments but the initial state, the
    parameters and the int options): ``engine(args)`` runs it on ``args`` and returns
    ``(code, t_end, info_k, info_i, ts, ys, us, outs, ev_t, ev_k, ev_a, stats, h_smallest,
    wall)``."""

    __slots__ = ("fixed", "fns", "lib", "n_rows")

    def __init__(self, lib, args):
        (fns, tab, mopt, ctrl, t0, t1, _, _, bank, bps, ev_dir, n_outputs, fopt, iopt) = args
        keep = [np.ascontiguousarray(x, dtype=np.float64) for x in tab]
        keep += [np.ascontiguousarray(x, dtype=np.float64) for x in (mopt, ctrl, bank.data,
                                                                       bps, fopt)]
        keep.append(np.ascontiguousarray(ev_dir, dtype=np.int64))
        a, C, c, d, m, e, H, mopt_, ctrl_, bank_, bps_, fopt_, ev_ = keep
        self.lib = lib
        self.fns = tuple(f or None for f in fns)
        self.n_rows = first_rows(t0, t1, float(fopt[O_DT_OUT]),
                                 int(iopt[I_MAX_OUTPUT]))
        #: (arguments after the functions up to y0, then bank to iopt) and what they point to
        self.fixed = (
            (*map(_ptr, (a, C, c, d, m, e, H)), c.shape[0], H.shape[0], _ptr(mopt_),
             _ptr(ctrl_), float(t0), float(t1)),
            (_ptr(bank_), int(bank.n_channels), _ptr(bps_), bps_.shape[0], _ptr(ev_),
             ev_.shape[0], int(n_outputs), _ptr(fopt_)),
            keep)

    def __call__(self, args):
        y0, p, iopt = args[6], args[7], args[13]
        head, mid, _ = self.fixed
        n, n_in, n_out_cols = y0.shape[0], mid[1], mid[6]
        cap = self.n_rows
        rows = (np.empty(cap), np.empty((cap, n)), np.empty((cap, n_in)),
                np.empty((cap, n_out_cols)))
        ev = (np.empty(_EVENT_CAP), np.empty(_EVENT_CAP, dtype=np.int64),
              np.empty(_EVENT_CAP, dtype=np.int64))
        stats = np.zeros(N_STATS, dtype=np.int64)
        res = np.zeros(5)
        mem = np.zeros(9, dtype=np.int64)
        status = self.lib.cl_integrate(
            *self.fns, *head, _ptr(y0), n, _ptr(p), *mid, _ptr(iopt), *map(_ptr, rows), cap,
            *map(_ptr, ev), _EVENT_CAP, _ptr(stats), _ptr(res), _ptr(mem))
        if status == UNSUPPORTED:     # engine_for checked the bounds: a bug if it happens
            raise RuntimeError("the C engine refused a plant within its bounds (states "
                               f"{n}, inputs {n_in}, outputs {n_out_cols})")
        k, ne = int(stats[S_OUTPUT]), int(stats[S_EVENTS])
        if mem[0]:
            widths = (1, n, n_in, n_out_cols)
            rows = tuple(_adopt(self.lib, int(mem[1 + j]), k * w, np.float64,
                                (k,) if j == 0 else (k, w)) for j, w in enumerate(widths))
        if mem[5]:
            ev = tuple(_adopt(self.lib, int(mem[6 + j]), ne, dt, (ne,))
                       for j, dt in enumerate((np.float64, np.int64, np.int64)))
        if status == NO_MEMORY:
            raise MemoryError("the integration engine could not grow its output rows or "
                              f"event log beyond {k} rows and {ne} events")
        ts, ys, us, outs = rows
        return (status, float(res[0]), int(res[3]), int(res[4]), ts[:k], ys[:k], us[:k],
                outs[:k], ev[0][:ne], ev[1][:ne], ev[2][:ne], stats, float(res[1]),
                float(res[2]))


def engine_for(args, n_states: int):
    """The C engine for runs with the loop arguments ``args`` (those of a prepared run,
    :func:`clutchsim.core.simulate.prepare_runs`) of a plant of ``n_states`` states, or
    None where they cannot take it (no engine on this machine, a plant beyond its bounds:
    :func:`beyond_bounds`)."""
    lib = _ready(args, n_states)
    return None if lib is None else _Engine(lib, args)


_I64T = types.int64
#: cl_integrate_nb's signature (engine.c): every integer and pointer an int64, t0 and t1
ENGINE_SIG = _I64T(*([_I64T] * 18 + [types.float64] * 2 + [_I64T] * 24))
FREE_SIG = types.void(_I64T)


class _Address(WrapperAddressProtocol):
    """A C function at ``address`` as a numba function value of signature ``sig`` (all its
    arguments scalars: numba calls it as a plain C function); ``keep``: what must outlive
    the address (the library)."""

    def __init__(self, address: int, sig, keep):
        self.address, self.sig, self.keep = int(address), sig, keep

    def __wrapper_address__(self):
        return self.address

    def signature(self):
        return self.sig


class BatchEngine(NamedTuple):
    """What a loop compiled by numba needs to run the C engine
    (:mod:`clutchsim.analysis.launch_batch`): ``integrate`` (``cl_integrate_nb``) and
    ``free`` (``cl_free_nb``) as function values, and the C addresses of the plant's seven
    functions (0 where the run does not call one)."""

    integrate: object
    free: object
    plant: np.ndarray


def batch_engine_for(args, n_states: int) -> BatchEngine | None:
    """The C engine for compiled callers of runs with the loop arguments ``args`` of a
    plant of ``n_states`` states, or None where they cannot take it (as
    :func:`engine_for`)."""
    lib = _ready(args, n_states)
    if lib is None:
        return None
    address = ctypes.cast(lib.cl_integrate_nb, ctypes.c_void_p).value
    free = ctypes.cast(lib.cl_free_nb, ctypes.c_void_p).value
    return BatchEngine(_Address(address, ENGINE_SIG, lib), _Address(free, FREE_SIG, lib),
                       np.array(args[0], dtype=np.int64))


#: cl_invert_nb's and cl_solve_into_row_nb's signatures (engine.c)
INVERT_SIG = _I64T(_I64T, types.float64, _I64T, _I64T, _I64T, _I64T)
SOLVE_ROW_SIG = types.void(*([_I64T] * 6))


def dense_linalg():
    """``(invert, solve_into_row)``: the engine's dense inverse of the leading block of a
    step's iteration matrix ``c·I − J`` and its stage solve into a row (engine.c's
    ``cl_invert_nb``, ``cl_solve_into_row_nb``) as numba function values of addresses and
    sizes, for tests and ``benchmarks/step_cost.py``; None where there is no engine."""
    lib = _library()
    if lib is None:
        return None
    return tuple(_Address(ctypes.cast(f, ctypes.c_void_p).value, sig, lib) for f, sig in (
        (lib.cl_invert_nb, INVERT_SIG), (lib.cl_solve_into_row_nb, SOLVE_ROW_SIG)))


@jit(inline="always")
def _a(x):
    """The address of the array ``x``'s data, as the engine's int64."""
    return np.int64(x.ctypes.data)


@jit
def integrate_nb(eng, free, plant, tab, mopt, ctrl, t0, t1, y0, p, bank, bps, ev_dir,
                 n_outputs, fopt, iopt, cap):
    """One run of the C engine from numba (``eng``, ``free``, ``plant``: a
    :class:`BatchEngine`), with the loop arguments after the plant's functions and
    ``cap`` rows to start with; returns what :class:`_Engine` returns.  Where the run
    outgrew the rows or the event log, the engine's own memory is freed and the run made
    again with room for all of it (the same run: the parameters are restored first)."""
    n = y0.shape[0]
    n_in = bank.n_channels
    p0 = p.copy()
    ecap = 256
    while True:
        ts = np.empty(cap)
        ys = np.empty((cap, n))
        us = np.empty((cap, n_in))
        outs = np.empty((cap, n_outputs))
        ev_t = np.empty(ecap)
        ev_k = np.empty(ecap, dtype=np.int64)
        ev_a = np.empty(ecap, dtype=np.int64)
        stats = np.zeros(N_STATS, dtype=np.int64)
        res = np.zeros(5)
        mem = np.zeros(9, dtype=np.int64)
        code = eng(plant[0], plant[1], plant[2], plant[3], plant[4], plant[5], plant[6],
                   _a(tab[0]), _a(tab[1]), _a(tab[2]), _a(tab[3]), _a(tab[4]), _a(tab[5]),
                   _a(tab[6]), np.int64(tab[2].shape[0]), np.int64(tab[6].shape[0]),
                   _a(mopt), _a(ctrl), t0, t1, _a(y0), np.int64(n), _a(p), _a(bank.data),
                   np.int64(n_in), _a(bps), np.int64(bps.shape[0]), _a(ev_dir),
                   np.int64(ev_dir.shape[0]), np.int64(n_outputs), _a(fopt), _a(iopt),
                   _a(ts), _a(ys), _a(us), _a(outs), np.int64(cap), _a(ev_t), _a(ev_k),
                   _a(ev_a), np.int64(ecap), _a(stats), _a(res), _a(mem))
        if mem[0] == 0 and mem[5] == 0:
            break
        for j in range(1, 5):
            if mem[0] != 0 and mem[j] != 0:
                free(mem[j])
        for j in range(6, 9):
            if mem[5] != 0 and mem[j] != 0:
                free(mem[j])
        if code == NO_MEMORY:
            raise MemoryError("the integration engine could not grow its rows or event log")
        cap = max(2 * cap, stats[S_OUTPUT] * 2 + 16)
        ecap = max(2 * ecap, stats[S_EVENTS] * 2 + 16)
        for i in range(p.shape[0]):
            p[i] = p0[i]
    k = stats[S_OUTPUT]
    ne = stats[S_EVENTS]
    return (code, res[0], np.int64(res[3]), np.int64(res[4]), ts[:k], ys[:k], us[:k],
            outs[:k], ev_t[:ne], ev_k[:ne], ev_a[:ne], stats, res[1], res[2])
