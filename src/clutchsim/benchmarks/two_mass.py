"""A two-mass plant for the Coulomb verification problem (Code_Aster V5.01.106).

Mass ``m1`` rests on a friction contact; a spring ``k`` joins it to mass ``m2``, which
is pushed by the force input ``force``::

    m1·dv1/dt = k·(x2 - x1) - F,      m2·dv2/dt = force(t) - k·(x2 - x1)

``F`` is the friction force of any :mod:`clutchsim.friction` model with the stick force
``F_e = k·(x2 - x1)`` (the force on ``m1`` other than friction).  States
``x1, v1, x2, v2`` then the model's states.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .._jit import jit
from ..core import System, register_system
from ..friction import friction_events, friction_force, friction_reset
from ..friction.base import FrictionModel

__all__ = ["make_two_mass"]

_M1, _M2, _K, _CODE, _NZ = range(5)
_HEADER = 5


class TwoMass(NamedTuple):
    """Tag type of the two-mass plant."""

    k: int = 0


@jit
def _spring(y, p):
    return p[_K] * (y[2] - y[0])


@jit
def _rhs(t, y, u, p, dy):
    nz = int(p[_NZ])
    fk = _spring(y, p)
    f = friction_force(int(p[_CODE]), p[_HEADER:], y[4:4 + nz], y[1], fk, 1.0, dy[4:4 + nz])
    dy[0] = y[1]
    dy[1] = (fk - f) / p[_M1]
    dy[2] = y[3]
    dy[3] = (u[0] - fk) / p[_M2]


@jit
def _events(t, y, u, p, g):
    nz = int(p[_NZ])
    friction_events(int(p[_CODE]), p[_HEADER:], y[4:4 + nz], y[1], _spring(y, p), 1.0, g)


@jit
def _reset(t, y, u, p, k):
    nz = int(p[_NZ])
    action = friction_reset(int(p[_CODE]), p[_HEADER:], y[4:4 + nz], y[1], _spring(y, p),
                            1.0, k)
    if action == 2:
        y[1] = 0.0
    return 1 if action != 0 else 0


@jit
def _outputs(t, y, u, p, out):
    nz = int(p[_NZ])
    dz = np.empty(nz)
    fk = _spring(y, p)
    out[0] = friction_force(int(p[_CODE]), p[_HEADER:], y[4:4 + nz], y[1], fk, 1.0, dz)
    out[1] = fk


register_system(TwoMass, rhs=_rhs, events=_events, reset=_reset, outputs=_outputs)


def make_two_mass(model: FrictionModel, *, m1: float, m2: float, k: float) -> System:
    """The two-mass plant around ``model``, from rest.

    Parameters
    ----------
    model : FrictionModel
        Friction on mass 1.
    m1, m2 : float
        Masses [kg] (> 0).
    k : float
        Stiffness of the spring between them [N/m] (> 0).

    Returns
    -------
    System
        Input ``force`` [N] on mass 2; outputs ``F`` (friction force) and ``F_spring`` [N].
    """
    for name, value in (("m1", m1), ("m2", m2), ("k", k)):
        if not (np.isfinite(value) and value > 0):
            raise ValueError(f"two-mass plant: {name} = {value!r} must be finite and > 0")
    header = np.array([m1, m2, k, model.code, model.n_states], dtype=float)
    return System(
        TwoMass(), np.concatenate([header, model.pack()]),
        np.concatenate([np.zeros(4), model.initial_state()]),
        ("x1", "v1", "x2", "v2") + model.state_names(),
        ("m", "m/s", "m", "m/s") + model.state_units(),
        input_names=("force",), input_units=("N",),
        output_names=("F", "F_spring"), output_units=("N", "N"),
        event_names=tuple(f"{model.name}: {e}" for e in model.event_names()),
        event_directions=tuple(int(d) for d in model.event_directions()),
        name=f"two-mass plant with {model.name}",
        metadata={"model": model.name, "m1": m1, "m2": m2, "k": k},
    )
