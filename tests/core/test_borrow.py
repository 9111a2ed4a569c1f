"""Arrays without reference counts (core/_borrow.py): views that share their owner's data,
stack scratch arrays with the layout and contents of np.empty/np.zeros."""

from __future__ import annotations

import numpy as np

from clutchsim._jit import jit
from clutchsim.core._borrow import borrowed, local_empty, local_zeros


@jit
def _fill(v, x):
    for i in range(v.shape[0]):
        v[i] = x + i


@jit
def _through_view(a):
    b = borrowed(a)
    _fill(b[1], 10.0)          # a row of a borrowed matrix, passed to a compiled call
    return b.sum(), b.shape[0], b.shape[1]


def test_borrowed_view_shares_the_owners_data():
    a = np.zeros((3, 4))
    s, r, c = _through_view(a)
    assert (r, c) == (3, 4)
    assert np.array_equal(a[1], 10.0 + np.arange(4))
    assert s == a.sum()
    assert a[0].sum() == 0.0 and a[2].sum() == 0.0


@jit
def _scratch(x, n):
    total = 0.0
    rows = np.zeros((n, 5))
    for k in range(n):
        z = local_zeros((2, 3))          # zero again at every iteration
        rows[k, 0] = z.sum()
        z[1, 2] = x + k
        z[0, 1] = 2.0 * k
        rows[k, 1] = z[1, 2]
        rows[k, 2] = z[0, 1]
        rows[k, 3] = z[1].sum()          # a row: strides of a C matrix
        e = local_empty(4)
        _fill(e, k)
        rows[k, 4] = e.sum()
        total += z.sum()
    return total, rows


def test_local_arrays_behave_like_numpy_ones():
    total, rows = _scratch(1.5, 4)
    k = np.arange(4.0)
    assert np.array_equal(rows[:, 0], np.zeros(4))              # zeros each time
    assert np.array_equal(rows[:, 1], 1.5 + k)
    assert np.array_equal(rows[:, 2], 2.0 * k)
    assert np.array_equal(rows[:, 3], 1.5 + k)
    assert np.array_equal(rows[:, 4], 4 * k + 6.0)              # k + (k+1) + (k+2) + (k+3)
    assert total == float(np.sum(1.5 + k + 2.0 * k))
