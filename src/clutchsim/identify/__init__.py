"""Parameter identification: fit friction and plant parameters to measured records.

:func:`fit` is an output-error fit (simulate the plant driven by the measured input, compare
the simulated with the measured output) on compiled simulations; :mod:`.plants` holds the
plants it can drive (friction rig, EMPS closed loop) and :mod:`.spec` reads TOML fit
specifications.  :func:`calibrate` fits a launch scenario's network (:mod:`.launch_plant`) to vehicle
logs (:mod:`.calibrate`), :func:`synthetic_log` makes logs with a known truth.
"""

from .calibrate import (
    CalibrationResult,
    CalibrationSpec,
    LaunchTrace,
    calibrate,
    load_calibration,
)
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
from .launch_plant import LaunchPlant
from .plants import INPUT_TARGETS, PLANTS, InputSpec, PlantSpec
from .spec import FitSpec, load_spec
from .synthetic import synthetic_log

__all__ = [
    "FIT_SOLVER_DEFAULTS",
    "INITIAL_STATES",
    "INPUT_TARGETS",
    "PLANTS",
    "CalibrationResult",
    "CalibrationSpec",
    "EMPSPlant",
    "FitOptions",
    "FitProblem",
    "FitResult",
    "FitSpec",
    "InputSpec",
    "LaunchPlant",
    "LaunchTrace",
    "PlantSpec",
    "Trace",
    "calibrate",
    "evaluate",
    "fit",
    "load_calibration",
    "load_spec",
    "make_emps",
    "nrmse",
    "solver_options",
    "synthetic_log",
]
