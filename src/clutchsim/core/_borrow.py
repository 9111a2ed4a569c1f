"""Borrowed array views: arrays that compiled calls pass without reference counting.

numba counts references to every array it passes to a compiled function that is not
inlined: the callee increments the count of each array argument on entry and decrements it
on exit, and both are *atomic* read-modify-write instructions on the array's memory-info
block.  The integration loop calls the plant (right-hand side, events, outputs, Jacobian:
function values, never inlined), the input bank and its own helpers with 4–8 arrays each,
a few hundred times per step; on the 2-core AMD EPYC these atomic operations took 27 % of
the default launch's integrator time (``perf``, samples in ``NRT_incref``/``NRT_decref``).

:func:`borrowed` returns a view of an array with the same type but without a memory-info
block, the way an array made by ``numba.carray`` over a raw pointer has none: numba then
skips the count (``NRT_incref`` of a null pointer returns at once).  numba has no option
for this, hence the one intrinsic below.

The caller must keep the owning array alive while the view is used: inside a compiled
function, use the owner again after the last use of its views (numba frees a local array
after its last use), or borrow only arrays the caller of the compiled function owns.
"""

from __future__ import annotations

from numba.core import cgutils, types
from numba.extending import intrinsic

__all__ = ["borrowed"]


@intrinsic
def borrowed(typingctx, arr):
    """A view of ``arr`` (same type, same data) that carries no reference count."""
    if not isinstance(arr, types.Array):
        return None

    def codegen(context, builder, signature, args):
        aryty = signature.args[0]
        src = context.make_array(aryty)(context, builder, args[0])
        dst = context.make_array(aryty)(context, builder)
        dst.meminfo = cgutils.get_null_value(dst.meminfo.type)
        dst.parent = cgutils.get_null_value(dst.parent.type)
        dst.nitems = src.nitems
        dst.itemsize = src.itemsize
        dst.data = src.data
        dst.shape = src.shape
        dst.strides = src.strides
        return dst._getvalue()

    return arr(arr), codegen
