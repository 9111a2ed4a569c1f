"""Post-processing of a plant and its results: linearisation, modes, frequency response,
the launch metrics of a run and the compiled batch that computes them, the judder band.
Studies that run scenarios (judder maps, a scenario's frequency response, sweeps,
durability) are in :mod:`clutchsim.studies`."""

from .frf import (
    FrequencyResponse,
    Peak,
    StateSpace,
    frequency_grid,
    frequency_response,
    state_space,
)
from .judder_band import JUDDER_BAND_HZ, judder_amplitude
from .launch_metrics import ENERGY_STATES, energy_balance, launch_metrics
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

__all__ = ["ENERGY_STATES", "JUDDER_BAND_HZ", "ElementPoint", "FrequencyResponse", "LinearModel",
           "Mode", "OperatingPoint", "OperatingPointError", "Peak", "StateSpace", "element_points",
           "energy_balance", "frequency_grid", "frequency_response", "judder_amplitude",
           "launch_metrics", "linearise", "modes", "operating_point", "state_space"]
