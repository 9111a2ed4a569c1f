"""Compilation settings shared by every compiled kernel of clutchsim.

numba's on-disk cache only checks the timestamp of the file that holds the
cached function, not of the functions it calls.  Our integrators are cached
specialisations that inline model kernels living in other files, so a stale
cache could silently run old model code.  We therefore key the cache directory
on a hash of clutchsim's own sources: any edit to any module gets a fresh cache.
A user-provided ``NUMBA_CACHE_DIR`` is the base directory instead of ``~/.cache``, keyed the
same way (``$NUMBA_CACHE_DIR/clutchsim-<hash>``): used as is, it kept compiled plants whose
inlined friction kernels had since been edited (numba checks only the timestamp of the
file that holds the cached function, and a generated plant's file does not change).
"""

from __future__ import annotations

import hashlib
import importlib.machinery
import importlib.util
import os
import sys
from pathlib import Path

import numba
from numba import njit

__all__ = ["cache_dir", "jit"]


def _source_digest() -> str:
    root = Path(__file__).resolve().parent
    h = hashlib.blake2b(digest_size=8)
    for path in sorted(root.rglob("*.py")):
        h.update(path.relative_to(root).as_posix().encode())
        h.update(path.read_bytes())
    return h.hexdigest()


def _configure_cache() -> str:
    user = os.environ.get("NUMBA_CACHE_DIR")
    if user:
        path = Path(user) / f"clutchsim-{_source_digest()}"
    else:
        base = Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache"))
        path = base / "clutchsim" / "numba" / _source_digest()
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError:  # read-only home: let numba fall back to __pycache__
        return ""
    numba.config.CACHE_DIR = str(path)
    return str(path)


cache_dir = _configure_cache()


def _tolerate_foreign_index_entries() -> None:
    """Let numba ignore cache-index entries whose types cannot be imported here.

    The integrators are specialised per plant tag type, and numba keeps all
    specialisations of one function in one index file.  An index written by a process
    that defined its own plant (a user's script, a notebook) names that plant's class;
    any other process that cannot import it would crash with ModuleNotFoundError when it
    reads the index.  We treat such an index as empty instead: the cost is a recompile,
    never a crash.  numba has no option for this, hence the narrow patch of one method.
    """
    from numba.core import caching

    original = getattr(caching.IndexDataCacheFile, "_load_index", None)
    if original is None or getattr(original, "_clutchsim_tolerant", False):
        return

    def _load_index(self):
        try:
            return original(self)
        except (ImportError, AttributeError, EOFError, ValueError, TypeError):
            return {}

    _load_index._clutchsim_tolerant = True
    caching.IndexDataCacheFile._load_index = _load_index


_tolerate_foreign_index_entries()


def _scipy_blas_findable() -> bool:
    """Is ``scipy.linalg.cython_blas`` installed?  Found on disk, not imported."""
    try:
        linalg = importlib.util.find_spec("scipy.linalg")   # imports scipy, not scipy.linalg
        locations = linalg and linalg.submodule_search_locations
        return bool(locations) and importlib.machinery.PathFinder.find_spec(
            "scipy.linalg.cython_blas", list(locations)) is not None
    except (ImportError, ValueError):
        return False


def _defer_blas_import() -> None:
    """Keep numba's start-up from importing ``scipy.linalg`` (~0.2–0.4 s of a cold start).

    The first compilation or cache load of any numba function imports
    ``numba.np.arraymath``, which calls ``numba.np.linalg.ensure_blas()`` at import to set
    its ``_HAVE_BLAS`` flag, and that imports ``scipy.linalg`` (and with it
    scipy's array-API layer, ``numpy.f2py`` and ``numpy.testing``), whether or not any
    compiled function uses linear algebra; clutchsim's do not (the C engine has its own
    small dense solver).  For that one call the flag is answered by finding
    ``scipy.linalg.cython_blas`` on disk; every later call (when a function that does use
    ``np.linalg`` or ``np.dot`` is compiled) runs numba's own check, imports included.
    numba has no option for this, hence the narrow patch of one function.
    """
    from numba.np import linalg

    original = getattr(linalg, "ensure_blas", None)
    if original is None or getattr(original, "_clutchsim_deferred", False):
        return

    def ensure_blas():
        arraymath = sys.modules.get("numba.np.arraymath")
        if arraymath is not None and not hasattr(arraymath, "_HAVE_BLAS"):
            # arraymath is being imported and asks only whether BLAS exists
            if not _scipy_blas_findable():
                raise ImportError("scipy 0.16+ is required for linear algebra")
            return None
        return original()

    ensure_blas._clutchsim_deferred = True
    linalg.ensure_blas = ensure_blas


_defer_blas_import()


def jit(func=None, **kwargs):
    """``numba.njit`` with on-disk caching, used for every compiled kernel."""
    kwargs.setdefault("cache", True)
    kwargs.setdefault("nogil", True)
    # IEEE semantics for float division (inf/NaN, which the integrators detect and report)
    # instead of a zero check and a Python exception inside compiled code
    kwargs.setdefault("error_model", "numpy")
    if func is None:
        return njit(**kwargs)
    return njit(**kwargs)(func)
