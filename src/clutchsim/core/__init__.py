"""The simulation core: signals, systems, integrators and results.  Knows nothing of friction."""

from .options import SOLVERS, SolverOptions
from .result import Event, Events, Result, Stats
from .signals import Constant, Pulse, Ramp, Signal, Sine, Step, Sum, Table, as_signal
from .simulate import simulate
from .status import Action, Outcome
from .system import (
    CONTINUE,
    FAIL,
    PASS,
    STATE_CHANGED,
    STOP,
    NativeFunction,
    System,
    register_system,
)

__all__ = [
    "CONTINUE",
    "FAIL",
    "PASS",
    "SOLVERS",
    "STATE_CHANGED",
    "STOP",
    "Action",
    "Constant",
    "Event",
    "Events",
    "NativeFunction",
    "Outcome",
    "Pulse",
    "Ramp",
    "Result",
    "Signal",
    "Sine",
    "SolverOptions",
    "Stats",
    "Step",
    "Sum",
    "System",
    "Table",
    "as_signal",
    "register_system",
    "simulate",
]
