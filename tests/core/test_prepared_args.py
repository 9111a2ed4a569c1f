"""The integration loop's fixed arguments (signal bank, breakpoints, method, option
vectors) are prepared once per plant type, signal objects, span, solver and options
object (``core.simulate._prepare``), and never reused for other ones."""

import importlib

import numpy as np

from clutchsim.core import SolverOptions, simulate
from clutchsim.core.reference_problems import oscillator
from clutchsim.core.signals import Constant, Step

sim_mod = importlib.import_module("clutchsim.core.simulate")
OMEGA = 2.0     # rad/s


def _exact(t, force):
    """x'' + ω² x = F from x = 1 m, v = 0: x = F/ω² + (1 - F/ω²) cos ωt [m]."""
    xs = force / OMEGA**2
    return xs + (1.0 - xs) * np.cos(OMEGA * t)


def test_the_same_objects_reuse_one_preparation_and_give_the_same_run():
    system = oscillator(omega=OMEGA)
    force, opts = Constant(0.5), SolverOptions(rtol=1e-8, atol=1e-10)
    a = simulate(system, (0.0, 2.0), {"F": force}, solver="rodas4", options=opts)
    n = len(sim_mod._PREPARED)
    b = simulate(system, (0.0, 2.0), {"F": force}, solver="rodas4", options=opts)
    assert len(sim_mod._PREPARED) == n            # no second preparation
    np.testing.assert_array_equal(a["x"], b["x"])
    np.testing.assert_allclose(a["x"], _exact(a.t, 0.5), atol=1e-6)


def test_other_signals_options_or_spans_are_never_served_a_stale_preparation():
    system = oscillator(omega=OMEGA)
    loose, tight = SolverOptions(rtol=1e-4, atol=1e-6), SolverOptions(rtol=1e-9, atol=1e-11)
    f1, f3 = Constant(1.0), Constant(3.0)
    runs = {}
    for force, F in ((f1, 1.0), (f3, 3.0), (f1, 1.0)):          # alternate the inputs
        for opts in (loose, tight, loose):                       # and the options
            res = simulate(system, (0.0, 2.0), {"F": force}, solver="rodas4", options=opts)
            np.testing.assert_allclose(res["x"], _exact(res.t, F),
                                       atol=1e-2 if opts is loose else 1e-7)
            key = (F, id(opts))
            if key in runs:                                      # the same run again
                np.testing.assert_array_equal(res["x"], runs[key]["x"])
            runs[key] = res
    assert runs[1.0, id(tight)].stats.steps > runs[1.0, id(loose)].stats.steps
    # a step at t = 1 s is a breakpoint of this span, not of a span ending before it
    step = Step(1.0, height=2.0)
    short = simulate(system, (0.0, 0.9), {"F": step}, solver="rodas4", options=tight)
    long = simulate(system, (0.0, 2.0), {"F": step}, solver="rodas4", options=tight)
    np.testing.assert_allclose(short["x"], _exact(short.t, 0.0), atol=1e-7)
    after = long.t > 1.0
    assert np.abs(long["x"][after] - _exact(long.t[after], 0.0)).max() > 0.1
