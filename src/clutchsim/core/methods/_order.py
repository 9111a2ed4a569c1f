"""Order conditions of Runge–Kutta and Rosenbrock methods from rooted trees.

A method has order ``p`` when ``b · Φ(τ) = 1/γ(τ)`` for every rooted tree ``τ`` with at
most ``p`` nodes (Butcher; Hairer, Nørsett & Wanner, *Solving ODEs I*, §II.2), where
``γ(τ)`` is the tree's density and ``Φ(τ)`` its vector of elementary weights.

For an explicit Runge–Kutta method, a node with children ``τ_1 … τ_m`` has the weight
``Φ_i = Π_k (A Φ(τ_k))_i``.  For a Rosenbrock method with the exact Jacobian (Hairer &
Wanner, *Solving ODEs II*, §IV.7, Table 7.1) a node with one child is reached through the
Jacobian: its weight is ``((A + Γ) Φ(τ_1))_i`` with the full ``Γ`` (diagonal ``γ``
included), while a node with two or more children uses ``A`` as above.  Expanding the
diagonal gives Table 7.1's right-hand sides (``1/2 − γ``, ``1/6 − γ + γ²``, ...).

Written by hand (a page of code) because no maintained Python library generates these
conditions for Rosenbrock methods.
"""

from __future__ import annotations

from functools import cache

import numpy as np

__all__ = ["order_residuals", "rooted_trees"]


@cache
def rooted_trees(n: int) -> tuple[tuple, ...]:
    """All rooted trees with ``n`` nodes; a tree is the sorted tuple of its subtrees."""
    if n == 1:
        return ((),)
    out = set()
    # children of the root: a multiset of trees whose sizes add up to n - 1
    for parts in _partitions(n - 1):
        for combo in _choose_trees(parts):
            out.add(tuple(sorted(combo)))
    return tuple(sorted(out))


def _partitions(n: int, largest: int | None = None):
    largest = n if largest is None else largest
    if n == 0:
        yield ()
        return
    for k in range(min(n, largest), 0, -1):
        for rest in _partitions(n - k, k):
            yield (k,) + rest


def _choose_trees(parts):
    if not parts:
        yield ()
        return
    for t in rooted_trees(parts[0]):
        for rest in _choose_trees(parts[1:]):
            yield (t,) + rest


def _size(tree) -> int:
    return 1 + sum(_size(c) for c in tree)


def _density(tree) -> int:
    d = _size(tree)
    for c in tree:
        d *= _density(c)
    return d


def _weights(tree, A, B):
    s = A.shape[0]
    if not tree:
        return np.ones(s)
    if len(tree) == 1 and B is not None:
        return B @ _weights(tree[0], A, B)
    phi = np.ones(s)
    for c in tree:
        phi = phi * (A @ _weights(c, A, B))
    return phi


def order_residuals(b, A, order: int, Gamma=None) -> list[tuple[tuple, float]]:
    """``[(tree, b·Φ(tree) − 1/γ(tree)), ...]`` for every tree up to ``order`` nodes.

    ``A``: the stage matrix (Butcher's ``A``, or a Rosenbrock method's ``α``);
    ``Gamma``: a Rosenbrock method's full ``Γ`` (``None`` for an explicit RK method).
    """
    A = np.asarray(A, dtype=float)
    b = np.asarray(b, dtype=float)
    B = None if Gamma is None else A + np.asarray(Gamma, dtype=float)
    out = []
    for n in range(1, order + 1):
        for tree in rooted_trees(n):
            out.append((tree, float(b @ _weights(tree, A, B) - 1.0 / _density(tree))))
    return out
