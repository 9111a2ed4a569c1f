"""Driveline: chain components (translated into networks) and the launch metrics of a run.

Running a scenario is :func:`clutchsim.scenario.run_scenario` (also
``clutchsim.run_scenario``): this package does not import :mod:`clutchsim.scenario`.
"""

from .chain import ENERGY_STATES, Chain
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
from .metrics import energy_balance, launch_metrics

__all__ = [
    "ENERGY_STATES",
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
    "energy_balance",
    "launch_metrics",
]
