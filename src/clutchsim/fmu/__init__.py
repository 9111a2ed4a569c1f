"""Export a scenario's plant as a Functional Mock-up Unit (Model Exchange, FMI 2.0 or 3.0).

* :mod:`clutchsim.fmu.export` — :func:`export_fmu` (behind ``clutchsim fmu``) and
  :func:`input_table` (a scenario's inputs as FMPy reads them);
* re-exported from :mod:`clutchsim.cgen`, which also compiles the plants clutchsim runs: the
  generated plant's Python source printed as C (:func:`print_c`), the system C compiler and
  the printed plant as a shared library (:class:`CPlant`).

See ``docs/fmu.md``.
"""

from ..cgen.compiler import CompilerError, CPlant, NoCompilerError, find_compiler
from ..cgen.cprint import CPrintError, print_c
from .export import FmuError, FmuExport, export_fmu, input_table

__all__ = ["CPlant", "CPrintError", "CompilerError", "FmuError", "FmuExport", "NoCompilerError",
           "export_fmu", "find_compiler", "input_table", "print_c"]
