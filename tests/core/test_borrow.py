"""Arrays without reference counts (core/_borrow.py): stack scratch arrays with the layout
and contents of np.empty/np.zeros."""

from __future__ import annotations

import numpy as np

from clutchsim._jit import jit
from clutchsim.core._borrow import local_empty, local_zeros


@jit
def _fill(v, x):
    for i in range(v.shape[0]):
        v[i] = x + i


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
