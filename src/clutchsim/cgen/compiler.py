"""A generated plant compiled to a shared library.

:func:`find_compiler` (``$CC``, then ``cc``, ``gcc``, ``clang``) and :func:`compile_shared`
(a shared library from C sources) come from :mod:`clutchsim._cc`, where the integration
engine (:mod:`clutchsim.core.cengine`) finds them too.
:func:`build_plant_library` prints a generated plant module as C (:mod:`clutchsim.cgen.cprint`)
with one entry point ``cs_<f>`` per function, of C pointers: the C engine calls it
(:class:`~clutchsim.core.system.NativeFunction` carries its address), Python through
:mod:`ctypes`, and the FMU glue directly; no numba compilation at all for a new topology.
:class:`CPlant` loads such a library.
"""

from __future__ import annotations

import ctypes
import os
import shutil
import tempfile
from pathlib import Path

import numpy as np

from .._cc import CompilerError, NoCompilerError, compile_shared, find_compiler
from ..core.system import NativeFunction
from .cprint import A1, A2, D, I, print_c

__all__ = ["PLANT_ENTRIES", "CPlant", "CompilerError", "NoCompilerError", "build_plant_library",
           "compile_shared", "find_compiler"]

#: the plant's entry points and their argument types (clutchsim.core.system protocol)
PLANT_ENTRIES = {
    "rhs": (D, A1, A1, A1, A1),
    "outputs": (D, A1, A1, A1, A1),
    "events": (D, A1, A1, A1, A1),
    "reset": (D, A1, A1, A1, I),
    "jac": (D, A1, A1, A1, A2),
    "factor": (D, A2, A1),
    "solve": (A1, A1, A2, I),
}
#: the entry points a plant may lack (its solver of the iteration matrix)
OPTIONAL_ENTRIES = ("factor", "solve")
#: the entry points that return an integer (the others return nothing)
RETURNS_INT = ("reset", "factor")


def build_plant_library(module, out: Path, entries: dict[str, tuple] | None = None):
    """Print the generated plant ``module`` as C (``entries``: name -> argument kinds,
    default :data:`PLANT_ENTRIES`) and compile it into the shared library ``out``,
    atomically (a reader never sees a half-written library; two processes building the
    same one both succeed); returns the printed
    :class:`~clutchsim.cgen.cprint.CProgram`.  Raises
    :class:`~clutchsim.cgen.cprint.CPrintError`, :class:`NoCompilerError`,
    :class:`CompilerError`."""
    entries = dict(entries or PLANT_ENTRIES)
    program = print_c(module, entries)
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    d = Path(tempfile.mkdtemp(prefix=".build-", dir=out.parent))
    try:
        (d / "plant.c").write_text(program.source)
        compile_shared([d / "plant.c"], d / out.name)
        os.replace(d / out.name, out)
    finally:
        shutil.rmtree(d, ignore_errors=True)
    return program


class CPlant:
    """A plant library of :func:`build_plant_library`, loaded.

    ``rhs(t, y, u, p, dy)``, ``events``, ``outputs``, ``reset(t, y, u, p, k) -> action`` and
    ``jac(t, y, u, p, J)`` are callable from Python (arrays float64, C-contiguous);
    :meth:`native` gives the same function as a
    :class:`~clutchsim.core.system.NativeFunction` for the C engine.

    ``CPlant(plan)`` prints and compiles ``plan``'s module into a temporary library (for
    checking the printed C against the plant clutchsim runs); ``CPlant.load(path)`` loads a
    library already built.  ``program``: the printed
    :class:`~clutchsim.cgen.cprint.CProgram` (None for a library loaded from disk)."""

    def __init__(self, plan=None, entries=None, *, path: Path | None = None):
        names = tuple(entries or PLANT_ENTRIES)
        self.program = None
        if path is None:
            d = Path(tempfile.mkdtemp(prefix="clutchsim-cplant-"))
            try:
                self.program = build_plant_library(plan.module, d / "plant.so",
                                                   {n: PLANT_ENTRIES[n] for n in names})
                self.lib = ctypes.CDLL(str(d / "plant.so"))
            finally:        # a loaded library stays mapped when its file is gone
                shutil.rmtree(d, ignore_errors=True)
        else:
            self.lib = ctypes.CDLL(str(path))
        dbl = ctypes.c_double
        ptr = np.ctypeslib.ndpointer(dtype=np.float64, flags="C_CONTIGUOUS")
        kinds = {D: dbl, I: ctypes.c_int, A1: ptr}
        for n in names:
            f = getattr(self.lib, f"cs_{n}")
            args = []
            for t in PLANT_ENTRIES[n]:
                args += [ptr, ctypes.c_int] if t == A2 else [kinds[t]]
            f.argtypes = args
            f.restype = ctypes.c_int if n in RETURNS_INT else None
        self.names = names

    @classmethod
    def load(cls, path: Path, entries=None) -> CPlant:
        """The library at ``path`` (built by :func:`build_plant_library`)."""
        return cls(entries=entries, path=path)

    def _call(self, name, t, y, u, p, last):
        """``cs_<name>`` on float64 arrays of any layout: the C functions take contiguous
        arrays, so others are copied in (and, for what the function writes: ``y`` of a
        reset, the last argument of the others, copied back)."""
        f = getattr(self.lib, f"cs_{name}")
        yc, uc, pc = (np.ascontiguousarray(a, dtype=np.float64) for a in (y, u, p))
        if name == "reset":
            r = f(t, yc, uc, pc, int(last))
            if yc is not y:
                y[...] = yc
            return int(r)
        oc = np.ascontiguousarray(last, dtype=np.float64)
        if oc.ndim == 2:
            f(t, yc, uc, pc, oc, oc.shape[1])
        else:
            f(t, yc, uc, pc, oc)
        if oc is not last:
            last[...] = oc
        return None

    def rhs(self, t, y, u, p, dy):
        self._call("rhs", t, y, u, p, dy)

    def outputs(self, t, y, u, p, out):
        self._call("outputs", t, y, u, p, out)

    def events(self, t, y, u, p, g):
        self._call("events", t, y, u, p, g)

    def reset(self, t, y, u, p, k) -> int:
        return self._call("reset", t, y, u, p, k)

    def jac(self, t, y, u, p, J):
        self._call("jac", t, y, u, p, J)

    def factor(self, c, J, F) -> int:
        """``cs_factor`` (``J`` C-contiguous; ``F`` written in place)."""
        Jc = np.ascontiguousarray(J, dtype=np.float64)
        return int(self.lib.cs_factor(c, Jc, Jc.shape[1], F))

    def solve(self, F, b, X, r) -> None:
        """``cs_solve``: row ``r`` of the C-contiguous ``X`` written in place."""
        self.lib.cs_solve(F, b, X, X.shape[1], int(r))

    def native(self, name: str):
        """Entry ``name`` for the integrators: its C address, callable from Python."""
        c_address = ctypes.cast(getattr(self.lib, f"cs_{name}"), ctypes.c_void_p).value
        return NativeFunction(c_address, getattr(self, name), keep=self)
