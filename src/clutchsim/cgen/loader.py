"""Load a generated plant module: printed as C and compiled once, numba where that fails.

Two plant generators write a plant as the source of a small Python module (the subset
:mod:`clutchsim.cgen.cprint` prints): the networks (:mod:`clutchsim.network.codegen`, one
module per topology) and the friction rig (:mod:`clutchsim.rig`, one per friction model).
:func:`load_plant` is their one way to a registered plant: it writes the module into
clutchsim's cache directory (keyed by clutchsim's sources) under a name that is the hash
of its source, prints it as C and compiles it with the system C compiler (once: a second
process loads the library), and registers its functions under a new tag type.  Where the
C path is impossible (no compiler, a construct the printer does not know, a numba that
passes arrays otherwise), it says so once per process and registers the module's own
functions, compiled by numba (10–40 s for a new plant, then cached on disk).
"""

from __future__ import annotations

import importlib.util
import logging
import os
import sys
import tempfile
import threading
from pathlib import Path
from typing import NamedTuple

from .._jit import cache_dir
from ..core import register_system

__all__ = ["load_plant", "module_dir"]

log = logging.getLogger("clutchsim")

_lock = threading.Lock()
#: (kind, key) -> the loaded module
_LOADED: dict[tuple[str, str], object] = {}
#: the kinds of failure of the C path already reported in this process
_FALLBACK_LOGGED: set[str] = set()


def module_dir(kind: str) -> Path:
    """The directory of the generated modules and libraries of ``kind`` ("network",
    "rig"): in clutchsim's cache directory, else in the system's temporary directory."""
    base = Path(cache_dir) if cache_dir else Path(tempfile.gettempdir()) / "clutchsim-net"
    d = base / kind
    d.mkdir(parents=True, exist_ok=True)
    return d


def _entries(mod) -> dict:
    """The plant entry points module ``mod`` defines (:data:`~clutchsim.cgen.compiler.
    PLANT_ENTRIES`; ``factor`` and ``solve`` only where it has them)."""
    from .compiler import OPTIONAL_ENTRIES, PLANT_ENTRIES
    return {k: v for k, v in PLANT_ENTRIES.items()
            if k not in OPTIONAL_ENTRIES or hasattr(mod, k)}


def _native(mod, lib: Path, entries: dict) -> dict | None:
    """The functions ``entries`` of module ``mod`` printed as C and compiled into ``lib``
    (built once), by name; None when that is impossible here (logged once per kind of
    failure)."""
    from . import CompilerError, CPlant, CPrintError, build_plant_library
    try:
        if not lib.exists():
            build_plant_library(mod, lib, entries)
        c = CPlant.load(lib, entries)
        return {n: c.native(n) for n in entries}
    except (CPrintError, CompilerError, OSError) as exc:
        key = type(exc).__name__
        if key not in _FALLBACK_LOGGED:
            _FALLBACK_LOGGED.add(key)
            log.warning("generated plants (networks, the friction rig) are compiled by "
                        "numba, not C (10–40 s per new plant instead of about 1 s): %s", exc)
        return None


def load_plant(kind: str, key: str, source: str, *, exact_jacobian: bool = True):
    """Write (atomically, once), import and register the generated plant module ``source``
    of ``kind`` ("network", "rig") whose hash is ``key``; returns the module, with ``TAG``
    (its tag type, registered) and ``FUNCTIONS`` (what was registered) set.

    ``exact_jacobian`` False registers no ``jac`` (nor the ``factor``/``solve`` written
    for it): the implicit integrators then difference the right-hand side."""
    with _lock:
        mod = _LOADED.get((kind, key))
        if mod is not None:
            return mod
        d = module_dir(kind)
        name = f"clutchsim_{kind}_{key}"
        path = d / f"{name}.py"
        if not path.exists() or path.read_text() != source:
            fd, tmp = tempfile.mkstemp(dir=d, suffix=".tmp")
            with os.fdopen(fd, "w") as f:
                f.write(source)
            os.replace(tmp, path)
        spec = importlib.util.spec_from_file_location(name, path)
        mod = importlib.util.module_from_spec(spec)
        sys.modules[name] = mod
        spec.loader.exec_module(mod)
        # one tag class per module, created at run time (its name carries the hash)
        tag = NamedTuple(f"{kind.capitalize()}_{key}", [("k", int)])  # noqa: UP014
        tag.__module__ = name
        setattr(mod, tag.__name__, tag)
        entries = _entries(mod)
        fns = _native(mod, d / f"{name}.so", entries) or {n: getattr(mod, n) for n in entries}
        if not exact_jacobian:      # the factors are written for the exact Jacobian
            fns = {n: f for n, f in fns.items() if n not in ("jac", "factor", "solve")}
        if "factor" in fns:
            fns["factor_size"] = mod.FACTOR_SIZE
        register_system(tag, **fns)
        mod.TAG = tag
        mod.FUNCTIONS = fns
        _LOADED[(kind, key)] = mod
        return mod
