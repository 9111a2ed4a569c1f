"""The component library of the driveline network (one module per component).

:data:`COMPONENTS` maps each scenario ``type`` to its class; adding a component is one new
module here and one line below (``docs/network.md``: the recipe).
"""

from __future__ import annotations

from .backlash import ElastoBacklash
from .converter import TorqueConverter
from .dmf import DualMassFlywheel
from .engine import Engine
from .friction import Brake, Clutch
from .ideal_gear import IdealGear
from .inertia import Inertia
from .planetary import Planetary
from .speed_torque import QuadraticSpeedTorque
from .spring_damper import SpringDamper
from .thermal import ThermalNode
from .torque_source import TorqueSource
from .vehicle import Vehicle

__all__ = ["COMPONENTS", "Brake", "Clutch", "DualMassFlywheel", "ElastoBacklash", "Engine",
           "IdealGear", "Inertia", "Planetary", "QuadraticSpeedTorque", "SpringDamper",
           "ThermalNode", "TorqueConverter", "TorqueSource", "Vehicle"]

#: scenario ``type`` -> component class
COMPONENTS = {c.kind: c for c in (Inertia, SpringDamper, IdealGear, Planetary, Clutch, Brake,
                                  TorqueSource, QuadraticSpeedTorque, Engine, Vehicle,
                                  ThermalNode, ElastoBacklash, DualMassFlywheel,
                                  TorqueConverter)}
