"""Parameter identification: fit friction and plant parameters to measured records.

:func:`fit` is an output-error fit (simulate the plant driven by the measured input, compare
the simulated with the measured output) on compiled simulations; :mod:`.plants` holds the
plants it can drive (friction rig, EMPS closed loop) and :mod:`.spec` reads TOML fit
specifications.
"""

from .emps import EMPSPlant, make_emps
from .fit import (
    FIT_SOLVER_DEFAULTS,
    INITIAL_STATES,
    FitOptions,
    FitProblem,
    FitResult,
    Trace,
    evaluate,
    fit,
    nrmse,
    solver_options,
)
from .plants import INPUT_TARGETS, PLANTS, InputSpec, PlantSpec
from .spec import FitSpec, load_spec

__all__ = [
           "FIT_SOLVER_DEFAULTS",
           "INITIAL_STATES",
           "INPUT_TARGETS",
           "PLANTS",
           "EMPSPlant",
           "FitOptions",
           "FitProblem",
           "FitResult",
           "FitSpec",
           "InputSpec",
           "PlantSpec",
           "Trace",
           "evaluate",
           "fit",
           "load_spec",
           "make_emps",
           "nrmse",
           "solver_options",
]
