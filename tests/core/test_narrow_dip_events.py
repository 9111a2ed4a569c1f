"""An event function that passes zero and comes back within a moment far shorter than a
step (a freewheel that locks for microseconds where the drive torque changes sign):
both ends of the step and every uniform sample inside it have one sign, so only the
search for the bottom of the valley finds the crossing (``core/engine.c``,
``_sharpen``).  Here the bouncing ball with gravity reversed, thrown down toward the
floor so that it turns only ``eps`` below it: the impact (the downward crossing of the
height) and the upward crossing a few microseconds later lie inside one step of a
trajectory whose polynomial solution lets the steps grow without bound."""

import math

import numpy as np
import pytest

from clutchsim.core import SolverOptions, System, simulate
from clutchsim.core.reference_problems import Ball


@pytest.mark.parametrize("solver", ["dopri5", "rodas4", "rodas5p", "ros34pw2"])
@pytest.mark.parametrize("eps", [1e-10, 1e-8])
def test_a_crossing_inside_a_dip_narrower_than_the_step_is_found(solver, eps):
    g, v0 = 9.81, 1.0
    h0 = v0 * v0 / (2.0 * g) - eps          # h'' = +g: it turns at v0/g, eps below 0
    ball = System(Ball(), np.array([-g, 0.0]), np.array([h0, -v0]), ("h", "v"), ("m", "m/s"),
                  event_names=("impact",), event_directions=(-1,), name="grazing ball")
    res = simulate(ball, (0.0, 0.5), solver=solver,
                   options=SolverOptions(rtol=1e-10, atol=1e-12))
    assert res.status == "completed", res.message
    t_down = (v0 - math.sqrt(2.0 * g * eps)) / g
    t_up = (v0 + math.sqrt(2.0 * g * eps)) / g
    assert t_up - t_down < 1e-3 * 0.5        # far narrower than the run
    assert [ev.name for ev in res.events] == ["impact"]
    assert abs(res.events[0].t - t_down) < 1e-9
    assert res.stats.steps < 40             # steps much wider than the dip
