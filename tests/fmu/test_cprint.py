"""The generated plant printed as C (clutchsim.cgen.cprint) computes what the compiled plant
computes: right-hand side, outputs, Jacobian, event functions and resets on random states
of the default launch, for model (6) and for coulomb-robust (lock solve, event iteration),
and of Modelica's SimpleGearShift (a planetary set, a clutch and a brake switching) and
ElasticBearing (a gear on a sprung support)."""

import importlib.util
import shutil

import numpy as np
import pytest
from _dl_paths import EXAMPLES
from _fmu_tools import c_plant_difference

from clutchsim.fmu import CPrintError, print_c
from clutchsim.network import Network, compile_network
from clutchsim.scenario import load_scenario

pytestmark = pytest.mark.skipif(shutil.which("cc") is None and shutil.which("gcc") is None,
                                reason="no C compiler on this machine")


def plant(scenario, model):
    sc = load_scenario(EXAMPLES / scenario)
    net = sc.network(model)
    net = net if isinstance(net, Network) else net.network()
    u0 = {n: float(np.asarray(s(0.0)).ravel()[0]) for n, s in sc.inputs.items()}
    plan = compile_network(net)
    return plan, plan.system(net.components, inputs0=u0)


@pytest.mark.parametrize(("scenario", "model"), [
    ("launch.toml", "mykhailevych2020"), ("launch.toml", "coulomb-robust"),
    ("simple_gear_shift.toml", None), ("elastic_bearing.toml", None)])
def test_c_plant_equals_compiled_plant(scenario, model):
    plan, system = plant(scenario, model)
    worst, c, checked_lock = c_plant_difference(plan, system)
    assert worst <= 1e-12
    assert checked_lock
    # the printed program holds the kernels it calls, printed from their own source
    assert "mykhailevych2020_force" in c.program.source or model != "mykhailevych2020"
    locks = any(s.endswith(".locked") for s in system.state_names)
    assert "cs_lock_solve" in c.program.source or not locks


@pytest.mark.parametrize(("line", "named"), [
    ("dy[0] = sum(y)", "a call of sum"),
    ("dy[0] = y[0:2]", "a slice outside a call"),
    ("dy[0] = y[0.5]", "an index that is not an integer"),
    ("dy[0] = 1.0 if y else 0.0", "an array .a1. where a number is needed"),
    ("try:\n        dy[0] = 1.0\n    finally:\n        pass", "the statement Try"),
])
def test_unprintable_construct_is_named(tmp_path, line, named):
    path = tmp_path / "bad_plant.py"
    path.write_text(f"def rhs(t, y, u, p, dy):\n    dy[1] = 0.0\n    {line}\n")
    spec = importlib.util.spec_from_file_location("bad_plant", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    with pytest.raises(CPrintError, match=rf"bad_plant\.rhs as C \(line 3.*{named}"):
        print_c(mod, {"rhs": ("double", "a1", "a1", "a1", "a1")})
