"""Plants without a static argument reach the integrators as function values: one compiled
integrator serves them all (a new plant compiles only its own functions)."""

import numba
import numpy as np
from numba import types

from clutchsim.core import _driver as drv
from clutchsim.core import simulate
from clutchsim.core.reference_problems import ball, oscillator, riccati
from clutchsim.core.system import FACTOR_SIG, JAC_SIG, KERNEL_SIG, RESET_SIG, SOLVE_SIG, kernels


def _function_value_signatures():
    return [sig for sig in drv.integrate.signatures
            if isinstance(sig[0], types.BaseTuple)
            and not isinstance(sig[0], types.BaseNamedTuple)]


def test_plants_without_static_share_one_compiled_integrator():
    for system, inputs in ((oscillator(), {"F": 0.0}), (riccati(), None), (ball(), None)):
        for solver in ("ros34pw2", "dopri5"):
            res = simulate(system, (0.0, 1.0), inputs, solver=solver)
            assert res.status == "completed", res.message
    assert len(_function_value_signatures()) == 1
    # and the answers are the plants' own: Riccati's exact solution 1/(1 + t²)
    res = simulate(riccati(), (0.0, 1.0), solver="rodas4")
    np.testing.assert_allclose(res["y"], 1.0 / (1.0 + res.t ** 2), rtol=1e-5)


def test_kernels_are_typed_as_function_values_also_for_every_rig_model():
    ks = kernels(oscillator().tag)
    assert [numba.typeof(k) for k in ks] == [types.FunctionType(KERNEL_SIG)] * 2 + [
        types.FunctionType(RESET_SIG), types.FunctionType(KERNEL_SIG),
        types.FunctionType(JAC_SIG), types.FunctionType(FACTOR_SIG),
        types.FunctionType(SOLVE_SIG)]
    assert kernels(oscillator().tag) is ks               # built once per tag type
    from clutchsim.friction import make_model
    from clutchsim.rig import make_rig
    for name in ("lugre", "dahl"):
        rig = make_rig(make_model(name), spring=2.0, pull_speed=0.1)
        rk = kernels(rig.tag)
        assert [numba.typeof(k) for k in rk] == [numba.typeof(k) for k in ks]
        res = simulate(rig, (0.0, 0.5), {"force": 0.0, "scale": 1.0}, solver="ros34pw2")
        assert res.status == "completed", res.message
    # two friction models, one compiled integrator: the models reach it as function values
    assert len(_function_value_signatures()) == 1
