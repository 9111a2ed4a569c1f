"""Compile the launch metrics in a second process while this one compiles the integrator.

From an empty numba cache (a fresh install, or clutchsim changed) a sweep's first batch
compiles its batch loop and the launch-metrics kernel (~22 s) it calls: numba compiles in
one thread, under one lock.  The metrics need no integrator: a child process compiles the
kernel's one signature (single runs and batches pass it contiguous columns) into the same
on-disk cache meanwhile, from which this process then loads it.  A single run has nothing
to compile beside the metrics (the C engine runs the plant: :mod:`clutchsim.core.cengine`),
and no child is started (measured, session 31: a fresh `clutchsim run` with a child that
the first analysis waits for took 45–53 s, without one 43–46 s; the child's start and the
two cores shared cost more than the few seconds of plant and engine building it overlaps).
A block with other work before its first launch (the demo's drift test) starts the child
in any case (``work_first``).  Within the block the first launch analysed waits for the
child (:func:`~clutchsim.analysis.launch_metrics.kernel_compiled_elsewhere`) where it would
otherwise compile the kernel itself, beside the child; its simulation runs meanwhile.  From
an empty cache the demo's kernel compiles while its drift test and first launch run.
With the metrics already in the cache no second process is started.  The child is
stopped when the guarded block ends; numba writes a cache file atomically, so stopping it
loses nothing.
"""

from __future__ import annotations

import contextlib
import logging
import multiprocessing
import os
from collections.abc import Iterator
from pathlib import Path

from .._jit import cache_dir
from ..analysis.launch_metrics import kernel_compiled_elsewhere

log = logging.getLogger("clutchsim")

__all__ = ["Beside", "metrics_compiled_beside"]


def _metrics_cached() -> bool:
    """Does numba's cache of this clutchsim version hold the launch-metrics kernel?  (Its
    index file, ``<module>.launch_kernel-<line>.py<ver>.nbi``: numba has no public query.
    A wrong answer costs time only: a needless child, or a compilation in series.)"""
    return bool(cache_dir) and any(Path(cache_dir).glob("*/*.launch_kernel-*.nbi"))


def _compile_metrics() -> None:
    """(In the child.) Compile the launch kernel for the types a sweep's batch calls it
    with, those of a single run too, then the energy balance for a single run's (nothing
    runs; nothing is kept).  A failure or an interrupt changes nothing but the time the
    parent takes."""
    logging.getLogger("clutchsim").setLevel(logging.CRITICAL)
    with contextlib.suppress(BaseException):
        import numba

        from ..analysis import _kernels
        from ..analysis.launch_batch import kernel_signature_example
        from ..analysis.launch_metrics import energy_balance_signature
        _kernels.launch_kernel.compile(
            tuple(numba.typeof(x) for x in kernel_signature_example()))
        _kernels.energy_balance.compile(energy_balance_signature())


#: seconds the first analysis waits for the child at most (the kernel compiles in ~22 s on
#: the 2-core machine, 17–24 s beside the demo's drift test; session 32)
WAIT_S = 600.0


class Beside:
    """The child compiling the launch metrics beside a block, if one was started."""

    def __init__(self, child=None):
        self._child = child

    @property
    def started(self) -> bool:
        return self._child is not None

    def wait(self, timeout: float = WAIT_S) -> None:
        """Wait until the child has compiled the metrics (or failed: this process then
        compiles them itself), instead of compiling them beside it; at most ``timeout``
        seconds (a child that hangs does not hang the run: this process then compiles
        them itself, and the child is stopped with the block)."""
        if self._child is not None and self._child.is_alive():
            log.info("launch metrics: waiting for the kernel compiling in a second process")
            self._child.join(timeout)
            if self._child.is_alive():
                log.warning("launch metrics: the second process has not compiled the kernel "
                            "in %.0f s; compiling it here", timeout)


@contextlib.contextmanager
def metrics_compiled_beside(batch: bool = False, *, work_first: bool = False
                            ) -> Iterator[Beside]:
    """Guard a block that runs launches (``batch``: a sweep's batches of launches): if the
    metrics are not compiled yet, a second core exists and this process compiles a batch
    loop meanwhile or has other work to do first (``work_first``), a child process compiles
    them meanwhile, and the first launch analysed waits for it (see the module
    docstring)."""
    if ((os.cpu_count() or 1) < 2 or _metrics_cached()
            or not (work_first or batch)):
        yield Beside()
        return
    child = multiprocessing.get_context("spawn").Process(
        target=_compile_metrics, name="clutchsim-metrics-compile", daemon=True)
    child.start()
    beside = Beside(child)
    try:
        with kernel_compiled_elsewhere(beside.wait):
            yield beside
    finally:
        if child.is_alive():
            child.terminate()
        child.join()
