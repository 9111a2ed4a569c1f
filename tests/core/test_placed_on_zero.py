"""An event function that a reset places exactly on zero, and that then leaves zero in its
own direction, is already past its crossing: it fires where the step starts
(core/engine.c; docs/core.md).  The plant: a free point ``y`` at rest; at t = 0.5 the
event "release" (k = 1) sets the mode to 1, from which on ``y' = -1`` and the event
"stop" (k = 0, direction -1, ``g = y``) is armed; before, ``g = 1`` (not armed).  The stop's
function is placed on 0 by the release and goes down at once: the stop fires at 0.5 and
holds the point (mode 2).  Without the rule the function starts from its next sign,
negative, never crosses, and ``y`` runs to -0.5.  A function that crossed and landed on
zero (the probe of test_events_and_guards) still fires once.

Before it fires at once, the step is taken again shorter (``PROBE``, ``MAX_PROBES``): its
first sample can hide a first move the right way (:class:`_Probe`)."""

import math
from typing import NamedTuple

import numpy as np
import pytest

from clutchsim._jit import jit
from clutchsim.core import SolverOptions, System, register_system, simulate


class _Placed(NamedTuple):
    k: int = 0


@jit
def _rhs(t, y, u, p, dy):
    dy[0] = -1.0 if y[1] == 1.0 else 0.0
    dy[1] = 0.0


@jit
def _events(t, y, u, p, g):
    g[0] = y[0] if y[1] == 1.0 else 1.0
    g[1] = t - 0.5 if y[1] == 0.0 else 1.0


@jit
def _reset(t, y, u, p, k):
    if k == 1:
        y[0] = p[0]         # 0, or a round-off past it (a lock's projection leaves ~1e-14)
        y[1] = 1.0
    else:
        y[1] = 2.0
    return 1


register_system(_Placed, rhs=_rhs, events=_events, reset=_reset)


@pytest.mark.parametrize("placed", [0.0, -1e-14, -1.8e-15])
@pytest.mark.parametrize("solver", ["rodas4", "dopri5"])
def test_a_function_placed_on_zero_that_leaves_it_its_own_way_fires_at_once(solver, placed):
    # -1e-14 and -1.8e-15: a release that leaves the function a round-off past zero, on
    # its far side (fuzzed networks, seed 7: a freewheel's slip after its lock's
    # projection); within 64 ulps of the largest state it counts as placed on zero
    system = System(_Placed(), np.array([placed]), np.zeros(2), ("y", "mode"), ("-", "-"),
                    event_names=("stop", "release"), event_directions=(-1, 1), name="placed")
    res = simulate(system, (0.0, 1.0), solver=solver,
                   options=SolverOptions(rtol=1e-9, atol=1e-12))
    assert [(e.name, round(e.t, 12)) for e in res.events] == [("release", 0.5), ("stop", 0.5)]
    assert res.final("mode") == 2.0 and res.final("y") == placed


class _Probe(NamedTuple):
    k: int = 0


@jit
def _probe_rhs(t, y, u, p, dy):
    # released at 0.5, the point moves forward for about tau·ln 2, then back
    dy[0] = (2.0 * math.exp(-(t - 0.5) / p[0]) - 1.0) if y[1] == 1.0 else 0.0
    dy[1] = 0.0
    dy[2] = math.sin(t) - y[2]          # a slow neighbour that sets the step size


@jit
def _probe_reset(t, y, u, p, k):
    if k == 1:
        y[0] = 0.0
        y[1] = 1.0
    else:
        y[1] = 2.0
    return 1


register_system(_Probe, rhs=_probe_rhs, events=_events, reset=_probe_reset)


@pytest.mark.parametrize("tau", [1e-5, 1e-6])
@pytest.mark.parametrize("solver", ["rodas4", "rodas5p", "dopri5"])
def test_a_first_move_the_right_way_hidden_in_a_step_is_probed(solver, tau):
    """Released on zero, the point first moves forward (``y > 0``) for ~0.7·tau, then
    back: the stop is where ``y`` returns to zero, at ``0.5 + 1.5936·tau`` (the root of
    ``2·(1 − e^(−x)) = x``).  The first step after the release was longer than the
    excursion for rodas5p and dopri5 (a slow neighbour sets it): its first sample was
    past zero and the stop fired at 0.5, on the release (a freewheel freed at its limit
    beside a stiff Stribeck clutch, fuzz seed 7)."""
    system = System(_Probe(), np.array([tau]), np.array([0.0, 0.0, 1.0]), ("y", "mode", "z"),
                    ("-", "-", "-"), event_names=("stop", "release"),
                    event_directions=(-1, 1), name="probe")
    res = simulate(system, (0.0, 1.0), solver=solver,
                   options=SolverOptions(rtol=1e-6, atol=1e-6))
    (rel, t_rel), (stop, t_stop) = [(e.name, e.t) for e in res.events]
    assert (rel, t_rel, stop) == ("release", 0.5, "stop")
    assert 1.0 * tau < t_stop - 0.5 < 1.5936 * tau * 1.5
    assert res.final("mode") == 2.0
