"""Solver choice and options, validated on construction."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

from .controllers import JacobianPolicy, StepController
from .methods import METHODS
from .system import closest

__all__ = ["CHATTER_WINDOW_MAX_S", "DEFAULT_METHOD", "SOLVERS", "SolverOptions", "check_solver"]

#: the method every entry point uses unless told otherwise (written here only)
DEFAULT_METHOD = "rodas4"

_DEFAULT_POLICY = JacobianPolicy()
#: the default chatter window's upper end [s] (1e-4 of a 4 s launch)
CHATTER_WINDOW_MAX_S = 4e-4

#: compiled methods (one tableau each, :mod:`clutchsim.core.methods`) and the scipy
#: reference backends
SOLVERS = {name: f"compiled {m.description}" for name, m in METHODS.items()} | {
    "scipy-radau": "scipy solve_ivp Radau (reference backend; Python speed)",
    "scipy-lsoda": "scipy solve_ivp LSODA (reference backend; Python speed)",
    "scipy-rk45": "scipy solve_ivp RK45 (reference backend; Python speed)",
}


def check_solver(name: str) -> str:
    """Return ``name`` if it is a known solver, else raise a ValueError listing them."""
    if not isinstance(name, str) or name not in SOLVERS:
        raise ValueError(f"solver = {name!r} is not known{closest(str(name), SOLVERS)}; "
                         f"valid solvers: {', '.join(SOLVERS)}")
    return name


@dataclass(frozen=True)
class SolverOptions:
    """Tolerances, step limits, output grid and the guards against hangs.

    Parameters
    ----------
    rtol, atol : float
        Relative and absolute local error tolerances (> 0).
    h0 : float
        Initial step [s]; 0 chooses one automatically.
    h_max : float
        Largest step [s]; 0 means the whole span.
    h_min : float
        Smallest step [s] before the run stops as failed ("step size collapsed"); the
        floor is never below 1e-14·max(1, |t|).
    max_steps : int
        Most steps (accepted + rejected) before the run stops as failed.
    wall_time : float
        Wall-time budget [s] for the compiled integrator; 0 means none.
    chatter_events : int
        Chatter detection: this many events ...
    chatter_window : float or None
        ... inside this many seconds stop the run as failed (0 events disables it).
        ``None`` (default) uses 1e-4 of the simulated time span, at most
        :data:`CHATTER_WINDOW_MAX_S` (0.4 ms): a hundred events in 0.4 ms of a 4 s launch
        is a sliding mode, not physics, and a longer run has no more events per second
        (a window growing with the span would call a day-long run's slow oscillations
        chatter).
    event_tol : float
        Events are located to this time tolerance [s].
    dt_out : float
        Output grid spacing [s] (dense output); 0 stores every accepted step.
    max_output : int
        Most stored output rows (a memory guard for very long runs).
    controller : StepController or None
        Step-size controller; ``None`` (default) takes the method family's own
        (:meth:`StepController.default_for`).
    jacobian : JacobianPolicy
        When W-methods refresh their Jacobian and the inverse of the
        iteration matrix.
    """

    rtol: float = 1e-6
    atol: float = 1e-8
    h0: float = 0.0
    h_max: float = 0.0
    h_min: float = 0.0
    max_steps: int = 2_000_000
    wall_time: float = 60.0
    chatter_events: int = 100
    chatter_window: float | None = None
    event_tol: float = 1e-12
    dt_out: float = 0.0
    max_output: int = 5_000_000
    controller: StepController | None = None
    jacobian: JacobianPolicy = _DEFAULT_POLICY

    def __post_init__(self):
        if self.controller is not None and not isinstance(self.controller, StepController):
            raise TypeError(f"SolverOptions: controller = {self.controller!r} must be a "
                            "StepController or None")
        if not isinstance(self.jacobian, JacobianPolicy):
            raise TypeError(f"SolverOptions: jacobian = {self.jacobian!r} must be a "
                            "JacobianPolicy")
        for name in ("rtol", "atol", "h0", "h_max", "h_min", "wall_time", "chatter_window",
                     "event_tol", "dt_out"):
            if name == "chatter_window" and self.chatter_window is None:
                continue
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float)) \
                    or not math.isfinite(value):
                raise ValueError(f"SolverOptions: {name} = {value!r} must be a finite number")
        for name in ("rtol", "atol", "event_tol"):
            if getattr(self, name) <= 0:
                raise ValueError(f"SolverOptions: {name} = {getattr(self, name)!r} must be > 0")
        for name in ("h0", "h_max", "h_min", "wall_time", "chatter_window", "dt_out"):
            if getattr(self, name) is not None and getattr(self, name) < 0:
                raise ValueError(f"SolverOptions: {name} = {getattr(self, name)!r} must be >= 0")
        for name in ("max_steps", "chatter_events", "max_output"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or value < 0:
                raise ValueError(f"SolverOptions: {name} = {value!r} must be an integer >= 0")
        if self.max_steps < 1 or self.max_output < 2:
            raise ValueError("SolverOptions: max_steps must be >= 1 and max_output >= 2")
        if self.rtol < 1e-14:
            raise ValueError(f"SolverOptions: rtol = {self.rtol!r} must be >= 1e-14 "
                             "(below double-precision round-off)")

    #: keys a scenario's [solver] table or a command line may set, and their types
    MAPPING_KEYS: ClassVar[dict[str, type]] = {
        "rtol": float, "atol": float, "h0": float, "h_max": float, "h_min": float,
        "dt_out": float, "max_steps": int, "wall_time": float, "chatter_events": int,
        "chatter_window": float, "event_tol": float, "max_output": int, "controller": str}

    @classmethod
    def from_mapping(cls, mapping, **defaults) -> SolverOptions:
        """Options from a plain mapping (a scenario's ``[solver]`` table, ``KEY=VALUE``
        items of a command line): the one place that reads them, so every entry point
        accepts the same keys.  ``controller`` names a :class:`StepController` kind.
        Unknown keys and values of the wrong type raise ValueError naming the key."""
        kw = dict(defaults)
        for key, value in dict(mapping).items():
            kind = cls.MAPPING_KEYS.get(key)
            if kind is None:
                raise ValueError(f"unknown solver option {key!r}"
                                 f"{closest(str(key), cls.MAPPING_KEYS)}; options: "
                                 f"{', '.join(cls.MAPPING_KEYS)}")
            if kind is str:
                if not isinstance(value, str):
                    raise ValueError(f"solver option {key} = {value!r} must be a string")
                kw[key] = StepController(kind=value)
                continue
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise ValueError(  # noqa: TRY004 - a bad value in a file is a ValueError
                    f"solver option {key} = {value!r} must be a number")
            if kind is int and float(value) != int(value):
                raise ValueError(f"solver option {key} = {value!r} must be an integer")
            kw[key] = kind(value)
        return cls(**kw)

    def chatter_window_for(self, span: float) -> float:
        """The chatter window [s] for a run over ``span`` seconds: ``chatter_window``, by
        default ``min(1e-4·span, CHATTER_WINDOW_MAX_S)``."""
        if self.chatter_window is not None:
            return self.chatter_window
        return min(1e-4 * span, CHATTER_WINDOW_MAX_S)
