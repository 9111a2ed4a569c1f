"""Driveline: chain components (translated into networks), scenarios and launch metrics."""

from ..scenario import load_scenario
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
from .run import LaunchResult, energy_balance, launch_metrics, run_scenario

__all__ = [
    "ENERGY_STATES",
    "Brake",
    "Chain",
    "Engine",
    "FrictionElement",
    "Gear",
    "Gearbox",
    "Inertia",
    "LaunchResult",
    "LossyGear",
    "OneWayClutch",
    "SpringDamper",
    "ThermalNode",
    "Vehicle",
    "energy_balance",
    "launch_metrics",
    "load_scenario",
    "run_scenario",
]
