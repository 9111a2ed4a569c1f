"""FMUs of the issue-18 components: gear lash (``tip_in_clunk.toml``), the dual-mass
flywheel (``launch_dmf.toml``) and the torque converter with its lock-up clutch
(``converter_launch.toml``).  For each: the printed C equals the compiled plant on random
states (right-hand side, outputs, Jacobian, events, resets: the printer's own check), the
FMU passes FMPy's compliance checks, and FMPy's run of it (CVode; the converter also as
co-simulation with the FMU's own ROS2) reproduces clutchsim's run in the 2e-3 tube, with
its energy balance below 1e-6.  clutchsim's reference run is written every 0.1 ms, so that
the comparison does not measure the interpolation of a 1-2 ms grid across a clunk.

Signals that jump or ring at an event (the lash torque at a clunk, the friction ring's
torque, a reset ``clutch.phi``) are compared in the tube with a width in time of one
output interval (``tube_tv``): FMPy sets the inputs only at CVode's root-function calls
(docs/fmu.md), which moves events by 1e-5 to 1e-4 s after a throttle ramp."""

import shutil

import numpy as np
import pytest
from _dl_paths import EXAMPLES
from _fmu_tools import (
    ENERGY,
    SWITCH_TOL,
    TUBE,
    c_plant_difference,
    energy_balance,
    reset_times,
    simulate,
    simulate_cs,
    switches,
    tube,
    tube_tv,
)

from clutchsim.fmu import export_fmu
from clutchsim.fmu.export import _plant_of
from clutchsim.scenario import load_scenario, run_scenario

pytest.importorskip("fmpy", reason="FMPy (the dev extra) runs the exported FMUs")
from fmpy.validation import validate_fmu

pytestmark = pytest.mark.skipif(shutil.which("cc") is None and shutil.which("gcc") is None,
                                reason="no C compiler on this machine")

FINE = ["solver.dt_out=1e-4"]


def prepare(tmp_path_factory, example, model, kind="me"):
    """The scenario, its FMU (checked by FMPy's validation), clutchsim's run of it every
    0.1 ms, and the printed C's worst difference from the compiled plant."""
    sc = load_scenario(EXAMPLES / f"{example}.toml")
    path = tmp_path_factory.mktemp(example) / f"{example}.fmu"
    info = export_fmu(sc, path, model, kind=kind)
    assert validate_fmu(str(path)) == []
    res = run_scenario(sc, model, overrides=FINE).result
    assert res.status == "completed"
    plan, _, system, _ = _plant_of(sc, model)
    worst, _, checked_lock = c_plant_difference(plan, system, k=30)
    assert checked_lock
    return sc, path, info, res, worst


@pytest.fixture(scope="module")
def lash(tmp_path_factory):
    return prepare(tmp_path_factory, "tip_in_clunk", None)


@pytest.fixture(scope="module")
def dmf(tmp_path_factory):
    return prepare(tmp_path_factory, "launch_dmf", "mykhailevych2020")


@pytest.fixture(scope="module")
def converter(tmp_path_factory):
    return prepare(tmp_path_factory, "converter_launch", None, kind="both")


def test_printed_c_equals_compiled_plant(lash, dmf, converter):
    for _, _, info, _, worst in (lash, dmf, converter):
        assert worst <= 1e-12, info.path.name


@pytest.mark.slow
def test_lash_fmu_clunks_as_clutchsim(lash):
    """Tip-out and tip-in across the final-drive lash: the teeth leave and hit their flanks
    (8 gap-edge crossings each way) at clutchsim's times, the speeds and energies are in the
    tube, the lash torque and the fast carrier mode in the tube with a width in time."""
    sc, path, info, res, _ = lash
    assert {"lash: gap edge +b/2", "lash: gap edge -b/2"} <= set(info.event_indicators)
    smooth = ["omega_engine", "omega_disc", "omega_wheels", "phi_driveshaft", "E_kinetic",
              *ENERGY]
    jumpy = ["omega_carrier", "phi_lash", "T_lash", "T_driveshaft", "a_vehicle", "E_spring"]
    f = simulate(path, sc, [*smooth, *jumpy, "contact_lash"], 1e-8, 1e-3, record_events=True)
    assert f["time"][-1] == pytest.approx(sc.t_end)
    for name in smooth:
        assert tube(f, res, name) <= TUBE, name
    for name in jumpy:
        assert tube_tv(f, res, name, 1e-3) <= TUBE, name
    # the FMU's events (FMPy records two rows at each) but the inputs' breakpoints
    t = f["time"]
    bps = np.concatenate([np.ravel(s.breakpoints()) for s in sc.inputs.values()])
    edges = [x for x in t[1:][np.diff(t) == 0] if np.min(np.abs(bps - x)) > 1e-9]
    ours = [e.t for e in res.events if e.name.startswith("lash: gap edge")]
    assert len(ours) == 16 and len(edges) == len(ours), (edges, ours)
    assert np.max(np.abs(np.array(edges) - np.array(ours))) <= SWITCH_TOL
    # between two edges the teeth are in the gap (no torque) or on a flank
    mid = (np.array(ours[:-1]) + np.array(ours[1:])) / 2
    assert set(np.interp(mid, t, f["contact_lash"]).round()) == {-1.0, 0.0, 1.0}
    assert energy_balance(f) < 1e-6


@pytest.mark.slow
def test_dmf_fmu_launches_as_clutchsim(dmf):
    """The dual-mass flywheel's friction ring sticks and slips 32 times, in clutchsim's
    order.  The switches while the clutch locks (before 1.2 s) cross transversally and lie
    at clutchsim's times; the later breakaways are grazing (the stuck ring's torque creeps
    up to its 6 N·m capacity), so FMPy's input timing, 1e-4 of the speeds, moves them by up
    to 3.3 ms (4e-3 allowed).  The ring's slip and torque follow those times and are not
    compared; the speeds, the arc spring, the temperatures and the energies are in the
    tube."""
    sc, path, info, res, _ = dmf
    assert {"dmf: stop", "dmf: breakaway", "dmf: arc spring second stage",
            "dmf: end stop"} <= set(info.event_indicators)
    smooth = ["omega_engine", "omega_dmf_secondary", "omega_disc", "omega_wheels", "phi_dmf",
              "w_slip_clutch", "theta_flywheel", "theta_pressure_plate", "E_kinetic",
              "E_spring", *ENERGY]
    jumpy = ["clutch.phi", "T_spring_dmf"]
    f = simulate(path, sc, [*smooth, *jumpy, "dmf.mode", "dmf.locked"], 1e-7, 1e-3,
                 record_events=True)
    assert f["time"][-1] == pytest.approx(sc.t_end)
    for name in smooth:
        assert tube(f, res, name) <= TUBE, name
    for name in jumpy:
        assert tube_tv(f, res, name, 1e-3) <= TUBE, name
    ours = np.array(reset_times(res, "dmf"))
    theirs = switches(f, "dmf")
    names = [e.name for e in res.events if e.name.startswith("dmf:") and e.action == "reset"]
    assert len(ours) == len(theirs) == 32
    # the same order: each switch turns the lock flag over
    assert [bool(x) for x in np.interp(theirs + 1e-9, f["time"], f["dmf.locked"]) > 0.5] == [
        n == "dmf: stop" for n in names]
    early = ours < 1.2
    assert np.max(np.abs(theirs - ours)[early]) <= SWITCH_TOL
    assert np.max(np.abs(theirs - ours)) <= 4e-3
    assert energy_balance(f) < 1e-6


@pytest.mark.slow
def test_converter_fmu_launches_and_locks_as_clutchsim(converter):
    """Creep against the stalled converter, launch, the lock-up clutch slipping at 30 % and
    locking at 3.27 s: as Model Exchange (CVode) and as co-simulation (its own ROS2,
    0.5 ms communication steps: the inputs are held over a step; 1 ms puts the spring
    energy at 2.9e-3) from one ``--kind both`` file."""
    sc, path, info, res, _ = converter
    assert info.kind == "both"
    assert ["lockup: stop", "lockup: breakaway"] == [
        e for e in info.event_indicators if e.startswith("lockup")]
    smooth = ["omega_engine", "omega_turbine", "omega_wheels", "phi_driveshaft",
              "speed_ratio_converter", "w_slip_lockup", "E_kinetic", "E_spring", *ENERGY]
    jumpy = ["T_pump_converter", "T_turbine_converter", "T_lockup"]
    names = [*smooth, *jumpy, "lockup.mode", "lockup.locked"]
    f = simulate(path, sc, names, 1e-8, 1e-3, record_events=True)    # 1e-7: E_spring 2.9e-3
    g = simulate_cs(path, sc, names, 1e-8, 5e-4)
    for run, dt in ((f, 1e-3), (g, 5e-4)):
        assert run["time"][-1] == pytest.approx(sc.t_end)
        for name in smooth:
            assert tube(run, res, name) <= TUBE, (name, dt)
        for name in jumpy:
            assert tube_tv(run, res, name, dt) <= TUBE, name
        assert energy_balance(run) < 1e-6
    (lock,) = reset_times(res, "lockup")
    assert lock == pytest.approx(3.2704, abs=1e-3)
    assert np.abs(switches(f, "lockup") - lock).max() <= SWITCH_TOL
    # co-simulation: seen at the first communication point after it
    seen = g["time"][1:][np.diff(g["lockup.locked"]) != 0]
    assert len(seen) == 1 and lock - 1e-9 <= seen[0] <= lock + 5e-4 + SWITCH_TOL
