"""What the integrators integrate: a compiled right-hand side with events, resets and outputs.

A plant (a friction test rig, a driveline, ...) defines four compiled functions, and up to
three optional ones,

``rhs(t, y, u, p, dy)``
    writes the state derivatives ``dy``;
``events(t, y, u, p, g)``
    writes the event-function values ``g`` (an event fires when ``g[k]`` crosses zero in
    its declared direction; a directional event whose function *starts* on its
    post-crossing side fires once at the initial time);
``reset(t, y, u, p, k) -> action``
    called at the located event ``k``; may change ``y`` in place (a *reset map*) and returns
    one of :data:`CONTINUE`, :data:`STATE_CHANGED`, :data:`STOP`, :data:`FAIL`, :data:`PASS`;
``outputs(t, y, u, p, out)``
    writes algebraic output signals (forces, powers, ...),
``jac(t, y, u, p, J)`` (optional)
    writes the exact Jacobian ``J[i, j] = d dy_i / d y_j`` (an ``(n, n)`` C-contiguous
    array, every entry, the quadrature columns included) at fixed inputs ``u``.  Without
    it the implicit integrators difference the right-hand side (one call per state).
``factor(c, J, F) -> ok`` and ``solve(F, b, X, r)`` (optional, with ``jac``)
    the plant's own solver for the iteration matrix ``M = c·I − J`` of the implicit
    stages, written for the sparsity of its Jacobian (the network plants generate them
    per topology, :mod:`clutchsim.network.elimination`): ``factor`` writes its factors to
    ``F`` (``factor_size`` floats) and returns 1, or returns 0 when it cannot factor this
    ``M`` safely, and the integrator inverts ``M`` densely for that step; ``solve`` writes
    ``X[r] = M⁻¹·b`` (``b`` is not a row of ``X``; quadrature rows included, as the dense
    path solves them).

where ``t`` is time [s], ``y`` the state vector, ``u`` the input vector and ``p`` a float
parameter vector (all arrays float64, C-contiguous).  It registers them under a *tag
type* (a ``NamedTuple`` subclass) with :func:`register_system`.

The plant's functions reach the integrators as C functions (the C engine,
:mod:`clutchsim.core.cengine`): a printed plant's own (:class:`NativeFunction`), or for
numba functions an adapter per function (:mod:`clutchsim.core._cfunctions`) that views the
engine's pointers as the arrays of the signatures :data:`KERNEL_SIG`, :data:`RESET_SIG`,
:data:`JAC_SIG`, :data:`FACTOR_SIG` and :data:`SOLVE_SIG`.  A plant family with variants
(the rig, one per friction model) registers one tag per variant with functions that fold
the variant in (closures over a constant compiled under their own names), not a run-time
dispatch.

The core knows nothing of friction: only these functions.
"""

from __future__ import annotations

import copy
import difflib
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
from numba import types

from .._jit import jit
from .status import Action

__all__ = [
    "CONTINUE",
    "FAIL",
    "PASS",
    "STATE_CHANGED",
    "STOP",
    "NativeFunction",
    "System",
    "closest",
    "register_system",
]

#: reset actions (see :class:`~clutchsim.core.status.Action`), as plain names for plants
CONTINUE = Action.CONTINUE
STATE_CHANGED = Action.STATE_CHANGED
STOP = Action.STOP
FAIL = Action.FAIL
PASS = Action.PASS


class _Functions(NamedTuple):
    rhs: object
    events: object
    reset: object
    outputs: object
    jac: object
    has_jac: bool
    factor: object
    solve: object
    factor_size: int


_REGISTRY: dict[type, _Functions] = {}

_ARRAY = types.float64[::1]
#: signature of rhs, events and outputs: (t, y, u, p, out) -> None
KERNEL_SIG = types.void(types.float64, _ARRAY, _ARRAY, _ARRAY, _ARRAY)
#: signature of reset: (t, y, u, p, k) -> action
RESET_SIG = types.int64(types.float64, _ARRAY, _ARRAY, _ARRAY, types.int64)
#: signature of jac: (t, y, u, p, J) -> None, J of shape (n, n)
JAC_SIG = types.void(types.float64, _ARRAY, _ARRAY, _ARRAY, types.float64[:, ::1])
#: signature of factor: (c, J, F) -> 1 (factored) or 0 (use the dense inverse)
FACTOR_SIG = types.int64(types.float64, types.float64[:, ::1], _ARRAY)
#: signature of solve: (F, b, X, r) -> None, writes row r of X
SOLVE_SIG = types.void(_ARRAY, _ARRAY, types.float64[:, ::1], types.int64)


class NativeFunction:
    """A plant function compiled outside numba (a C shared library, :mod:`clutchsim.cgen`).

    ``c_address`` is the function with plain C pointers (the ``cs_`` entry of a printed
    plant), which the C engine calls (:mod:`clutchsim.core.cengine`); ``call`` runs the same
    function from Python (``ctypes``), so a native plant function is called like a compiled
    one: ``f(t, y, u, p, out)``.  ``keep`` holds what must outlive the address (the loaded
    library).
    """

    def __init__(self, c_address: int, call, keep=None):
        if not c_address:
            raise ValueError("native function: null address")
        self.c_address = int(c_address)
        self._call = call
        self._keep = keep

    def __call__(self, *args):
        return self._call(*args)


def plant_functions(tag):
    """The compiled functions registered for ``tag``: a named tuple (rhs, events, reset,
    outputs, jac, has_jac, factor, solve, factor_size), e.g. to time a plant alone in a
    compiled loop."""
    return _REGISTRY[type(tag)]


def has_jacobian(tag) -> bool:
    """Did the plant of ``tag`` register an exact Jacobian?"""
    return _REGISTRY[type(tag)].has_jac


def factor_size(tag) -> int:
    """Floats of the factors of the plant's own iteration-matrix solver (0: it has none,
    the integrators invert densely)."""
    return _REGISTRY[type(tag)].factor_size


@jit
def _no_events(t, y, u, p, g):
    pass


@jit
def _no_reset(t, y, u, p, k):
    return 0


@jit
def _no_outputs(t, y, u, p, out):
    pass


@jit
def _no_jac(t, y, u, p, J):
    pass


@jit
def _no_factor(c, J, F):
    return 0


@jit
def _no_solve(F, b, X, r):
    pass


def register_system(tag: type, *, rhs, events=None, reset=None, outputs=None,
                    jac=None, factor=None, solve=None, factor_size: int = 0) -> type:
    """Register the compiled functions of a plant under the ``NamedTuple`` type ``tag``.

    The functions reach the integrators as function values (see the module docstring),
    so they must accept float64 C-contiguous arrays.  Each is a numba-compiled function or
    a :class:`NativeFunction` (compiled elsewhere: the network plants' C,
    :mod:`clutchsim.cgen`).

    ``jac``: the exact Jacobian ``jac(t, y, u, p, J)`` (see the module docstring); the
    implicit integrators use it instead of finite differences.

    ``factor``, ``solve``, ``factor_size``: the plant's own solver of the iteration matrix
    (see the module docstring); only with ``jac`` (the pattern it is written for is the
    exact Jacobian's).
    """
    if not (isinstance(tag, type) and issubclass(tag, tuple) and hasattr(tag, "_fields")):
        raise TypeError(f"tag must be a NamedTuple class, got {tag!r}")
    if (factor is None) != (solve is None) or (factor is not None) != (factor_size > 0):
        raise ValueError(f"{tag.__name__}: factor, solve and factor_size > 0 go together "
                         f"(got factor={factor!r}, solve={solve!r}, "
                         f"factor_size={factor_size!r})")
    if factor is not None and jac is None:
        raise ValueError(f"{tag.__name__}: factor and solve need the exact jac they are "
                         "written for")
    _REGISTRY[tag] = _Functions(rhs, events or _no_events, reset or _no_reset,
                                outputs or _no_outputs, jac or _no_jac, jac is not None,
                                factor or _no_factor, solve or _no_solve,
                                int(factor_size))
    return tag


# Python-callable entry points (the scipy reference backend, linearisation, checks, tests):
# the registered functions called from Python, compiled functions and native ones alike.
def call_rhs(tag, t, y, u, p, dy):
    _REGISTRY[type(tag)].rhs(t, y, u, p, dy)


def call_events(tag, t, y, u, p, g):
    _REGISTRY[type(tag)].events(t, y, u, p, g)


def call_reset(tag, t, y, u, p, k):
    return _REGISTRY[type(tag)].reset(t, y, u, p, k)


def call_outputs(tag, t, y, u, p, out):
    _REGISTRY[type(tag)].outputs(t, y, u, p, out)


def call_jac(tag, t, y, u, p, J):
    _REGISTRY[type(tag)].jac(t, y, u, p, J)


def call_factor(tag, c, J, F):
    return _REGISTRY[type(tag)].factor(c, J, F)


def call_solve(tag, F, b, X, r):
    _REGISTRY[type(tag)].solve(F, b, X, r)


def closest(name: str, valid) -> str:
    """`` (did you mean 'x'?)`` for the closest valid name, or an empty string."""
    valid = [str(v) for v in valid]
    match = difflib.get_close_matches(str(name), valid, n=1, cutoff=0.5)
    if not match:  # abbreviations and case: 'Force' -> 'F', 'LUGRE' -> 'lugre'
        low = str(name).lower()
        match = [v for v in valid if v.lower() == low] or \
            [v for v in valid if low.startswith(v.lower()) or v.lower().startswith(low)]
    return f" (did you mean {match[0]!r}?)" if match else ""


def _names(value, what: str) -> tuple[str, ...]:
    out = tuple(value)
    if not all(isinstance(x, str) for x in out):
        raise TypeError(f"{what} must be strings, got {out!r}")
    return out


@dataclass(frozen=True, eq=False)
class System:
    """A plant ready to simulate: its tag, parameter vector and named, unit-carrying signals.

    Parameters
    ----------
    tag : NamedTuple
        Instance of a tag type registered with :func:`register_system`.
    params : ndarray
        Float parameter vector ``p`` passed to every compiled function.
    y0 : ndarray
        Default initial state.
    state_names, state_units : sequence of str
        One per state.
    input_names, input_units : sequence of str
        One per input channel ``u``.
    output_names, output_units : sequence of str
        One per algebraic output.
    event_names : sequence of str
        One per event function.
    event_directions : sequence of int
        −1 (falling), +1 (rising) or 0 (both), one per event function.
    event_sources : sequence of str, optional
        The part of the plant each event function belongs to (a component's name), kept
        with the located events (:attr:`Event.source`) and the result
        (:attr:`Result.event_source`) so that code can tell which part ended a run without
        reading its name; default ``""`` for each.
    name : str
        Human-readable name used in messages.
    quadratures : int
        Number of trailing states that are pure integrals (energy accounts): no derivative
        depends on them.  The implicit integrators leave them out of the finite-difference
        Jacobian and the inverted block of the iteration matrix (their columns are
        zero); default 0.
    metadata : dict
        Free-form description kept with results (scenario, model, parameter set, ...).
    invariants : callable, optional
        The plant's physics checks, run on every result: ``invariants(ts, ys, outs, rtol,
        atol)`` with the run's times, states and outputs returns a list of violations,
        objects with ``text`` (what, where, the values) and ``fatal`` (the result is wrong,
        not only at the edge of the tolerances).  A fatal one makes the run's outcome
        :attr:`~clutchsim.core.Outcome.INVARIANT_VIOLATED`, the others are warnings
        (:mod:`clutchsim.network.invariants` for a network's).  The core knows nothing of
        what they check.
    """

    tag: tuple
    params: np.ndarray
    y0: np.ndarray
    state_names: tuple[str, ...]
    state_units: tuple[str, ...]
    input_names: tuple[str, ...] = ()
    input_units: tuple[str, ...] = ()
    output_names: tuple[str, ...] = ()
    output_units: tuple[str, ...] = ()
    event_names: tuple[str, ...] = ()
    event_directions: tuple[int, ...] = ()
    name: str = "system"
    metadata: dict = field(default_factory=dict)
    quadratures: int = 0
    event_sources: tuple[str, ...] = ()
    invariants: Callable | None = field(default=None, compare=False, repr=False)

    def __post_init__(self):
        if type(self.tag) not in _REGISTRY:
            raise TypeError(f"{self.name}: tag type {type(self.tag).__name__} is not registered "
                            "(call register_system first)")
        p = np.ascontiguousarray(self.params, dtype=np.float64).ravel()
        y0 = np.ascontiguousarray(self.y0, dtype=np.float64).ravel()
        object.__setattr__(self, "params", p)
        object.__setattr__(self, "y0", y0)
        for attr in ("state_names", "state_units", "input_names", "input_units",
                     "output_names", "output_units", "event_names"):
            object.__setattr__(self, attr, _names(getattr(self, attr), attr))
        object.__setattr__(self, "event_directions", tuple(int(d) for d in self.event_directions))
        sources = tuple(str(s) for s in self.event_sources) or ("",) * len(self.event_names)
        object.__setattr__(self, "event_sources", sources)
        pairs = [("state_names", "state_units"), ("input_names", "input_units"),
                 ("output_names", "output_units"), ("event_names", "event_directions"),
                 ("event_names", "event_sources")]
        for a, b in pairs:
            if len(getattr(self, a)) != len(getattr(self, b)):
                raise ValueError(f"{self.name}: {a} and {b} differ in length")
        if len(self.state_names) != y0.size:
            raise ValueError(f"{self.name}: y0 has {y0.size} entries for "
                             f"{len(self.state_names)} states")
        q = self.quadratures
        if isinstance(q, bool) or not isinstance(q, (int, np.integer)) or \
                not 0 <= q < max(y0.size, 1):
            raise ValueError(f"{self.name}: quadratures = {q!r} must be an integer in "
                             f"[0, {max(y0.size - 1, 0)}] (trailing pure-integral states; at "
                             "least one state must remain in the implicit solve)")
        if any(d not in (-1, 0, 1) for d in self.event_directions):
            raise ValueError(f"{self.name}: event directions must be -1, 0 or +1, "
                             f"got {self.event_directions}")

    @property
    def n_states(self) -> int:
        return len(self.state_names)

    @property
    def n_events(self) -> int:
        return len(self.event_names)

    def with_values(self, params: np.ndarray, y0: np.ndarray,
                    event_names: tuple[str, ...] | None = None) -> System:
        """The same plant with another parameter vector and initial state (same layout,
        float64) and, where given, event names: a sweep's variant.  Only what changes is
        checked (the layout was checked when this system was made), so a variant costs
        microseconds, not the full construction."""
        p = np.ascontiguousarray(params, dtype=np.float64).ravel()
        y = np.ascontiguousarray(y0, dtype=np.float64).ravel()
        if p.size != self.params.size or y.size != self.y0.size:
            raise ValueError(f"{self.name}: a variant needs {self.params.size} parameters "
                             f"and {self.y0.size} initial states, got {p.size} and {y.size}")
        out = copy.copy(self)
        object.__setattr__(out, "metadata", dict(self.metadata))
        object.__setattr__(out, "params", p)
        object.__setattr__(out, "y0", y)
        if event_names is not None:
            names = _names(event_names, "event_names")
            if len(names) != len(self.event_names):
                raise ValueError(f"{self.name}: {len(names)} event names for "
                                 f"{len(self.event_names)} events")
            object.__setattr__(out, "event_names", names)
        return out

    def with_params(self, params: np.ndarray) -> System:
        """The same plant with another parameter vector (same layout)."""
        from dataclasses import replace
        return replace(self, params=params)
