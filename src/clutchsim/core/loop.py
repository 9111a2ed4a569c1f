"""The compiled integration loop, for code that drives it from its own compiled loop.

:func:`clutchsim.core.simulate` calls :func:`integrate` once per run from Python.  A caller
that runs many variants of one system in one compiled call (a sweep's chunk:
:mod:`clutchsim.analysis.launch_batch`) calls it from numba instead, with the arguments
:func:`clutchsim.core.simulate.prepare_runs` builds, and reads its counters at the
``S_*`` slots.  :func:`now` is the monotonic clock the loop's wall-time budget reads.
"""

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

__all__ = ["N_STATS", "S_EVENTS", "S_EV_CALLS", "S_JAC", "S_LU", "S_OUTPUT", "S_REJECTED",
           "S_RHS", "S_STEPS", "integrate", "now"]
