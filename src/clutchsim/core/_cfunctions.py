"""A plant's functions as the C engine calls them: plain C functions of plain pointers.

The engine (``engine.c``) calls seven functions of fixed C signatures (its ``kern_t``,
``reset_t``, ``jac_t``, ``fac_t``, ``sol_t``): scalars and ``double *``, no shapes but
the Jacobian's order.  A printed plant (:mod:`clutchsim.cgen`: the networks and the
friction rig) has them already, its :class:`~.system.NativeFunction`'s ``c_address``.  A
plant of numba functions (:func:`~.system.register_system`: the reference problems, the
two-mass benchmark, the EMPS drive, a user's own plant) gets one adapter per function: a
numba ``cfunc`` that views the pointers as arrays of the plant's sizes (constants of the
adapter) and calls the registered function on them, with the arrays it would take from
the engine's own loop, of the same types.  ``cfunc`` is numba's documented way to give
a compiled function a C address; numba caches the adapters on disk (the sizes and the
function are part of the cache key), so a plant compiles its adapters once per machine
(~0.1–0.3 s each, measured) and a later process loads them.
"""

from __future__ import annotations

import threading
from typing import NamedTuple

import numpy as np
from numba import carray, cfunc, types
from numba.core.registry import CPUDispatcher

from .system import NativeFunction, System, factor_size, has_jacobian, plant_functions

__all__ = ["Sizes", "c_functions"]

_D = types.float64
_P = types.CPointer(types.float64)
_I = types.intc
#: engine.c's signatures: kern_t (rhs, events, outputs), reset_t, jac_t, fac_t, sol_t
_KERNEL = types.void(_D, _P, _P, _P, _P)
_RESET = _I(_D, _P, _P, _P, _I)
_JAC = types.void(_D, _P, _P, _P, _P, _I)
_FACTOR = _I(_D, _P, _I, _P)
_SOLVE = types.void(_P, _P, _P, _I, _I)


class Sizes(NamedTuple):
    """The lengths of a plant's arrays: states, inputs, parameters, outputs, event
    functions, floats of its factors."""

    n: int
    n_in: int
    n_p: int
    n_out: int
    n_ev: int
    n_factor: int

    @classmethod
    def of(cls, system: System) -> Sizes:
        return cls(system.n_states, len(system.input_names), int(system.params.size),
                   len(system.output_names), system.n_events, factor_size(system.tag))


# One builder per signature: each closes over the registered function and the sizes only
# (numba keys its cache on the closure's values).  The engine passes its scratch arrays,
# never null, so a length of 0 is a valid view.
def _kernel(f, n, n_in, n_p, n_out):
    @cfunc(_KERNEL, cache=True)
    def adapter(t, y, u, p, out):
        f(t, carray(y, n), carray(u, n_in), carray(p, n_p), carray(out, n_out))
    return adapter


def _reset(f, n, n_in, n_p):
    @cfunc(_RESET, cache=True)
    def adapter(t, y, u, p, k):
        return f(t, carray(y, n), carray(u, n_in), carray(p, n_p), np.int64(k))
    return adapter


def _jac(f, n, n_in, n_p):
    @cfunc(_JAC, cache=True)
    def adapter(t, y, u, p, J, order):
        f(t, carray(y, n), carray(u, n_in), carray(p, n_p), carray(J, (order, order)))
    return adapter


def _factor(f, n_factor):
    @cfunc(_FACTOR, cache=True)
    def adapter(c, J, order, F):
        return f(c, carray(J, (order, order)), carray(F, n_factor))
    return adapter


def _solve(f, n_factor, n):
    # the engine's X is its stage matrix, of rows of n; the function writes row r
    @cfunc(_SOLVE, cache=True)
    def adapter(F, b, X, order, r):
        f(carray(F, n_factor), carray(b, order), carray(X, (r + 1, order)), np.int64(r))
    return adapter


_lock = threading.Lock()
#: (plant type, sizes) -> (the seven addresses, the adapters that own them)
_ADAPTED: dict = {}


def _address(f, build, *sizes) -> tuple[int, object]:
    """The C address of plant function ``f``: its own where it is printed C, else that
    of its adapter (``build(f, *sizes)``), with what must stay alive for it."""
    if isinstance(f, NativeFunction):
        return f.c_address, f
    if not isinstance(f, CPUDispatcher):
        raise TypeError(f"plant function {f!r} is neither numba-compiled (@numba.njit) nor "
                        "printed C; register_system takes those")
    adapter = build(f, *sizes)
    return adapter.address, adapter


def c_functions(system: System) -> tuple[int, ...]:
    """The C addresses of ``system``'s (rhs, events, reset, outputs, jac, factor, solve)
    as the engine calls them; 0 for the Jacobian without an exact one and for the
    factors without a factor size (the run does not call those).  Built once per plant
    type and sizes in a process (adapters compiled or loaded from numba's cache)."""
    sizes = Sizes.of(system)
    key = (type(system.tag), sizes)
    with _lock:
        hit = _ADAPTED.get(key)
        if hit is None:
            fns = plant_functions(system.tag)
            n, n_in, n_p, n_out, n_ev, n_factor = sizes
            made = [_address(fns.rhs, _kernel, n, n_in, n_p, n),
                    _address(fns.events, _kernel, n, n_in, n_p, n_ev),
                    _address(fns.reset, _reset, n, n_in, n_p),
                    _address(fns.outputs, _kernel, n, n_in, n_p, n_out)]
            exact = has_jacobian(system.tag)
            made.append(_address(fns.jac, _jac, n, n_in, n_p) if exact else (0, None))
            if n_factor > 0:
                made += [_address(fns.factor, _factor, n_factor),
                         _address(fns.solve, _solve, n_factor, n)]
            else:
                made += [(0, None), (0, None)]
            hit = _ADAPTED[key] = (tuple(a for a, _ in made), tuple(k for _, k in made))
    return hit[0]
