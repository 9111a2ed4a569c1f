"""Measured data: read CSV, NPZ and MAT records into validated, unit-converted columns, and
vehicle logs (CSV, MDF4, CAN through a DBC) with their channels at their own rates."""

from .channels import ChannelMap, MappedLog, load_channel_map, map_log
from .filters import moving_average
from .launches import Launch, LaunchOptions, cut_launch, find_launches
from .logs import Channel, VehicleLog, read_log, write_log
from .measurement import Measurement, read_measurements
from .shared import shared_dir

__all__ = ["Channel", "ChannelMap", "Launch", "LaunchOptions", "MappedLog", "Measurement",
           "VehicleLog", "cut_launch", "find_launches", "load_channel_map", "map_log",
           "moving_average", "read_log", "read_measurements", "shared_dir", "write_log"]
