"""The simulation core: signals, systems, integrators and results.  Knows nothing of friction."""

from .options import SOLVERS, SolverOptions
from .result import Event, Result, Stats, atomic_write
from .signals import Constant, Pulse, Ramp, Signal, Sine, Step, Sum, Table, as_signal
from .simulate import simulate
from .system import CONTINUE, FAIL, STATE_CHANGED, STOP, System, register_system

__all__ = [
    "SOLVERS", "SolverOptions", "Event", "Result", "Stats", "atomic_write", "Constant", "Pulse",
    "Ramp", "Signal", "Sine", "Step", "Sum", "Table", "as_signal", "simulate", "CONTINUE",
    "FAIL", "STATE_CHANGED", "STOP", "System", "register_system",
]
