"""The system C compiler, and a generated plant compiled to a shared library.

:func:`find_compiler` looks for the compiler (``$CC``, then ``cc``, ``gcc``, ``clang``);
:func:`compile_shared` builds a shared library from C sources; :class:`CPlant` is the
plant of a :class:`~clutchsim.network.plant.Plan` printed as C
(:mod:`clutchsim.fmu.cprint`) and loaded with :mod:`ctypes`, with the same calls as the
compiled plant (``rhs(t, y, u, p, dy)``, ...), for checking one against the other.
"""

from __future__ import annotations

import ctypes
import os
import shutil
import subprocess
import tempfile
from pathlib import Path

import numpy as np

from .cprint import A1, A2, D, I, print_c

__all__ = ["PLANT_ENTRIES", "CPlant", "CompilerError", "NoCompilerError", "compile_shared", "find_compiler"]

#: names looked for, in this order, after $CC
COMPILERS = ("cc", "gcc", "clang")
#: flags: ISO C99, no fused multiply-add (numba does not contract either), position
#: independent, optimised
CFLAGS = ("-std=c99", "-O2", "-fPIC", "-ffp-contract=off", "-fno-fast-math", "-Wall",
          "-Wno-unused-variable", "-Wno-unused-but-set-variable", "-Wno-unused-function")

#: the plant's entry points and their argument types (clutchsim.core.system protocol)
PLANT_ENTRIES = {
    "rhs": (D, A1, A1, A1, A1),
    "outputs": (D, A1, A1, A1, A1),
    "events": (D, A1, A1, A1, A1),
    "reset": (D, A1, A1, A1, I),
    "jac": (D, A1, A1, A1, A2),
}


class CompilerError(RuntimeError):
    """The compiler rejected the printed program."""


class NoCompilerError(CompilerError, LookupError):
    """No C compiler on this machine (the message says what was looked for)."""


def find_compiler() -> str:
    """Path of the system C compiler (``$CC``, else the first of :data:`COMPILERS` on the
    ``PATH``); :class:`NoCompilerError` saying what was looked for when there is none."""
    cc = os.environ.get("CC")
    tried = []
    if cc:
        found = shutil.which(cc)
        if found:
            return found
        tried.append(f"$CC={cc}")
    for name in COMPILERS:
        found = shutil.which(name)
        if found:
            return found
        tried.append(name)
    raise NoCompilerError(
        f"no C compiler found (looked for {', '.join(tried)} on the PATH); install one, "
        "e.g. `apt-get install gcc` (Debian/Ubuntu), `dnf install gcc` (Fedora) or "
        "`xcode-select --install` (macOS), or set CC to its path")


def compile_shared(sources: list[Path], out: Path, include: list[Path] = ()) -> Path:
    """Compile C ``sources`` into the shared library ``out`` with the system compiler."""
    cc = find_compiler()
    cmd = [cc, *CFLAGS, "-shared", "-o", str(out), *[f"-I{d}" for d in include],
           *map(str, sources), "-lm"]
    proc = subprocess.run(cmd, capture_output=True, text=True, check=False)
    if proc.returncode != 0:
        raise CompilerError(f"{Path(cc).name} failed on the printed plant (exit "
                            f"{proc.returncode}): {proc.stderr.strip()[:1500]}")
    return out


class CPlant:
    """The plant of ``plan`` printed as C, compiled and loaded (see the module docstring).

    ``entries``: which of :data:`PLANT_ENTRIES` to print (default all)."""

    def __init__(self, plan, entries=None):
        names = tuple(entries or PLANT_ENTRIES)
        self.program = print_c(plan.module, {n: PLANT_ENTRIES[n] for n in names})
        d = Path(tempfile.mkdtemp(prefix="clutchsim-cplant-"))
        try:
            (d / "plant.c").write_text(self.program.source)
            self.lib = ctypes.CDLL(str(compile_shared([d / "plant.c"], d / "plant.so")))
        finally:        # a loaded library stays mapped when its file is gone
            shutil.rmtree(d, ignore_errors=True)
        dbl = ctypes.c_double
        ptr = np.ctypeslib.ndpointer(dtype=np.float64, flags="C_CONTIGUOUS")
        kinds = {D: dbl, I: ctypes.c_int, A1: ptr}
        for n in names:
            f = getattr(self.lib, f"cs_{n}")
            args = []
            for t in PLANT_ENTRIES[n]:
                args += [ptr, ctypes.c_int] if t == A2 else [kinds[t]]
            f.argtypes = args
            f.restype = ctypes.c_int if n == "reset" else None
        self.names = names

    def _call(self, name, *args):
        return getattr(self.lib, f"cs_{name}")(*args)

    def rhs(self, t, y, u, p, dy):
        self._call("rhs", t, y, u, p, dy)

    def outputs(self, t, y, u, p, out):
        self._call("outputs", t, y, u, p, out)

    def events(self, t, y, u, p, g):
        self._call("events", t, y, u, p, g)

    def reset(self, t, y, u, p, k) -> int:
        return int(self._call("reset", t, y, u, p, int(k)))

    def jac(self, t, y, u, p, J):
        self._call("jac", t, y, u, p, J, J.shape[1])
