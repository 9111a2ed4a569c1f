"""Measured data: read CSV, NPZ and MAT records into validated, unit-converted columns."""

from .filters import moving_average
from .measurement import Measurement, read_measurements
from .shared import shared_dir

__all__ = ["Measurement", "moving_average", "read_measurements", "shared_dir"]
