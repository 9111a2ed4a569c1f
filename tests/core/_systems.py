"""Small reference plants with known solutions, used by the core tests."""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from clutchsim._jit import jit
from clutchsim.core import System, register_system


class Oscillator(NamedTuple):
    k: int = 0


@jit
def _osc_rhs(t, y, u, p, dy):
    dy[0] = y[1]
    dy[1] = -p[0] * p[0] * y[0] - 2.0 * p[1] * p[0] * y[1] + u[0]


register_system(Oscillator, rhs=_osc_rhs)


def oscillator(omega=2.0, zeta=0.0, x0=1.0, v0=0.0):
    """x'' + 2ζω x' + ω² x = u."""
    return System(Oscillator(), np.array([omega, zeta]), np.array([x0, v0]), ("x", "v"),
                  ("m", "m/s"), input_names=("F",), input_units=("N",), name="oscillator")


class Ball(NamedTuple):
    k: int = 0


@jit
def _ball_rhs(t, y, u, p, dy):
    dy[0] = y[1]
    dy[1] = -p[0]


@jit
def _ball_events(t, y, u, p, g):
    g[0] = y[0]


@jit
def _ball_reset(t, y, u, p, k):
    y[0] = 0.0
    y[1] = -p[1] * y[1]
    return 1


register_system(Ball, rhs=_ball_rhs, events=_ball_events, reset=_ball_reset)


def ball(g=9.81, e=0.8, h0=1.0):
    return System(Ball(), np.array([g, e]), np.array([h0, 0.0]), ("h", "v"), ("m", "m/s"),
                  event_names=("impact",), event_directions=(-1,), name="bouncing ball")


def ball_bounce_times(g, e, h0, n):
    """Analytic impact times of the bouncing ball."""
    t = math.sqrt(2 * h0 / g)
    v = math.sqrt(2 * g * h0)
    out = [t]
    for _ in range(n - 1):
        v *= e
        t += 2 * v / g
        out.append(t)
    return np.array(out)
