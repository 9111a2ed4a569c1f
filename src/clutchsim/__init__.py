"""clutchsim: dry friction clutch and driveline simulation.

Friction models that do not stall the solver, a compiled simulation core with located
events, friction benchmarks, vehicle launches and parameter fitting.

>>> import clutchsim as cs
>>> res = cs.run_rig(cs.make_model("lugre"), 30.0, force=0.0, spring=2.0, pull_speed=0.1)
>>> res.status
'completed'
"""

from . import _jit  # noqa: F401  (configures numba's cache before any kernel is compiled)
from ._version import __version__
from .core import (
    Constant,
    Pulse,
    Ramp,
    Result,
    Sine,
    SolverOptions,
    Step,
    System,
    Table,
    register_system,
    simulate,
)
from .friction import (
    MODELS,
    describe_models,
    get_model_class,
    load_parameter_set,
    make_model,
)
from .rig import make_rig, run_rig
from .sweeps import sweep

__all__ = [
    "MODELS",
    "Constant",
    "Pulse",
    "Ramp",
    "Result",
    "Sine",
    "SolverOptions",
    "Step",
    "System",
    "Table",
    "__version__",
    "describe_models",
    "get_model_class",
    "load_parameter_set",
    "make_model",
    "make_rig",
    "register_system",
    "run_rig",
    "simulate",
    "sweep",
]
