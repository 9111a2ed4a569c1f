"""Issue 34's network as an FMU (Model Exchange under FMPy's CVode, and co-simulation with
the FMU's own Rosenbrock): the clutch and the brake are both loaded beyond their zero
capacity at t0.  The clutch starts locked at its zero slip and the plant's settling after
the brake's break-away frees it in the direction of its stick torque; with the old initial
state (a free element in its stuck mode) the co-simulation FMU slid the clutch against its
slip, friction that created energy.  The FMU's event iteration (plant_core.c) fires every
event due at one instant, as the native integrator does: twin clutches whose slips cross
zero together."""

import shutil

import numpy as np
import pytest
from _fmu_tools import simulate, simulate_cs

from clutchsim.fmu import export_fmu
from clutchsim.scenario import load_scenario, run_scenario

pytest.importorskip("fmpy", reason="FMPy (the dev extra) runs the exported FMUs")
pytestmark = pytest.mark.skipif(shutil.which("cc") is None and shutil.which("gcc") is None,
                                reason="no C compiler on this machine")

SCENARIO = """
[scenario]
name = "issue34"
t_end = 0.5
clutch = "clutch"
models = ["coulomb-robust"]
expect_lockup = false

[solver]
method = "rodas4"
rtol = 1e-9
atol = 1e-10
dt_out = 0.0005

[inputs]
s1 = { type = "sine", amplitude = 1.0, freq = 1.0 }

[network]
connect = [["src.flange", "brake.flange", "P.a"], ["P.b", "sd.a"], ["sd.b", "A.a"],
           ["A.b", "clutch.a"], ["clutch.b", "B.a"]]

[[component]]
type = "torque"
name = "src"
input = "s1"

[[component]]
type = "brake"
name = "brake"
command = "s1"
friction = { model = "coulomb-robust", overrides = { F_c = 0.5, F_s = 0.5 } }

[[component]]
type = "inertia"
name = "P"
J = 4.0

[[component]]
type = "spring_damper"
name = "sd"
c = 1e4
d = 10.0

[[component]]
type = "inertia"
name = "A"
J = 1.0
omega0 = 10.0

[[component]]
type = "clutch"
name = "clutch"
command = "s1"
friction = { model = "coulomb-robust", overrides = { F_c = 1.56, F_s = 1.716 } }

[[component]]
type = "inertia"
name = "B"
J = 1.0
omega0 = 10.0
"""


@pytest.mark.parametrize("kind", ["me", "cs"])
def test_fmu_fires_every_event_due_at_t0(tmp_path, kind):
    path_toml = tmp_path / "issue34.toml"
    path_toml.write_text(SCENARIO, encoding="utf-8")
    scenario = load_scenario(path_toml)
    fmu = tmp_path / "issue34.fmu"
    export_fmu(scenario, fmu, "coulomb-robust", kind=kind)
    names = ["omega_B", "W_friction", "clutch.mode", "w_slip_clutch"]
    run = simulate if kind == "me" else simulate_cs
    f = run(fmu, scenario, names, 1e-8, 0.005)
    wf = f["W_friction"]
    assert np.all(np.diff(wf) >= -1e-6) and wf[-1] > 1.0, "friction created energy"
    # B is driven by nothing but the clutch, whose other side is slower: it slows down
    assert f["omega_B"][-1] < 9.9
    sliding = f["clutch.mode"] != 0.0
    assert np.all(f["clutch.mode"][sliding] * f["w_slip_clutch"][sliding] >= -1e-6)



def _shaft(i):
    return f"""
[[component]]
type = "torque"
name = "s{i}"
input = "tau"

[[component]]
type = "inertia"
name = "A{i}"
J = 0.2
omega0 = 50.0

[[component]]
type = "clutch"
name = "c{i}"
command = "cmd"
friction = {{ model = "mykhailevych2020", parameter_set = "mykhailevych2020_clutch" }}

[[component]]
type = "inertia"
name = "B{i}"
J = 1.0
"""


TWINS = """
[scenario]
name = "twins"
t_end = 1.0
clutch = "c1"
models = ["mykhailevych2020"]
expect_lockup = false

[solver]
method = "rodas4"
rtol = 1e-9
atol = 1e-10
dt_out = 0.001

[inputs]
tau = "20 + 30 * sine(1, 3)"
cmd = "ramp(0.0, 0.5, 1)"

[network]
connect = [["s1.flange", "A1.a"], ["A1.b", "c1.a"], ["c1.b", "B1.a"],
           ["s2.flange", "A2.a"], ["A2.b", "c2.a"], ["c2.b", "B2.a"]]
""" + _shaft(1) + _shaft(2)


@pytest.mark.parametrize("kind", ["me", "cs"])
def test_fmu_twin_clutches_fire_their_events_together(tmp_path, kind):
    """Two identical shafts (a torque source, a model (6) clutch, a load): their clutches
    slip through zero at the same instants, and both events of each instant must fire.
    With one event per pass of the FMU's event iteration, the second was recorded as the
    indicator's new sign and lost: the twins ended 23.4 rad/s apart (ME and CS alike)."""
    path_toml = tmp_path / "twins.toml"
    path_toml.write_text(TWINS, encoding="utf-8")
    scenario = load_scenario(path_toml)
    fmu = tmp_path / "twins.fmu"
    export_fmu(scenario, fmu, "mykhailevych2020", kind=kind)
    run = simulate if kind == "me" else simulate_cs
    f = run(fmu, scenario, ["omega_B1", "omega_B2"], 1e-8, 0.001)
    scale = 1.0 + np.max(np.abs(f["omega_B1"]))
    assert np.max(np.abs(f["omega_B1"] - f["omega_B2"])) <= 1e-9 * scale
    native = run_scenario(scenario, "mykhailevych2020").result
    assert native["omega_B1"][-1] == pytest.approx(native["omega_B2"][-1], abs=0.0)
    assert f["omega_B1"][-1] == pytest.approx(native["omega_B1"][-1], rel=1e-2)
