"""The component library of the driveline network (one module per component).

:data:`COMPONENTS` maps each scenario ``type`` to its class; adding a component is one new
module here and one line below (``docs/network.md``: the recipe).
"""

from __future__ import annotations

from .backlash import ElastoBacklash
from .band_brake import BandBrake
from .cone_clutch import ConeClutch
from .converter import TorqueConverter
from .damper import Damper, TranslationalDamper
from .differential import OpenDifferential
from .dmf import DualMassFlywheel
from .dog_clutch import DogClutch
from .driver import Driver
from .eddy_current import EddyCurrentBrake, TranslationalEddyCurrentBrake
from .elasto_gap import ElastoGap
from .engine import Engine
from .friction import Brake, Clutch
from .gearbox_lash import LossyGearWithLash
from .hydraulic_actuator import HydraulicActuator
from .ideal_gear import IdealGear
from .inertia import Inertia, Mass
from .launch_controller import LaunchController
from .limited_slip_differential import LimitedSlipDifferential
from .lossy_gear import Gearbox, LossyGear
from .mass_stop import MassWithStopAndFriction
from .mount import TorsionalMount
from .one_way_clutch import OneWayClutch
from .planetary import Planetary
from .prescribed import (
    Accelerate,
    ConstantSpeed,
    Move,
    Position,
    Speed,
    TranslationalAccelerate,
    TranslationalConstantSpeed,
    TranslationalMove,
    TranslationalPosition,
    TranslationalSpeed,
)
from .release_system import ReleaseSystem
from .servo_actuator import ServoActuator
from .speed_torque import (
    InverseSpeedForce,
    InverseSpeedTorque,
    LinearSpeedForce,
    LinearSpeedTorque,
    QuadraticSpeedForce,
    QuadraticSpeedTorque,
    SignForce,
    SignTorque,
)
from .spring_damper import SpringDamper
from .synchronizer import Synchronizer
from .thermal import ThermalNode
from .torque_pulsation import TorquePulsation
from .torque_source import TorqueSource
from .translational import (
    Force,
    SupportFriction,
    TranslationalBrake,
    TranslationalSpringDamper,
)
from .translational_vehicle import TranslationalVehicle
from .tyre import Tyre
from .vehicle import Vehicle
from .wet_clutch import WetClutch

__all__ = ["COMPONENTS", "Accelerate", "BandBrake", "Brake", "Clutch", "ConeClutch",
           "ConstantSpeed", "Damper", "DogClutch", "Driver", "DualMassFlywheel",
           "EddyCurrentBrake", "ElastoBacklash", "ElastoGap", "Engine", "Force", "Gearbox",
           "HydraulicActuator", "IdealGear", "Inertia", "InverseSpeedForce", "InverseSpeedTorque",
           "LaunchController", "LimitedSlipDifferential", "LinearSpeedForce",
           "LinearSpeedTorque", "LossyGear", "LossyGearWithLash", "Mass",
           "MassWithStopAndFriction", "Move", "OneWayClutch",
           "OpenDifferential", "Planetary", "Position", "QuadraticSpeedForce",
           "QuadraticSpeedTorque", "ReleaseSystem", "ServoActuator", "SignForce", "SignTorque",
           "Speed", "SpringDamper", "SupportFriction", "Synchronizer",
           "ThermalNode", "TorqueConverter",
           "TorquePulsation", "TorqueSource", "TorsionalMount", "TranslationalAccelerate",
           "TranslationalBrake", "TranslationalConstantSpeed", "TranslationalDamper",
           "TranslationalEddyCurrentBrake", "TranslationalMove", "TranslationalPosition",
           "TranslationalSpeed", "TranslationalSpringDamper", "TranslationalVehicle", "Tyre",
           "Vehicle",
           "WetClutch"]

#: scenario ``type`` -> component class
COMPONENTS = {c.kind: c for c in (Inertia, SpringDamper, IdealGear, LossyGear, Gearbox,
                                  Planetary, Clutch, OneWayClutch, Brake, TorqueSource,
                                  TorquePulsation, QuadraticSpeedTorque, Engine, Vehicle,
                                  ThermalNode, ElastoBacklash, DualMassFlywheel,
                                  TorqueConverter, ReleaseSystem, HydraulicActuator,
                                  ServoActuator, LaunchController, Driver,
                                  # translational (Modelica Mechanics.Translational)
                                  Mass, TranslationalSpringDamper, Force, SupportFriction,
                                  TranslationalBrake, MassWithStopAndFriction,
                                  Damper, TranslationalDamper, ElastoGap,
                                  # prescribed motion (network/components/prescribed.py)
                                  Speed, Position, Accelerate, Move, ConstantSpeed,
                                  TranslationalSpeed, TranslationalPosition,
                                  TranslationalAccelerate, TranslationalMove,
                                  TranslationalConstantSpeed, TranslationalVehicle,
                                  # speed-dependent and eddy-current loads
                                  LinearSpeedTorque, InverseSpeedTorque, SignTorque,
                                  QuadraticSpeedForce, LinearSpeedForce, InverseSpeedForce,
                                  SignForce, EddyCurrentBrake, TranslationalEddyCurrentBrake,
                                  LossyGearWithLash,
                                  # shift elements and differentials (issue 38)
                                  BandBrake, ConeClutch, DogClutch, OpenDifferential,
                                  Synchronizer,
                                  # the vehicle around the driveline (issue 39)
                                  Tyre, TorsionalMount,
                                  # the wet multi-plate clutch (issue 38, item 3)
                                  WetClutch,
                                  # the limited-slip differential (issue 38, item 4)
                                  LimitedSlipDifferential)}
