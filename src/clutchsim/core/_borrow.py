"""Arrays without reference counts: borrowed views, and scratch arrays on the stack.

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

:func:`local_empty` and :func:`local_zeros` are ``np.empty``/``np.zeros`` of a literal
shape on the calling function's stack, also without a count.  The generated network plants
use them for their scratch arrays: each ``np.empty`` was a heap allocation, a free and
atomic counts per call of the event functions, the outputs and the Jacobian.
"""

from __future__ import annotations

from numba.core import cgutils, types
from numba.extending import intrinsic

__all__ = ["borrowed", "local_empty", "local_zeros"]


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


def _literal_shape(shape):
    dims = shape.types if isinstance(shape, types.BaseTuple) else (shape,)
    if not dims or not all(isinstance(d, types.IntegerLiteral) for d in dims):
        return None
    return tuple(max(int(d.literal_value), 0) for d in dims)


def _local_array(shape, zero):
    dims = _literal_shape(shape)
    if dims is None:
        return None
    arrty = types.Array(types.float64, len(dims), "C")

    def codegen(context, builder, signature, args):
        size = 1
        for d in dims:
            size *= d
        intp = context.get_value_type(types.intp)
        f64 = context.get_data_type(types.float64)
        # in the entry block: one slot per call site, not one per loop iteration
        data = cgutils.alloca_once(builder, f64, size=intp(max(size, 1)))
        if zero:
            cgutils.memset(builder, data, intp(8 * max(size, 1)), 0)
        ary = context.make_array(arrty)(context, builder)
        strides, acc = [], 8
        for d in reversed(dims):
            strides.insert(0, acc)
            acc *= d
        context.populate_array(ary, data=data,
                               shape=[intp(d) for d in dims],
                               strides=[intp(s) for s in strides],
                               itemsize=intp(8), meminfo=None)
        return ary._getvalue()

    return arrty(shape), codegen


@intrinsic
def local_empty(typingctx, shape):
    """``np.empty(shape)`` of float64 on the stack of the calling function, without a
    reference count; ``shape`` is a literal int or tuple of ints.  The array must not
    outlive the call it was made in (the generated network plants use it for their
    scratch arrays: a heap allocation and its atomic counts per call cost more than the
    arithmetic of a right-hand side)."""
    return _local_array(shape, False)


@intrinsic
def local_zeros(typingctx, shape):
    """:func:`local_empty`, filled with zeros."""
    return _local_array(shape, True)
