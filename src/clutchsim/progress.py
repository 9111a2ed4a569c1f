"""A one-line progress bar with rate and ETA on stderr, for terminals only.

Used by ``clutchsim run`` (per model), ``sweep`` (per run) and ``fit`` (per simulation).
It draws nothing when stderr is not a terminal, in CI (``CI`` set), or with ``--quiet``;
rich would do the same, but one redrawn line is all we need and keeps it dependency-free.
"""

from __future__ import annotations

import os
import sys
import time

__all__ = ["Progress", "progress_for"]


class Progress:
    """Callable ``progress(done, total)`` that redraws one stderr line.

    Parameters
    ----------
    unit : str
        What is counted (``runs``, ``simulations``, ``models``).
    min_interval : float
        Seconds between redraws (the final state is always drawn).
    """

    def __init__(self, unit: str = "runs", *, min_interval: float = 0.1, stream=None):
        self.unit = unit
        self.min_interval = min_interval
        self.stream = stream if stream is not None else sys.stderr
        self.first: tuple[float, int] | None = None
        self.last_draw = 0.0

    def __call__(self, done: int, total: int) -> None:
        now = time.perf_counter()
        if self.first is None:
            self.first = (now, done)
        if done < total and now - self.last_draw < self.min_interval:
            return
        self.last_draw = now
        t1, d1 = self.first
        rate = (done - d1) / (now - t1) if now > t1 and done > d1 else 0.0
        eta = f"{(total - done) / rate:5.0f} s" if rate > 0 else "    ?"
        width = 30
        fill = int(width * min(done, total) / max(total, 1))
        self.stream.write(f"\r[{'#' * fill}{'.' * (width - fill)}] {done}/{total} {self.unit} "
                          f"{rate:6.1f}/s ETA {eta}")
        if done >= total:
            self.stream.write("\n")
        self.stream.flush()


def progress_for(args, unit: str = "runs") -> Progress | None:
    """A :class:`Progress` when output goes to a terminal and the user did not ask for quiet."""
    if getattr(args, "quiet", False) or os.environ.get("CI") or not sys.stderr.isatty():
        return None
    return Progress(unit)
