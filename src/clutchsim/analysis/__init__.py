"""Analyses of a plant beyond time simulation: linearisation, modes, judder."""

from .judder import JudderMap, JudderResult, judder_amplitude, judder_analysis, judder_map
from .linear import (
    ElementPoint,
    FrequencyResponse,
    LinearModel,
    Mode,
    OperatingPoint,
    OperatingPointError,
    element_points,
    frequency_response,
    linearise,
    modes,
    operating_point,
)

__all__ = ["ElementPoint", "FrequencyResponse", "JudderMap", "JudderResult", "LinearModel", "Mode", "OperatingPoint",
           "OperatingPointError", "element_points", "frequency_response", "judder_amplitude", "judder_analysis",
           "judder_map", "linearise", "modes", "operating_point"]
