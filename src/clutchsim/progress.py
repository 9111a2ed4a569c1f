"""A one-line progress bar with rate and ETA on stderr, for terminals only.

Used by ``clutchsim run`` (per model), ``rig`` (one run), ``sweep`` (per run) and ``fit``
(per simulation).  It draws nothing when stderr is not a terminal, in CI (``CI`` set), or
with ``--quiet``; rich would do the same, but one redrawn line is all we need and keeps it
dependency-free.

With ``tick`` (seconds), a background thread redraws the line with the time spent on the
current item, so that one long simulation shows it is alive: the compiled integrator
releases the GIL, and a single run has no count to report.  Call :meth:`Progress.close`
(or use it as a context manager) to stop the thread.
"""

from __future__ import annotations

import math
import os
import sys
import threading
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

    def __init__(self, unit: str = "runs", *, min_interval: float = 0.1, stream=None,
                 tick: float | None = None):
        self.unit = unit
        self.min_interval = min_interval
        self.stream = stream if stream is not None else sys.stderr
        self.first: tuple[float, int] | None = None
        self.last_draw = -math.inf   # the first call always draws
        self.state: tuple[int, int, float] | None = None   # done, total, since
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._thread = None
        if tick is not None:
            self._thread = threading.Thread(target=self._ticker, args=(float(tick),),
                                            name="clutchsim-progress", daemon=True)
            self._thread.start()

    def __call__(self, done: int, total: int) -> None:
        now = time.perf_counter()
        with self._lock:
            if self.state is None or self.state[0] != done:
                self.state = (done, total, now)
            if self.first is None:
                self.first = (now, done)
            if done < total and now - self.last_draw < self.min_interval:
                return
            self._draw(done, total, now)
        if done >= total:
            self.close()

    def _draw(self, done: int, total: int, now: float, current: str = "") -> None:
        self.last_draw = now
        t1, d1 = self.first
        rate = (done - d1) / (now - t1) if now > t1 and done > d1 else 0.0
        eta = f"{(total - done) / rate:5.0f} s" if rate > 0 else "    ?"
        width = 30
        fill = int(width * min(done, total) / max(total, 1))
        self.stream.write(f"\r[{'#' * fill}{'.' * (width - fill)}] {done}/{total} {self.unit} "
                          f"{rate:6.1f}/s ETA {eta}{current}")
        if done >= total:
            self.stream.write("\n")
        self.stream.flush()

    def _ticker(self, every: float) -> None:
        while not self._stop.wait(every):
            with self._lock:
                if self.state is None or self.state[0] >= self.state[1]:
                    continue
                done, total, since = self.state
                now = time.perf_counter()
                self._draw(done, total, now, f"; this one running for {now - since:.0f} s  ")

    def close(self) -> None:
        """Stop the ticking thread (if any); the line is left as last drawn."""
        self._stop.set()
        thread, self._thread = self._thread, None
        if thread is not None and thread is not threading.current_thread():
            thread.join()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False


def progress_for(args, unit: str = "runs", *, tick: float | None = None) -> Progress | None:
    """A :class:`Progress` when output goes to a terminal and the user did not ask for quiet
    (``tick``: redraw the time on the current item every ``tick`` seconds)."""
    if getattr(args, "quiet", False) or os.environ.get("CI") or not sys.stderr.isatty():
        return None
    return Progress(unit, tick=tick)
