"""The generated plant printed as C (clutchsim.fmu.cprint) computes what the compiled plant
computes: right-hand side, outputs, Jacobian, event functions and resets on random states
of the default launch, for model (6) and for coulomb-robust (lock solve, event iteration),
and of Modelica's SimpleGearShift (a planetary set, a clutch and a brake switching) and
ElasticBearing (a gear on a sprung support)."""

import importlib.util
import shutil

import numpy as np
import pytest
from _dl_paths import EXAMPLES

from clutchsim.fmu import CPlant, CPrintError, print_c
from clutchsim.network import Network, compile_network
from clutchsim.scenario import load_scenario

pytestmark = pytest.mark.skipif(shutil.which("cc") is None and shutil.which("gcc") is None,
                                reason="no C compiler on this machine")


def plant(scenario, model):
    sc = load_scenario(EXAMPLES / scenario)
    net = sc.chain(model)
    net = net if isinstance(net, Network) else net.network()
    u0 = {n: float(np.asarray(s(0.0)).ravel()[0]) for n, s in sc.inputs.items()}
    plan = compile_network(net)
    return plan, plan.system(net.components, inputs0=u0)


def random_states(system, rng, k=100):
    n = len(system.y0)
    for _ in range(k):
        y = system.y0 * (1.0 + 0.5 * rng.standard_normal(n)) + 3.0 * rng.standard_normal(n)
        yield y, rng.uniform(-0.2, 1.2, len(system.input_names)), rng.uniform(0.0, 4.0)


def rel(a, b):
    return float(np.max(np.abs(a - b) / (1.0 + np.abs(a)))) if np.size(a) else 0.0


@pytest.mark.parametrize(("scenario", "model"), [
    ("launch.toml", "mykhailevych2020"), ("launch.toml", "coulomb-robust"),
    ("simple_gear_shift.toml", None), ("elastic_bearing.toml", None)])
def test_c_plant_equals_compiled_plant(scenario, model):
    plan, system = plant(scenario, model)
    c = CPlant(plan)
    mod, p = plan.module, system.params
    n, no, ne = len(system.y0), len(system.output_names), len(system.event_names)
    rng = np.random.default_rng(7)
    worst = 0.0
    checked_lock = False
    locks = [s[:-len(".locked")] for s in system.state_names if s.endswith(".locked")]
    for y, u, t in random_states(system, rng):
        for el in locks:                        # both modes of each switching element
            ilk = system.state_names.index(f"{el}.locked")
            y[ilk] = float(rng.integers(0, 2))
            y[system.state_names.index(f"{el}.mode")] = 0.0 if y[ilk] else float(
                rng.choice([-1.0, 1.0]))
            checked_lock |= y[ilk] > 0.5
        for name, size in (("rhs", n), ("outputs", no), ("events", ne)):
            a, b = np.zeros(size), np.zeros(size)
            getattr(mod, name)(t, y, u, p, a)
            getattr(c, name)(t, y, u, p, b)
            assert np.all(np.isfinite(a))
            worst = max(worst, rel(a, b))
        A, B = np.zeros((n, n)), np.zeros((n, n))
        mod.jac(t, y, u, p, A)
        c.jac(t, y, u, p, B)
        worst = max(worst, rel(A, B))
        for k in range(ne):
            ya, yb = y.copy(), y.copy()
            ra, rb = mod.reset(t, ya, u, p, k), c.reset(t, yb, u, p, k)
            assert ra == rb, (k, ra, rb)
            worst = max(worst, rel(ya, yb))
    assert worst <= 1e-12
    assert checked_lock or not locks
    # the printed program holds the kernels it calls, printed from their own source
    assert "mykhailevych2020_force" in c.program.source or model != "mykhailevych2020"
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
