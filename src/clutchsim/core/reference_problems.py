"""Reference problems with known solutions: the test bed of the integrators.

Harmonic oscillator (exact), Riccati equation y' = -2ty² (exact 1/(1+t²)), bouncing ball
(analytic impact times), an oscillator watched by monitoring events (analytic crossing
times), a stiff Prothero–Robinson equation watched by a clock event (exact cos t), stiff van
der Pol, a naive sign() switch (chatters), and a
right-hand side that turns NaN.  They live in the package (not in the tests) so that every
process can import their tag types: numba's cache index records them.
"""

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


class Monitored(NamedTuple):
    k: int = 0


@jit
def _monitored_rhs(t, y, u, p, dy):
    dy[0] = y[1]
    dy[1] = -p[0] * p[0] * y[0]


@jit
def _monitored_events(t, y, u, p, g):
    g[0] = y[0]
    g[1] = math.sin(p[1] * t)


@jit
def _monitored_reset(t, y, u, p, k):
    return int(p[2])


register_system(Monitored, rhs=_monitored_rhs, events=_monitored_events,
                reset=_monitored_reset)


def monitored_oscillator(omega=1.0, Omega=2.0 * math.pi, action=0):
    """x'' = -ω² x (x0 = 1, v0 = 0) with two monitoring events whose reset changes nothing
    and answers ``action``: ``x`` crossing zero (at t = (k + ½)·π/ω) and ``sin(Ω·t)``
    crossing zero (at t = k·π/Ω)."""
    return System(Monitored(), np.array([omega, Omega, float(action)]), np.array([1.0, 0.0]),
                  ("x", "v"), ("m", "m/s"), event_names=("x = 0", "sin(Ωt) = 0"),
                  event_directions=(0, 0), name="monitored oscillator")


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


class StiffTracker(NamedTuple):
    """Prothero–Robinson ``y' = −λ·(y − cos t) − sin t`` (exact ``y = cos t``; stiff for
    large λ) watched by a clock event ``sin(Ω·t) = 0`` whose reset changes nothing and
    answers ``action``."""

    k: int = 0


@jit
def _tracker_rhs(t, y, u, p, dy):
    dy[0] = -p[0] * (y[0] - math.cos(t)) - math.sin(t)


@jit
def _tracker_events(t, y, u, p, g):
    g[0] = math.sin(p[1] * t)


# its reset is the monitored oscillator's: nothing changes, the action is p[2]
register_system(StiffTracker, rhs=_tracker_rhs, events=_tracker_events,
                reset=_monitored_reset)


def stiff_tracker(lam=1e6, Omega=1.0, action=0):
    """The :class:`StiffTracker` problem, ``y(0) = 1``; its events at ``t = k·π/Ω``."""
    return System(StiffTracker(), np.array([lam, Omega, float(action)]), np.array([1.0]),
                  ("y",), ("-",), event_names=("sin(Ωt) = 0",), event_directions=(0,),
                  name="stiff tracker")


class VanDerPol(NamedTuple):
    k: int = 0


@jit
def _vdp_rhs(t, y, u, p, dy):
    dy[0] = y[1]
    dy[1] = p[0] * (1.0 - y[0] * y[0]) * y[1] - y[0]


register_system(VanDerPol, rhs=_vdp_rhs)


def van_der_pol(mu=100.0):
    return System(VanDerPol(), np.array([mu]), np.array([2.0, 0.0]), ("x", "y"), ("-", "-"),
                  name="van der Pol")


class SignSwitch(NamedTuple):
    """x' = u - c·sign(x): a naive Coulomb block.  With c > |u| it sticks at x = 0 in a
    sliding mode that a switching law cannot represent (chatter)."""

    k: int = 0


@jit
def _sign_rhs(t, y, u, p, dy):
    s = 1.0 if y[0] > 0.0 else (-1.0 if y[0] < 0.0 else 0.0)
    dy[0] = u[0] - p[0] * s
    dy[1] = 1.0


@jit
def _sign_events(t, y, u, p, g):
    g[0] = y[0]


register_system(SignSwitch, rhs=_sign_rhs, events=_sign_events)


def sign_switch(c=1.0, x0=1.0, monitored=True):
    names = ("sign change of x",) if monitored else ()
    dirs = (0,) if monitored else ()
    tag = SignSwitch() if monitored else SignSwitchNoEvents()
    return System(tag, np.array([c]), np.array([x0, 0.0]), ("x", "clock"), ("m", "s"),
                  input_names=("u",), input_units=("m/s",), event_names=names,
                  event_directions=dirs, name="naive sign switch")


class SignSwitchNoEvents(NamedTuple):
    k: int = 0


register_system(SignSwitchNoEvents, rhs=_sign_rhs)


class Poison(NamedTuple):
    """Produces NaN in its second state once t > p[0]."""

    k: int = 0


@jit
def _poison_rhs(t, y, u, p, dy):
    dy[0] = 1.0
    dy[1] = math.sqrt(p[0] - t)


register_system(Poison, rhs=_poison_rhs)


def poison(t_nan=0.5):
    return System(Poison(), np.array([t_nan]), np.zeros(2), ("a", "b"), ("-", "-"),
                  name="poison")


class Riccati(NamedTuple):
    """y' = -2 t y², y(0) = 1: exact solution 1 / (1 + t²)."""

    k: int = 0


@jit
def _riccati_rhs(t, y, u, p, dy):
    dy[0] = -2.0 * t * y[0] * y[0]


register_system(Riccati, rhs=_riccati_rhs)


def riccati():
    return System(Riccati(), np.zeros(1), np.ones(1), ("y",), ("-",), name="riccati")


class ProbePlant(NamedTuple):
    """y0' = c (the parameter p[0]); two events (y0 crossing 1 and 2) whose reset records
    k·100 + c in y1: checks that the parameters and the event index reach the plant."""

    k: int = 0


@jit
def _probe_rhs(t, y, u, p, dy):
    dy[0] = p[0]
    dy[1] = 0.0


@jit
def _probe_events(t, y, u, p, g):
    g[0] = y[0] - 1.0
    g[1] = y[0] - 2.0


@jit
def _probe_reset(t, y, u, p, k):
    y[1] = y[1] * 1000.0 + k * 100.0 + p[0]
    return 1


@jit
def _probe_outputs(t, y, u, p, out):
    out[0] = p[0]


register_system(ProbePlant, rhs=_probe_rhs, events=_probe_events, reset=_probe_reset,
                outputs=_probe_outputs)


def probe(c: float = 7.0):
    return System(ProbePlant(), np.array([c]), np.zeros(2), ("y", "log"), ("-", "-"),
                  output_names=("c",), output_units=("-",),
                  event_names=("y = 1", "y = 2"), event_directions=(1, 1), name="probe")
