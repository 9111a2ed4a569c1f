"""The compiled integration loop, for code that drives it from its own compiled loop.

:func:`clutchsim.core.simulate` calls :func:`integrate` once per run from Python.  A caller
that runs many variants of one system in one compiled call (a sweep's chunk:
:mod:`clutchsim.analysis.launch_batch`) calls it from numba instead, with the arguments
:func:`clutchsim.core.simulate.prepare_runs` builds, and reads its counters at the
``S_*`` slots.  :func:`now` is the monotonic clock the loop's wall-time budget reads.
:func:`run_loop` is one run in the C engine (:mod:`clutchsim.core.cengine`) or, where the
caller has none for the plant, in :func:`integrate`: numba compiles only the one its
arguments' types choose (a branch on ``c_eng is None`` compiled both: the numba loop's
59 s inside every C-engine batch's first compilation, measured).
"""

from numba import types
from numba.extending import overload

from ._clock import now
from ._driver import (
    N_STATS,
    S_EV_CALLS,
    S_EVENTS,
    S_JAC,
    S_LU,
    S_OUTPUT,
    S_REJECTED,
    S_RHS,
    S_STEPS,
    integrate,
)
from .cengine import integrate_nb

__all__ = ["N_STATS", "S_EVENTS", "S_EV_CALLS", "S_JAC", "S_LU", "S_OUTPUT", "S_REJECTED",
           "S_RHS", "S_STEPS", "integrate", "now", "run_loop"]


def run_loop(c_eng, c_free, c_plant, fns, tab, mopt, ctrl, t0, t1, y0, p, bank, bps, ev_dir,
             n_outputs, fopt, iopt, c_rows):
    """Compiled-only: one run, returning what :func:`integrate` returns: in the C engine
    (``c_eng``, ``c_free``, ``c_plant``: a :class:`~clutchsim.core.cengine.BatchEngine`;
    ``c_rows`` its first rows) or, with ``c_eng`` None, in the numba loop on the plant's
    function values ``fns``."""
    raise NotImplementedError("run_loop is only callable from compiled code")


@overload(run_loop, jit_options={"cache": True})
def _run_loop_impl(c_eng, c_free, c_plant, fns, tab, mopt, ctrl, t0, t1, y0, p, bank, bps,
                   ev_dir, n_outputs, fopt, iopt, c_rows):
    if isinstance(c_eng, types.NoneType):
        def numba_loop(c_eng, c_free, c_plant, fns, tab, mopt, ctrl, t0, t1, y0, p, bank, bps,
                       ev_dir, n_outputs, fopt, iopt, c_rows):
            return integrate(fns, tab, mopt, ctrl, t0, t1, y0, p, bank, bps, ev_dir,
                             n_outputs, fopt, iopt)
        return numba_loop

    def c_engine(c_eng, c_free, c_plant, fns, tab, mopt, ctrl, t0, t1, y0, p, bank, bps,
                 ev_dir, n_outputs, fopt, iopt, c_rows):
        return integrate_nb(c_eng, c_free, c_plant, tab, mopt, ctrl, t0, t1, y0, p, bank,
                            bps, ev_dir, n_outputs, fopt, iopt, c_rows)
    return c_engine
