"""Export a scenario's plant as a Functional Mock-up Unit (FMI 2.0 Model Exchange).

* :mod:`clutchsim.fmu.cprint` — the generated plant's Python source printed as C;
* :mod:`clutchsim.fmu.compiler` — the system C compiler; the printed plant as a shared
  library (:class:`~clutchsim.fmu.compiler.CPlant`).

See ``docs/fmu.md``.
"""

from .compiler import CompilerError, CPlant, find_compiler
from .cprint import CPrintError, print_c

__all__ = ["CPlant", "CPrintError", "CompilerError", "find_compiler", "print_c"]
