"""The friction rig's plant: generated per friction model and compiled as C.

Each model's rig module (:func:`clutchsim.rig.rig_source`) calls the model's own kernels;
:mod:`clutchsim.cgen.loader` prints it as C (about a second for a new model, where numba
took 10-12 s per model) and falls back to numba without a C compiler.  Checked here: the
registered functions are the C ones, they compute the rig's equations from the model's
kernels (called through the compiled dispatchers, an independent path) in both drives, a
stuck reset stops the body, and the numba fallback gives the same run."""

import numpy as np
import pytest

from clutchsim.core import NativeFunction
from clutchsim.core.system import plant_functions
from clutchsim.friction import MODELS, friction_force, make_model
from clutchsim.rig import RIG_HEADER, make_rig, run_rig

#: a model's rig in the domain of its default parameter set
DOMAIN = {"rotational-friction": "rotational"}


def _model(name):
    return make_model(name)


def _states(m, rng, k):
    """Friction states a run can reach: at rest, and sliding at random speeds."""
    yield np.asarray(m.initial_state(), float), 0.0
    for _ in range(k):
        v = float(rng.choice([-1.0, 1.0]) * 10.0 ** rng.uniform(-4, 0))
        yield np.asarray(m.sliding_state(v), float), v


@pytest.mark.parametrize("name", sorted(MODELS))
def test_rig_plant_is_c_and_computes_the_rig_equations(name):
    m = _model(name)
    domain = DOMAIN.get(name, "translational")
    rng = np.random.default_rng(7)
    mass, k, V, y0 = 2.0, 30.0, 0.1, 0.02
    force = make_rig(m, domain=domain, mass=mass, spring=k, pull_speed=V, spring_offset=y0)
    velocity = make_rig(m, domain=domain, drive="velocity")
    fns = plant_functions(force.tag)
    assert all(isinstance(f, NativeFunction)
               for f in (fns.rhs, fns.events, fns.reset, fns.outputs, fns.jac))
    nz = m.n_states
    pf = force.params[RIG_HEADER:]
    for z, v in _states(m, rng, 12):
        t, x, f_app, scale = rng.uniform(0, 2), rng.uniform(-0.1, 0.1), rng.normal(), 0.7
        # force drive: m·dv/dt = F_app + k·(y0 + V·t − x) − F
        y = np.concatenate([[x, v], z])
        u = np.array([f_app, scale])
        spring = k * (y0 + V * t - x)
        dz = np.zeros(nz)
        F = friction_force(m.code, pf, z, v, f_app + spring, scale, dz)
        dy = np.full(2 + nz, np.nan)
        fns.rhs(t, y, u, force.params, dy)
        np.testing.assert_allclose(dy, [v, (f_app + spring - F) / mass, *dz],
                                   rtol=1e-13, atol=1e-300)
        out = np.full(4 + nz, np.nan)
        fns.outputs(t, y, u, force.params, out)
        np.testing.assert_allclose(out, [F, f_app + spring, spring, F * v, *dz],
                                   rtol=1e-13, atol=1e-300)
        # velocity drive: v is the input, y = [x, z]
        yv = np.concatenate([[x], z])
        uv = np.array([v, scale])
        dzv = np.zeros(nz)
        Fv = friction_force(m.code, pf, z, v, 0.0, scale, dzv)
        dyv = np.full(1 + nz, np.nan)
        plant_functions(velocity.tag).rhs(t, yv, uv, velocity.params, dyv)
        np.testing.assert_allclose(dyv, [v, *dzv], rtol=1e-13, atol=1e-300)
        outv = np.full(4 + nz, np.nan)
        plant_functions(velocity.tag).outputs(t, yv, uv, velocity.params, outv)
        np.testing.assert_allclose(outv, [Fv, 0.0, 0.0, Fv * v, *dzv], rtol=1e-13,
                                   atol=1e-300)


def test_a_stuck_reset_stops_the_body():
    """coulomb-robust: a slide whose slip reaches zero under a load within the capacity
    sticks; the rig then sets the body's speed to exactly 0 (the stick is exact)."""
    m = _model("coulomb-robust")
    res = run_rig(m, 2.0, force=0.3 * m.F_c, v0=0.5)
    assert res.status == "completed", res.message
    # the slide decelerates at (F_c - 0.3 F_c)/m and stops at t = v0·m/(0.7 F_c)
    stop = [e for e in res.events if e.name == "coulomb-robust: stop"]
    assert len(stop) == 1 and stop[0].t == pytest.approx(0.5 / (0.7 * m.F_c), rel=1e-9)
    after = res.t > stop[0].t
    assert after.any() and np.all(res["v"][after] == 0.0) and np.all(res["mode"][after] == 0.0)

