"""Analyses of a plant beyond time simulation: linearisation, modes, judder, frequency
response."""

from .frf import (
    FrequencyResponse,
    Peak,
    StateSpace,
    frequency_grid,
    frequency_response,
    frf_analysis,
    state_space,
)
from .judder import JudderMap, JudderResult, judder_amplitude, judder_analysis, judder_map
from .linear import (
    ElementPoint,
    LinearModel,
    Mode,
    OperatingPoint,
    OperatingPointError,
    element_points,
    linearise,
    modes,
    operating_point,
)

__all__ = ["ElementPoint", "FrequencyResponse", "JudderMap", "JudderResult", "LinearModel", "Mode",
           "OperatingPoint", "OperatingPointError", "Peak", "StateSpace", "element_points",
           "frequency_grid", "frequency_response", "frf_analysis", "judder_amplitude",
           "judder_analysis", "judder_map", "linearise", "modes", "operating_point", "state_space"]
