"""FMU of the vehicle around the driveline (issue 39): ``examples/launch_tyre.toml``, a
launch on tyres with longitudinal slip (``tyre``) and a powertrain block on torsional mounts
(``torsional_mount``).  The printed C equals the compiled plant on random states (the
printer's own check), the FMU passes FMPy's compliance checks, and FMPy's run of it (CVode)
reproduces clutchsim's run in the 2e-3 tube with its energy balance below 1e-6."""

import shutil

import numpy as np
import pytest
from _dl_paths import EXAMPLES
from _fmu_tools import ENERGY, TUBE, c_plant_difference, energy_balance, simulate, tube

from clutchsim.fmu import export_fmu
from clutchsim.fmu.export import _plant_of
from clutchsim.scenario import load_scenario, run_scenario

pytest.importorskip("fmpy", reason="FMPy (the dev extra) runs the exported FMUs")
from fmpy.validation import validate_fmu

pytestmark = pytest.mark.skipif(shutil.which("cc") is None and shutil.which("gcc") is None,
                                reason="no C compiler on this machine")


@pytest.fixture(scope="module")
def launch(tmp_path_factory):
    sc = load_scenario(EXAMPLES / "launch_tyre.toml")
    path = tmp_path_factory.mktemp("launch_tyre") / "launch_tyre.fmu"
    info = export_fmu(sc, path, None)
    return sc, path, info


def test_tyre_and_mount_fmu_validates_and_prints_the_plant(launch):
    sc, path, info = launch
    assert validate_fmu(str(path)) == []
    assert info.path == path
    plan, _, system, _ = _plant_of(sc, None)
    assert {"tyres.kappa", "phi_mounts"} <= set(system.state_names)
    worst, _, _ = c_plant_difference(plan, system, k=30)
    assert worst <= 1e-12


@pytest.mark.slow
def test_tyre_and_mount_fmu_launches_as_clutchsim(launch):
    sc, path, _ = launch
    res = run_scenario(sc, None, overrides=["solver.dt_out=1e-3"]).result
    assert res.status == "completed"
    names = ["omega_engine", "omega_tyres", "omega_car", "tyres.kappa", "phi_mounts",
             "phi_driveshaft", "F_x_tyres", "T_mounts", "E_kinetic", "E_spring", *ENERGY]
    f = simulate(path, sc, names, 1e-8, 1e-3)
    assert f["time"][-1] == pytest.approx(sc.t_end)
    for name in names:
        assert tube(f, res, name) <= TUBE, name
    assert energy_balance(f) < 1e-6


@pytest.mark.slow
def test_fault_fmu_opens_the_clutch_as_clutchsim(tmp_path):
    """launch_tyre.toml with the clutch stuck open at 3 s (docs/components.md, faults): the
    fault is an event indicator of the FMU, and FMPy's run follows clutchsim's (the
    clutch breaks away at the fault, the engine flares) in the tube, its balance closed."""
    text = (EXAMPLES / "launch_tyre.toml").read_text(encoding="utf-8")
    old = '[[component]]\ntype = "clutch"\nname = "clutch"\n'
    src = tmp_path / "fault.toml"
    src.write_text(text.replace(old, old + "fault_time = 3.0\nfault_capacity_factor = 0.0\n"),
                   encoding="utf-8")
    sc = load_scenario(src)
    path = tmp_path / "fault.fmu"
    info = export_fmu(sc, path, None)
    assert validate_fmu(str(path)) == []
    assert "clutch: fault, stuck open (no torque) at 3 s" in info.event_indicators
    res = run_scenario(sc, None, overrides=["solver.dt_out=1e-3"]).result
    assert res.status == "completed"
    assert "clutch: fault, stuck open (no torque) at 3 s" in [e.name for e in res.events]
    after = res.t > 3.0 + 1e-9
    assert res["clutch.locked"][res.t < 3.0][-1] == 1.0
    assert np.all(res["clutch.locked"][after] == 0.0)
    assert np.all(res["T_friction_clutch"][after] == 0.0)
    assert res["omega_engine"][-1] > 1.2 * res["omega_engine"][~after][-1]
    names = ["omega_engine", "omega_car", "tyres.kappa", "E_kinetic", "E_spring", *ENERGY]
    f = simulate(path, sc, names, 1e-8, 1e-3)
    assert f["time"][-1] == pytest.approx(sc.t_end)
    for name in names:
        assert tube(f, res, name) <= TUBE, name
    assert energy_balance(f) < 1e-6


@pytest.mark.slow
def test_temperature_triggered_fault_fmu_strikes_as_clutchsim(tmp_path):
    """hill_start.toml with the clutch losing a tenth of its capacity when the pressure plate
    first exceeds 45 °C (a signal-triggered fault, docs/components.md, faults): the trigger
    is an event indicator of the FMU, whose bank copies only the clutch's values, and
    FMPy's run strikes it as clutchsim's does and follows it in the tube."""
    text = (EXAMPLES / "hill_start.toml").read_text(encoding="utf-8")
    old = 'name = "clutch"\ntype = "clutch"\n'
    src = tmp_path / "trig.toml"
    src.write_text(text.replace(old, old + "fault_temperature = 45.0\n"
                                "fault_capacity_factor = 0.9\n"), encoding="utf-8")
    sc = load_scenario(src)
    path = tmp_path / "trig.fmu"
    info = export_fmu(sc, path, None)
    assert validate_fmu(str(path)) == []
    name = "clutch: fault, capacity x 0.9 when pressure_plate first exceeds 45 °C"
    assert name in info.event_indicators
    res = run_scenario(sc, None, overrides=["solver.dt_out=1e-3"]).result
    assert res.status == "completed", res.message
    struck = [e.t for e in res.events if e.name == name]
    assert len(struck) == 1 and 0.0 < struck[0] < sc.t_end
    names = ["omega_engine", "omega_wheels", "theta_pressure_plate", "fault_clutch",
             "E_kinetic", "E_spring", *ENERGY]
    f = simulate(path, sc, names, 1e-8, 1e-3)
    assert f["time"][-1] == pytest.approx(sc.t_end)
    for n in names:
        assert tube(f, res, n) <= TUBE, n
    assert energy_balance(f) < 1e-6
