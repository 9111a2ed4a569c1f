"""Step-size controllers and the Jacobian/iteration-matrix reuse policy, as small immutable
objects.

A controller turns the error norm ``e`` of a step (``e ≤ 1``: accepted) into the next step
size.  With ``q = p̂ + 1`` (the embedded order plus one):

* ``"I"``: ``h_new = h · clip(safety · e^(−1/q), min_factor, max_factor)`` — the classic
  controller (Hairer, Nørsett & Wanner, *Solving ODEs I*, §II.4).
* ``"predictive"``: Gustafsson's predictive controller as in Hairer & Wanner's
  ``rodas.f`` (*Solving ODEs II*, §IV.8, eq. 8.21): the smaller of the I step and
  ``h · (h/h_old) · (e_old/e²)^(1/q)``; it avoids the step rejections an I controller
  makes when the error grows steadily.  Default of the Rosenbrock methods.
* ``"pid"``: Söderlind's digital filter, ``h_new = h · safety · e_n^(−β1/q) ·
  e_{n−1}^(−β2/q) · e_{n−2}^(−β3/q)``, clipped (G. Söderlind, *Digital filters in adaptive
  time-stepping*, ACM TOMS 29:1–26, 2003).  The default ``beta = (0.7, −0.4, 0)`` is the
  PI controller of *Solving ODEs I*, §IV.2 (``α = 0.7/k``, ``β = 0.4/k``).

After a rejected step the next step never grows.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["CONTROLLERS", "JacobianPolicy", "StepController"]

#: controller kinds and their codes in the compiled loop
CONTROLLERS = {"I": 0, "predictive": 1, "pid": 2}
C_KIND, C_SAFETY, C_MIN, C_MAX, C_B1, C_B2, C_B3 = range(7)
N_CTRL = 7


@dataclass(frozen=True)
class StepController:
    """How the step size follows the error estimate (see the module docstring).

    Parameters
    ----------
    kind : str
        ``"I"``, ``"predictive"`` or ``"pid"``.
    safety : float
        Safety factor in (0, 1].
    min_factor, max_factor : float
        Bounds of ``h_new / h`` (``0 < min_factor < 1 < max_factor``).
    beta : (float, float, float)
        Exponents of the ``"pid"`` filter (ignored by the other kinds).
    """

    kind: str = "predictive"
    safety: float = 0.9
    min_factor: float = 0.2
    max_factor: float = 6.0
    beta: tuple[float, float, float] = (0.7, -0.4, 0.0)

    def __post_init__(self):
        if self.kind not in CONTROLLERS:
            from .system import closest
            raise ValueError(f"StepController: kind = {self.kind!r} is not known"
                             f"{closest(str(self.kind), CONTROLLERS)}; valid kinds: "
                             f"{', '.join(CONTROLLERS)}")
        for name in ("safety", "min_factor", "max_factor"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                raise ValueError(f"StepController: {name} = {v!r} must be a finite number")
        if not 0.0 < self.safety <= 1.0:
            raise ValueError(f"StepController: safety = {self.safety!r} must be in (0, 1]")
        if not 0.0 < self.min_factor < 1.0 < self.max_factor:
            raise ValueError(f"StepController: min_factor = {self.min_factor!r} and max_factor "
                             f"= {self.max_factor!r} must satisfy 0 < min_factor < 1 < "
                             "max_factor")
        beta = tuple(self.beta)
        if len(beta) != 3 or not all(isinstance(b, (int, float)) and math.isfinite(b)
                                     for b in beta):
            raise ValueError(f"StepController: beta = {self.beta!r} must be three finite "
                             "numbers")
        object.__setattr__(self, "beta", tuple(float(b) for b in beta))

    @classmethod
    def default_for(cls, family_explicit: bool) -> StepController:
        """The default of a method family: I for explicit pairs (Dormand & Prince's
        ``dopri5`` constants), predictive for Rosenbrock methods (``rodas.f``)."""
        if family_explicit:
            return cls(kind="I", safety=0.9, min_factor=0.2, max_factor=10.0)
        return cls()

    def packed(self) -> np.ndarray:
        out = np.zeros(N_CTRL)
        out[C_KIND] = CONTROLLERS[self.kind]
        out[C_SAFETY], out[C_MIN], out[C_MAX] = self.safety, self.min_factor, self.max_factor
        out[C_B1], out[C_B2], out[C_B3] = self.beta
        return out


@dataclass(frozen=True)
class JacobianPolicy:
    """When the implicit methods form a new Jacobian and invert a new iteration
    matrix.

    Parameters
    ----------
    max_age : int
        A W-method (ROS34PW2) reuses its Jacobian for at most this many accepted steps;
        it is always refreshed after a rejected step, an event or a breakpoint.  Methods
        that need the exact Jacobian (RODAS4, RODAS5P) form one every step.
    lu_reuse : float
        A W-method keeps its inverse of ``I/(γh) − J`` while the step size stays within
        this relative band of the one it was inverted for (a W-method keeps its order with
        any matrix; the band bounds the loss of stability); 0 inverts anew every step.
    """

    max_age: int = 40
    lu_reuse: float = 0.0

    def __post_init__(self):
        if isinstance(self.max_age, bool) or not isinstance(self.max_age, int) \
                or self.max_age < 1:
            raise ValueError(f"JacobianPolicy: max_age = {self.max_age!r} must be an "
                             "integer >= 1")
        if isinstance(self.lu_reuse, bool) or not isinstance(self.lu_reuse, (int, float)) \
                or not 0.0 <= self.lu_reuse < 1.0:
            raise ValueError(f"JacobianPolicy: lu_reuse = {self.lu_reuse!r} must be in "
                             "[0, 1)")
