"""Small, explicit filters for measured signals (nothing is filtered unless asked)."""

from __future__ import annotations

import numpy as np

__all__ = ["moving_average"]


def moving_average(values, n: int) -> np.ndarray:
    """Centred moving average over ``n`` samples, the ends padded with the end values.

    Same length as ``values``; ``n <= 1`` returns a copy.
    """
    x = np.asarray(values, dtype=float).ravel()
    n = int(n)
    if n <= 1:
        return x.copy()
    pad = np.concatenate([np.full(n // 2, x[0]), x, np.full(n - 1 - n // 2, x[-1])])
    return np.convolve(pad, np.ones(n) / n, mode="valid")
