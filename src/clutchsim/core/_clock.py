"""A monotonic clock for compiled code: the integrators' wall-time budget.

On 64-bit POSIX systems the compiled code calls ``clock_gettime(CLOCK_MONOTONIC)`` of the C
library directly (the clock behind :func:`time.perf_counter` on Linux).  An
``objmode`` block calling :func:`time.perf_counter` would do the same, but numba compiles
an ``objmode`` block again in every process, even when the function around it comes from
the on-disk cache: ~40 ms of each cold start on the project machine.  Elsewhere (Windows,
32-bit) that ``objmode`` block is what runs.
"""

from __future__ import annotations

import sys
import time

import numba
from llvmlite import ir
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic

from .._jit import jit

__all__ = ["NATIVE", "now"]

#: the compiled code reads the C library's clock (``struct timespec`` as two 64-bit fields)
NATIVE = hasattr(time, "clock_gettime") and sys.maxsize > 2**32
_CLOCK_ID = int(getattr(time, "CLOCK_MONOTONIC", 1))


@intrinsic
def _monotonic_ns(typingctx):
    def codegen(context, builder, signature, args):
        i64 = ir.IntType(64)
        timespec = ir.LiteralStructType([i64, i64])
        fnty = ir.FunctionType(ir.IntType(32), [ir.IntType(32), timespec.as_pointer()])
        clock_gettime = cgutils.get_or_insert_function(builder.module, fnty, "clock_gettime")
        ts = cgutils.alloca_once(builder, timespec)
        builder.call(clock_gettime, [ir.Constant(ir.IntType(32), _CLOCK_ID), ts])
        sec = builder.load(cgutils.gep_inbounds(builder, ts, 0, 0))
        nsec = builder.load(cgutils.gep_inbounds(builder, ts, 0, 1))
        return builder.add(builder.mul(sec, ir.Constant(i64, 1_000_000_000)), nsec)

    return types.int64(), codegen


if NATIVE:
    @jit
    def now():
        """Seconds of a monotonic clock (only differences mean anything)."""
        return _monotonic_ns() * 1e-9
else:
    @jit(nogil=False)
    def now():
        """Seconds of a monotonic clock (only differences mean anything)."""
        with numba.objmode(t="float64"):
            t = time.perf_counter()
        return t
