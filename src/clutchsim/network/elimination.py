"""Straight-line elimination of a network plant's iteration matrix, generated per topology.

Every stage of a Rosenbrock step solves a system with ``M = c·I − J`` (``c = 1/(γh)``).
The integrators' default (``invert`` in the C engine, ``core/engine.c``) inverts ``M``
densely; a driveline's Jacobian is sparse (33 of the 100 entries of the default launch's implicit
block), and its pattern is fixed by the topology.  :func:`elimination_source` writes, for
one pattern, the two functions of the plant protocol (:mod:`clutchsim.core.system`):

``factor(c, J, F) -> 1 or 0``
    an LU factorisation of ``M`` without pivoting, in a static order, as straight-line
    code over the pattern's entries and their fill (no loops, no index arrays); the factors
    go to ``F``.  Returns 0 where the static order is not safe for this matrix (below), and
    the integrator then inverts ``M`` densely, with partial pivoting, for that step;
``solve(F, b, X, r)``
    ``X[r] = M⁻¹·b`` by the forward and back substitutions, again straight-line.

Quadrature rows (the trailing states no derivative depends on) are finished by one
substitution each, ``x_q = (b_q + J[q, :nd]·x) / c``, as in the dense path.

The order is minimum degree on the symmetrised pattern, ties broken towards states whose
derivative does not depend on themselves (a spring's twist: its pivot is exactly ``c``).
Measured on the default launch's pattern (AMD EPYC, 2 cores; numba, straight-line against
the dense Gauss–Jordan of the numba loop the C engine replaced): the factorisation takes ~31 ns
against ~520 ns for the dense inverse, a stage solve ~17 against ~53 ns.  Index arrays
(a generic sparse LU) lost to the dense code at this size (session 13,
``docs/performance.md``); written out per topology they do not.  No library writes this:
SuiteSparse's KLU and SciPy's SuperLU take index arrays at run time, whose cost at ten
states is what this replaces.

**When the static order is refused.**  Without pivoting an elimination is only as good as
its pivots.  ``factor`` returns 0 when a pivot is zero or not finite, when it lost more
than eight digits to cancellation against the diagonal entry it started as
(``|u_kk| ≤ 1e-8·|m_kk|``), or when an entry of the factors grew beyond ``1e8`` times the
largest entry of ``M`` (the growth factor that bounds the backward error of Gaussian
elimination, Higham, *Accuracy and Stability of Numerical Algorithms*, §9.3).  The
integrator then takes its dense inverse with partial pivoting for that step.
"""

from __future__ import annotations

import numpy as np

__all__ = ["Elimination", "elimination_order", "elimination_source"]

#: a pivot must keep more than this fraction of its starting diagonal entry
PIVOT_KEEP = 1e-8
#: largest growth of the factors' entries over the largest entry of ``M``
MAX_GROWTH = 1e8


class Elimination:
    """The generated source of one pattern (:func:`elimination_source`): ``lines`` (the
    two functions, decorated ``@jit``), ``size`` (floats of ``F``), ``order`` (the
    elimination order of the implicit states) and ``flops`` (multiply-adds of a
    factorisation)."""

    def __init__(self, lines, size, order, flops):
        self.lines, self.size, self.order, self.flops = lines, size, order, flops


def elimination_order(pattern: np.ndarray) -> list[int]:
    """Minimum-degree order of the square boolean ``pattern`` (of ``J``; the diagonal of
    ``M`` is always there), ties to states without a self-dependence, then by index."""
    nd = pattern.shape[0]
    sym = pattern | pattern.T
    np.fill_diagonal(sym, False)
    left = list(range(nd))
    order = []
    while left:
        k = min(left, key=lambda i: (int(sym[i, left].sum()), bool(pattern[i, i]), i))
        order.append(k)
        left.remove(k)
        nb = [j for j in left if sym[k, j]]
        for a in nb:
            for b in nb:
                if a != b:
                    sym[a, b] = True
    return order


def _max_tree(terms: list[str]) -> str:
    """``max`` of ``terms`` as a balanced tree (a chain would be one long dependency)."""
    while len(terms) > 1:
        terms = [f"max({terms[i]}, {terms[i + 1]})" if i + 1 < len(terms) else terms[i]
                 for i in range(0, len(terms), 2)]
    return terms[0]


def elimination_source(pattern: np.ndarray, n: int, *, max_flops: int | None = None
                       ) -> Elimination | None:
    """``factor`` and ``solve`` (see the module docstring) for the boolean ``pattern`` of
    a Jacobian of ``n`` states, whose first ``nd = pattern.shape[1]`` columns are the
    implicit states (``pattern`` is ``(n, nd)``; the columns of the quadratures are zero).

    Returns None when straight-line code would not beat the dense inverse: when the
    factorisation with its fill needs more than ``max_flops`` multiply-adds (default
    ``nd³/4``: the dense Gauss–Jordan does ~``nd³`` with four per vector instruction)."""
    pattern = np.asarray(pattern, dtype=bool)
    nd = pattern.shape[1]
    if pattern.shape[0] != n or nd > n or nd == 0:
        raise ValueError(f"pattern of shape {pattern.shape} for {n} states")
    block = pattern[:nd]
    order = elimination_order(block)
    pos = {k: i for i, k in enumerate(order)}
    # entries of M in the permuted order: (row, col) -> expression of its starting value
    start = {}
    for i in range(nd):
        for j in range(nd):
            if block[i, j] or i == j:
                pi, pj = pos[i], pos[j]
                if i == j:
                    start[(pi, pj)] = f"c - J[{i}, {j}]" if block[i, j] else "c"
                else:
                    start[(pi, pj)] = f"-J[{i}, {j}]"

    def a(i, j):
        return f"a{i}_{j}"

    f = ["@jit", "def factor(c, J, F):"]
    b = [f"{a(i, j)} = {start[(i, j)]}" for (i, j) in sorted(start)]
    b.append(f"big = {_max_tree([f'abs({a(i, j)})' for (i, j) in sorted(start)])}")
    b += [f"m{k} = abs({a(k, k)})" for k in range(nd)]
    ent = set(start)        # the entries so far, fill included
    flops = 0
    for k in range(nd):
        b.append(f"if not abs({a(k, k)}) > {PIVOT_KEEP!r} * m{k}:")
        b.append("    return 0")
        b.append(f"d{k} = 1.0 / {a(k, k)}")
        rows = [i for i in range(k + 1, nd) if (i, k) in ent]
        cols = [j for j in range(k + 1, nd) if (k, j) in ent]
        for i in rows:
            b.append(f"l{i}_{k} = {a(i, k)} * d{k}")
            for j in cols:
                if (i, j) in ent:
                    b.append(f"{a(i, j)} -= l{i}_{k} * {a(k, j)}")
                else:
                    b.append(f"{a(i, j)} = -(l{i}_{k} * {a(k, j)})")
                    ent.add((i, j))
                flops += 1
    if flops > (nd ** 3 // 4 if max_flops is None else max_flops):
        return None
    # growth: every entry the elimination produced is a U entry or an unscaled L entry
    b.append(f"grown = {_max_tree([f'abs({a(i, j)})' for (i, j) in sorted(ent)])}")
    b.append(f"if not grown <= {MAX_GROWTH!r} * big:")
    b.append("    return 0")
    slot = {}

    def put(key, expr):
        slot[key] = len(slot)
        b.append(f"F[{slot[key]}] = {expr}")

    for k in range(nd):
        put(("d", k), f"d{k}")
    for (i, j) in sorted(ent):
        if i > j:
            put((i, j), f"l{i}_{j}")
        elif i < j:
            put((i, j), a(i, j))
    quad = [(q, j) for q in range(nd, n) for j in range(nd) if pattern[q, j]]
    for q, j in quad:
        put(("q", q, j), f"J[{q}, {j}]")
    if n > nd:
        put(("g",), "1.0 / c")
    b.append("return 1")
    f += ["    " + ln for ln in b]

    s = ["@jit", "def solve(F, b, X, r):"]
    sb = []
    for i in range(nd):
        terms = "".join(f" - F[{slot[(i, j)]}] * z{j}" for j in range(i) if (i, j) in ent)
        sb.append(f"z{i} = b[{order[i]}]{terms}")
    for i in reversed(range(nd)):
        terms = "".join(f" - F[{slot[(i, j)]}] * x{j}" for j in range(i + 1, nd)
                        if (i, j) in ent)
        sb.append(f"x{i} = ({f'z{i}' if not terms else f'z{i}{terms}'}) * F[{slot[('d', i)]}]")
        sb.append(f"X[r, {order[i]}] = x{i}")
    for q in range(nd, n):
        terms = "".join(f" + F[{slot[('q', q, j)]}] * x{pos[j]}" for j in range(nd)
                        if pattern[q, j])
        sb.append(f"X[r, {q}] = (b[{q}]{terms}) * F[{slot[('g',)]}]")
    s += ["    " + ln for ln in sb]
    return Elimination(f + [""] + s + [""], max(len(slot), 1), order, flops)
