"""clutchsim: dry friction clutch and driveline simulation.

Friction models that do not stall the solver, a compiled simulation core with
located events, friction benchmarks, vehicle launches and parameter fitting.
"""

from . import _jit  # noqa: F401  (configures numba's cache before any kernel is compiled)
from ._version import __version__

__all__ = ["__version__"]
