"""Analyses of a plant beyond time simulation: linearisation, modes, judder."""

from .judder import JudderResult, judder_amplitude, judder_analysis
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

__all__ = ["ElementPoint", "JudderResult", "LinearModel", "Mode", "OperatingPoint",
           "OperatingPointError", "element_points", "judder_amplitude", "judder_analysis",
           "linearise", "modes", "operating_point"]
