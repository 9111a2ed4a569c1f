"""The piecewise-linear tables of the generated plants: the interval search by counting
(small tables) and by bisection (large ones) find the same interval, so the same bits."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from clutchsim.core.signals import SMALL_TABLE, interval
from clutchsim.network._kernels import table_column


def _bisection(xp, fp, x):
    """The search the plants used before counting: (value, slope), held outside."""
    n = len(xp)
    if n == 1 or x <= xp[0]:
        return fp[0], 0.0
    if x >= xp[-1]:
        return fp[-1], 0.0
    lo, hi = 0, n - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if xp[mid] <= x:
            lo = mid
        else:
            hi = mid
    s = (fp[hi] - fp[lo]) / (xp[hi] - xp[lo])
    return fp[lo] + s * (x - xp[lo]), s


@settings(max_examples=300, deadline=None)
@given(n=st.integers(1, 2 * SMALL_TABLE + 3), seed=st.integers(0, 2**32 - 1),
       data=st.data())
def test_table_column_matches_bisection_bit_for_bit(n, seed, data):
    rng = np.random.default_rng(seed)
    xp = np.cumsum(rng.uniform(0.01, 2.0, size=n)) - 3.0
    fp = rng.normal(size=(2, n))
    p = np.concatenate([[9.9, 9.9], xp, fp.ravel()])     # at an offset, two value columns
    # probe between, at and outside the breakpoints
    where = data.draw(st.sampled_from(["inside", "at", "outside"]))
    if where == "at":
        x = float(xp[data.draw(st.integers(0, n - 1))])
    elif where == "outside":
        x = float(xp[0] - 1.0 if data.draw(st.booleans()) else xp[-1] + 1.0)
    else:
        x = float(rng.uniform(xp[0], xp[-1]))
    for k in (1, 2):
        got = table_column(p, 2, n, k, x)
        want = _bisection(list(xp), list(fp[k - 1]), x)
        assert got == want
    assert np.isclose(table_column(p, 2, n, 1, x)[0], np.interp(x, xp, fp[0]), rtol=0,
                      atol=1e-12 * (1 + np.max(np.abs(fp[0]))))


@settings(max_examples=300, deadline=None)
@given(n=st.integers(2, 2 * SMALL_TABLE + 3), seed=st.integers(0, 2**32 - 1))
def test_interval_is_the_last_breakpoint_at_or_below_x_with_repeated_breakpoints(n, seed):
    # input-signal tables repeat a time for a step; the search must land on the last copy
    rng = np.random.default_rng(seed)
    a = np.cumsum(rng.choice([0.0, 0.5, 1.0], size=n))
    a[-1] += 1.0                                  # so that a[0] <= x < a[-1] has room
    x = float(rng.choice([rng.uniform(a[0], a[-1]), *a[:-1]]))
    lo = interval(a, 0, n, x)
    assert a[lo] <= x < a[lo + 1]
    assert lo == max(i for i in range(n - 1) if a[i] <= x)
