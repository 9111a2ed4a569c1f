"""Driveline: components, the compiled chain plant, scenarios and launch metrics."""

from .chain import ENERGY_STATES, Chain
from .components import (Brake, Engine, FrictionElement, Gear, Gearbox, Inertia, SpringDamper,
                         ThermalNode, Vehicle)

__all__ = ["Chain", "ENERGY_STATES", "Brake", "Engine", "FrictionElement", "Gear", "Gearbox",
           "Inertia", "SpringDamper", "ThermalNode", "Vehicle"]
