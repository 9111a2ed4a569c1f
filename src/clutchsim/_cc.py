"""The system C compiler: find it, and compile C sources into a shared library.

A utility of the lowest floor: the integration engine (:mod:`clutchsim.core.cengine`)
and the code generator (:mod:`clutchsim.cgen`, plants; :mod:`clutchsim.fmu`, FMUs and the
real-time library) compile with it.
"""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

__all__ = ["CFLAGS", "COMPILERS", "CompilerError", "NoCompilerError", "compile_shared",
           "find_compiler"]

#: names looked for, in this order, after $CC
COMPILERS = ("cc", "gcc", "clang")
#: flags: ISO C99, no fused multiply-add (numba does not contract either), position
#: independent, optimised; calls between the library's own functions bound at link time
#: (``-fno-semantic-interposition``: the numba entries inline the plant's) and math
#: functions that do not set ``errno`` (the results are the same; numba does not set it
#: either): the default launch's loop 4.20 -> 3.94 ms against ``-O2`` (minima of 300)
CFLAGS = ("-std=c99", "-O3", "-fno-semantic-interposition", "-fno-math-errno", "-fPIC",
          "-ffp-contract=off", "-fno-fast-math", "-Wall",
          "-Wno-unused-variable", "-Wno-unused-but-set-variable", "-Wno-unused-function")


class CompilerError(RuntimeError):
    """The compiler rejected a program."""


class NoCompilerError(CompilerError, LookupError):
    """No C compiler on this machine (the message says what was looked for)."""


def find_compiler() -> str:
    """Path of the system C compiler (``$CC``, else the first of :data:`COMPILERS` on the
    ``PATH``); :class:`NoCompilerError` saying what was looked for when there is none, or
    when ``$CC`` names no executable (the user chose that compiler: another one is never
    used in its place)."""
    cc = os.environ.get("CC")
    tried = []
    if cc:
        found = shutil.which(cc)
        if found:
            return found
        raise NoCompilerError(
            f"CC={cc!r} is not an executable compiler (not found, or not executable, on the "
            "PATH): set CC to the path of a C compiler, or unset it to use the first of "
            f"{', '.join(COMPILERS)} on the PATH")
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
        names = ", ".join(Path(s).name for s in sources)
        raise CompilerError(f"{Path(cc).name} failed on {names} (exit {proc.returncode}): "
                            f"{proc.stderr.strip()[:1500]}")
    return out
