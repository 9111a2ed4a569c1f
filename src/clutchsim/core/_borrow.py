"""Scratch arrays on the stack, without reference counts.

numba counts references to every array it passes to a compiled function that is not
inlined, with *atomic* read-modify-write instructions on the array's memory-info block,
and ``np.empty`` is a heap allocation and a free besides.  :func:`local_empty` and
:func:`local_zeros` are ``np.empty``/``np.zeros`` of a literal shape on the calling
function's stack, without a count.  The generated network plants use them for their
scratch arrays (where numba compiles them: printed C has its own), which cost a heap
allocation, a free and atomic counts per call of the event functions, the outputs and the
Jacobian.
"""

from __future__ import annotations

from numba.core import cgutils, types
from numba.extending import intrinsic

__all__ = ["local_empty", "local_zeros"]


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
