"""Tell the user when a first call is slow because numba is compiling, so it is not taken
for a hang.

The first simulation of a plant type in a process either loads what it runs from the
on-disk caches (under a second) or, after installing or changing clutchsim, compiles it:
the C engine in 3–4 s (once per machine), a printed plant in 0.2–0.8 s, a numba plant's
functions and their C adapters in about a second.  The launch metrics' kernel compiles
once too (~22 s), at the first launch analysed.
Nothing can be printed from inside numba's compiler, so a timer thread logs one line if the
guarded block is still running after :data:`NOTICE_AFTER_S` seconds.  numba gives no
progress hook for this, hence the timer.  The caller guards only the loading or compiling
(``simulate`` prepares the plant's C functions and the engine before it runs them), so a
run that is merely long is not announced as compiling.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Hashable, Iterator
from contextlib import contextmanager

from .._jit import cache_dir

__all__ = ["NOTICE_AFTER_S", "compile_notice"]

log = logging.getLogger("clutchsim")

#: seconds a first call may take before the notice is logged
NOTICE_AFTER_S = 3.0

_lock = threading.Lock()
_started: set = set()    # keys whose first call has begun in this process


@contextmanager
def compile_notice(key: Hashable, what: str, after: float | None = None,
                   subject: str = "the integrator",
                   takes: str = "about half a minute on two cores") -> Iterator[bool]:
    """Log (INFO, logger ``clutchsim``) one line if the first block guarded for ``key`` in
    this process takes longer than ``after`` seconds (default :data:`NOTICE_AFTER_S`).

    Yields whether this is that first block; later ones, from any thread, log nothing.

    Parameters
    ----------
    key : hashable
        What is compiled once per process, e.g. ``(plant tag type, backend)``.
    what : str
        Named in the message, e.g. the system's name.
    after : float, optional
        Delay [s] before the notice.
    subject : str
        What compiles, named in the message.
    takes : str
        How long it takes from an empty cache, said in the message.
    """
    with _lock:
        first = key not in _started
        _started.add(key)
    if not first:
        yield False
        return
    where = f" in {cache_dir}" if cache_dir else ""
    message = (f"{what}: compiling {subject} (the first run after installing or "
               f"changing clutchsim; {takes}, then cached on disk{where})...")
    timer = threading.Timer(NOTICE_AFTER_S if after is None else after, log.info,
                            args=(message,))
    timer.daemon = True
    timer.start()
    try:
        yield True
    finally:
        timer.cancel()
