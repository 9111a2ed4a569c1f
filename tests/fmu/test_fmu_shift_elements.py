"""FMUs of the issue-38 elements: the cone clutch (``cone_synchroniser.toml``), the band
brake on an open differential (``band_brake_differential.toml``), the limited-slip
differential (``lsd_split_mu.toml``), the dog clutch
(``dog_clutch.toml``), its elastic teeth (``dog_backlash.toml``), the synchroniser
(``synchronizer.toml``) and the wet clutch (``wet_clutch_engagement.toml``).  For each:
the printed C
equals the compiled plant on random states (right-hand side, outputs, Jacobian, events,
resets), the FMU passes FMPy's compliance checks, and FMPy's run of it (CVode) follows
clutchsim's run in the 2e-3 tube, locks where clutchsim locks, and closes its energy
balance below 1e-6."""

import ctypes
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
    simulate,
    tube,
    tube_tv,
)

from clutchsim.fmu import export_fmu
from clutchsim.fmu.export import _plant_of, discrete_mask
from clutchsim.scenario import load_scenario, run_scenario

pytest.importorskip("fmpy", reason="FMPy (the dev extra) runs the exported FMUs")
from fmpy.validation import validate_fmu

pytestmark = pytest.mark.skipif(shutil.which("cc") is None and shutil.which("gcc") is None,
                                reason="no C compiler on this machine")

CASES = {
    # example: (the element, its events, the speeds compared, the outputs compared)
    "cone_synchroniser": ("cone", ("stop", "breakaway"),
                          ["omega_gear", "omega_shaft", "theta_ring"], ["capacity_cone"]),
    "band_brake_differential": ("band", ("stop", "breakaway"),
                                ["omega_prop", "omega_left", "omega_right"],
                                ["capacity_band", "T_diff_left", "T_diff_right"]),
    "dog_clutch": ("dog", ("engage", "release", "clash"), ["omega_input", "omega_output"],
                   ["dog.clashes"]),
    # the wet clutch: its drag (film shrinkage, mist, the oil's viscosity) and the piston
    "wet_clutch_engagement": ("pack", ("stop", "breakaway"),
                              ["omega_shaft", "omega_load", "theta_oil", "theta_plates",
                               "W_drag_pack"], ["capacity_pack", "W_drag_pack"]),
    "synchronizer": ("sync", ("stop", "release", "engage"), ["omega_gear", "omega_shaft"],
                     ["sync.engaged"]),
    # the limited-slip differential: the packs hold, then break away (split-mu launch)
    "lsd_split_mu": ("lsd", ("stop", "breakaway"), ["omega_left", "omega_right"],
                     ["capacity_lsd", "F_clamp_lsd", "T_lsd"]),
    # the elastic teeth: their mode is a discrete state the FMU keeps between events (CVode
    # once carried round-off into it and fired "engage" at every step, plant_core.c)
    "dog_backlash": ("dog", ("flank +backlash/2", "flank -backlash/2"),
                     ["omega_input", "omega_output"], ["contact_dog"]),
}


@pytest.mark.parametrize("example", sorted(CASES))
def test_fmu_of_the_shift_elements_runs_as_clutchsim(tmp_path, example):
    element, events, speeds, outputs = CASES[example]
    sc = load_scenario(EXAMPLES / f"{example}.toml")
    path = tmp_path / f"{example}.fmu"
    info = export_fmu(sc, path, None)
    assert validate_fmu(str(path)) == []
    assert {f"{element}: {e}" for e in events} <= set(info.event_indicators)
    plan, _, system, _ = _plant_of(sc, None)
    worst, _, checked_lock = c_plant_difference(plan, system, k=30)
    assert worst <= 1e-12 and checked_lock
    res = run_scenario(sc, None).result
    assert res.status == "completed"
    # (elastic dog teeth are never locked: no lock state)
    lock = [f"{element}.locked"] if f"{element}.locked" in res.signals else []
    names = [*speeds, *outputs, "E_kinetic", "E_spring", *ENERGY, *lock]
    # 0.1 ms: FMPy sets the inputs only where CVode calls its root functions, and a coarser
    # input table stalls CVode on the force ramps (mxstep before 0.5 ms at 1 ms)
    f = simulate(path, sc, names, 1e-8, 1e-4, record_events=True)
    assert f["time"][-1] == pytest.approx(sc.t_end)
    # no event storm: FMPy stops where clutchsim switches, and at the scripted inputs' jumps
    # (at most one beside each switch here); the elastic dog once stopped 2e6 times at 5 ms
    assert int(np.sum(np.diff(f["time"]) == 0)) <= 2 * len(res.events) + 2
    # (the dog's engagement is a jump of the speeds: compared with a width in time of one
    # output interval of clutchsim's run)
    for name in [*speeds, *ENERGY]:
        assert tube_tv(f, res, name, 1e-3) <= TUBE, name
        if example not in ("dog_clutch", "synchronizer"):
            assert tube(f, res, name) <= TUBE, name
    # the counters and capacities at the end
    for name in outputs:
        assert f[name][-1] == pytest.approx(res[name][-1], rel=TUBE, abs=1e-9), name
    # the element locks (or breaks away) where clutchsim's does (after t0: the FMU settles
    # the band, at rest with no force, in its initialisation)
    t = f["time"]
    if not lock:
        assert energy_balance(f) < 1e-6
        return
    theirs = t[1:][(np.diff(f[f"{element}.locked"]) != 0) & (np.diff(t) == 0)]
    locks = {f"{element}: {e}" for e in ("stop", "breakaway", "engage", "release")}
    ours = [e.t for e in res.events if e.name in locks and e.t > 0.0]
    assert len(theirs) == len(ours)
    assert np.max(np.abs(np.array(theirs) - np.array(ours)), initial=0.0) <= SWITCH_TOL
    assert energy_balance(f) < 1e-6


def test_the_fmu_keeps_its_discrete_states_between_events(tmp_path):
    """The switching states (modes, lock flags, counters) are the FMU's discrete states:
    ``fmi2SetContinuousStates`` leaves them as the last event left them (an importer's
    integrator moves them only by round-off), the continuous ones it takes."""
    sc = load_scenario(EXAMPLES / "dog_backlash.toml")
    plan, comps, system, _ = _plant_of(sc, None)
    mask = discrete_mask(plan, comps)
    assert {n for n, d in zip(system.state_names, mask) if d} == {"dog.mode", "dog.clashes"}
    sc = load_scenario(EXAMPLES / "synchronizer.toml")
    plan, comps, system, _ = _plant_of(sc, None)
    assert {n for n, d in zip(system.state_names, discrete_mask(plan, comps)) if d} == {
        "sync.mode", "sync.engaged", "sync.locked"}
    # the dog's FMU in continuous-time mode: a round-off in its mode is not taken
    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Model
    path = tmp_path / "dog_backlash.fmu"
    export_fmu(load_scenario(EXAMPLES / "dog_backlash.toml"), path, None)
    md = read_model_description(str(path))
    fmu = FMU2Model(guid=md.guid, unzipDirectory=extract(str(path)),
                    modelIdentifier=md.modelExchange.modelIdentifier, instanceName="dog")
    fmu.instantiate()
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    fmu.newDiscreteStates()
    fmu.enterContinuousTimeMode()
    names = [d.variable.derivative.name for d in md.derivatives]
    n = len(names)
    x = np.zeros(n)
    fmu.getContinuousStates(x.ctypes.data_as(ctypes.POINTER(ctypes.c_double)), n)
    i_mode, i_phi = names.index("dog.mode"), names.index("phi_dog")
    assert x[i_mode] == 0.0
    x[i_mode], x[i_phi] = 1e-51, x[i_phi] + 1e-3
    fmu.setContinuousStates(x.ctypes.data_as(ctypes.POINTER(ctypes.c_double)), n)
    y = np.zeros(n)
    fmu.getContinuousStates(y.ctypes.data_as(ctypes.POINTER(ctypes.c_double)), n)
    assert y[i_mode] == 0.0 and y[i_phi] == x[i_phi]
    fmu.terminate()
    fmu.freeInstance()


def test_fmu_of_the_double_sided_synchroniser_shifts_as_clutchsim(tmp_path):
    """examples/amt_upshift_sleeve.toml (one sleeve force, sides +1 and -1): the printed C
    equals the compiled plant, FMPy validates the FMU, and its run releases first gear and
    engages second where clutchsim does."""
    sc = load_scenario(EXAMPLES / "amt_upshift_sleeve.toml")
    path = tmp_path / "amt_upshift_sleeve.fmu"
    export_fmu(sc, path, None)
    assert validate_fmu(str(path)) == []
    plan, _, system, _ = _plant_of(sc, None)
    worst, _, checked_lock = c_plant_difference(plan, system, k=30)
    assert worst <= 1e-12 and checked_lock
    res = run_scenario(sc, None).result
    f = simulate(path, sc, ["omega_output", "sync1.locked", "sync2.locked", "sync1.mode",
                            "sync2.mode", "sync2.engaged"], 1e-8, 1e-4, record_events=True)
    assert f["time"][-1] == pytest.approx(sc.t_end)
    t = f["time"]
    for side, name in (("sync1", "release"), ("sync2", "engage")):
        theirs = t[1:][(np.diff(f[f"{side}.locked"]) != 0) & (np.diff(t) == 0)]
        [ours] = [e.t for e in res.events if e.name == f"{side}: {name}"]
        assert np.min(np.abs(theirs - ours)) <= SWITCH_TOL, (side, theirs, ours)
    assert f["sync2.engaged"][-1] == 1.0
    assert tube_tv(f, res, "omega_output", 1e-3) <= TUBE


def test_fmu_of_a_gearbox_with_synchronizers_is_its_expanded_plant(tmp_path):
    """examples/amt_upshift_gearbox.toml (a `gearbox` with a `synchronizer` table, expanded
    into pinions, idlers and synchronisers, its sleeve forces generated): FMPy validates the
    FMU, the generated sleeve forces are its inputs and each synchroniser's events its event
    indicators.  (The printed C of synchronisers against the compiled plant is checked on
    amt_upshift_sleeve.toml above: the expansion writes the same components.)"""
    sc = load_scenario(EXAMPLES / "amt_upshift_gearbox.toml")
    path = tmp_path / "amt_upshift_gearbox.fmu"
    info = export_fmu(sc, path, None)
    assert validate_fmu(str(path)) == []
    assert {"gearbox_sleeve1", "gearbox_sleeve2"} <= set(info.inputs)
    assert {f"gearbox_sync{k}: {e}" for k in (1, 2) for e in ("stop", "release", "engage")} \
        <= set(info.event_indicators)
