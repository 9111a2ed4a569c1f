"""Driveline: chain components (translated into networks).  The launch metrics of a run
are :mod:`clutchsim.analysis.launch_metrics`.

Running a scenario is :func:`clutchsim.scenario.run_scenario` (also
``clutchsim.run_scenario``): this package does not import :mod:`clutchsim.scenario`.
"""

from .chain import Chain
from .components import (
    Brake,
    Engine,
    FrictionElement,
    Gear,
    Gearbox,
    Inertia,
    LossyGear,
    OneWayClutch,
    SpringDamper,
    ThermalNode,
    Vehicle,
)

__all__ = [
    "Brake",
    "Chain",
    "Engine",
    "FrictionElement",
    "Gear",
    "Gearbox",
    "Inertia",
    "LossyGear",
    "OneWayClutch",
    "SpringDamper",
    "ThermalNode",
    "Vehicle",
]
