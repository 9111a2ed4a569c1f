"""A generated network plant as C: printed from its own Python source and compiled by the
system C compiler.

* :mod:`clutchsim.cgen.cprint` — :func:`print_c`, the printer (the generated module and the
  friction kernels it calls, one subset of Python, read through :mod:`ast`);
* :mod:`clutchsim.cgen.compiler` — the system C compiler; :func:`build_plant_library`
  writes a plant's shared library, :class:`CPlant` loads one: Python callables for checks
  and tools, and :class:`~clutchsim.core.system.NativeFunction` values (the C addresses)
  that the C engine calls directly.

Two users: the network plants clutchsim integrates (:mod:`clutchsim.network.codegen`, a
new topology compiles in about a second instead of numba's 10–40 s) and the FMU export
(:mod:`clutchsim.fmu`).  See ``docs/network.md`` and ``docs/fmu.md``.
"""

from .compiler import (
    PLANT_ENTRIES,
    CompilerError,
    CPlant,
    NoCompilerError,
    build_plant_library,
    compile_shared,
    find_compiler,
)
from .cprint import CPrintError, CProgram, print_c

__all__ = ["PLANT_ENTRIES", "CPlant", "CPrintError", "CProgram", "CompilerError",
           "NoCompilerError", "build_plant_library", "compile_shared", "find_compiler",
           "print_c"]
