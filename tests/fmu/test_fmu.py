"""The exported FMU, run by an independent importer (FMPy): it passes FMPy's compliance
checks, completes with CVode (Model Exchange, FMI 2 and FMI 3) or with its own ROS2 solver
(co-simulation) and reproduces clutchsim's own run of the scenario inside the 2e-3 tube
(max |FMU - clutchsim| / max(|clutchsim|, 1) on the FMU's output grid), switching at
clutchsim's times, with an energy balance of its own run below 1e-6; ``clutchsim fmu``
refuses what it cannot export with exit status 2 and writes nothing."""

import json
import shutil
import zipfile

import numpy as np
import pandas as pd
import pytest
from _dl_paths import EXAMPLES, shared_dir
from _fmu_tools import (
    ENERGY,
    SWITCH_TOL,
    TUBE,
    assert_same_switches,
    energy_balance,
    simulate,
    simulate_cs,
    simulate_cs_slopes,
    switches,
    tube,
    tube_tv,
)

from clutchsim.cli import main
from clutchsim.fmu import export_fmu, input_table
from clutchsim.scenario import load_scenario, run_scenario

fmpy = pytest.importorskip("fmpy", reason="FMPy (the dev extra) runs the exported FMUs")
from fmpy.validation import validate_fmu

pytestmark = pytest.mark.skipif(shutil.which("cc") is None and shutil.which("gcc") is None,
                                reason="no C compiler on this machine")


@pytest.mark.slow
@pytest.mark.parametrize("fmi", ["2", "3"])
def test_default_launch_fmu_reproduces_clutchsim(tmp_path, fmi):
    scenario = EXAMPLES / "launch.toml"
    path = tmp_path / "launch.fmu"
    info = export_fmu(scenario, path, "mykhailevych2020", fmi=fmi)
    assert validate_fmu(str(path)) == []
    md = fmpy.read_model_description(str(path))
    assert md.fmiVersion == f"{fmi}.0" and md.modelExchange is not None
    assert md.coSimulation is None
    with zipfile.ZipFile(path) as zf:
        names = set(zf.namelist())
    assert info.platform == ("linux64" if fmi == "2" else "x86_64-linux")
    assert f"binaries/{info.platform}/{info.model_identifier}.so" in names
    assert {"modelDescription.xml", "sources/plant.c", f"sources/fmi{fmi}_me.c",
            "sources/plant_core.c"} <= names
    # variables: clutchsim's names, units, start values
    by = {v.name: v for v in md.modelVariables}
    assert by["throttle"].causality == "input" and float(by["throttle"].start) == 0.1
    assert float(by["clutch_command"].start) == 0.0
    assert by["omega_engine"].unit == "rad/s" and float(by["omega_engine"].start) == 83.78
    assert by["T_clutch"].causality == "output" and by["T_clutch"].unit == "N·m"
    assert by["theta_pressure_plate"].unit == "°C"
    assert by["clutch.friction.T_stat"].variability == "tunable"
    assert by["engine.J"].variability == "constant"      # structural: in M⁻¹
    # model (6) has one set of equations: its only clutch indicator is the zero crossing
    # of the slip, where its reset policy (clamp) re-initialises phi; the other is the
    # engine's stall
    assert md.numberOfEventIndicators == 2
    assert [e for e in info.event_indicators if e.startswith("clutch")] == [
        "clutch: velocity_zero_crossing"]

    r = run_scenario(scenario, "mykhailevych2020")
    res = r.result
    assert res.status == "completed"
    out = ["omega_engine", "omega_disc", "omega_gearbox_input", "omega_wheels", "w_slip_clutch",
           "T_clutch", "theta_pressure_plate", "theta_flywheel", "E_kinetic", "E_spring",
           *ENERGY]
    f = simulate(path, scenario, out, 1e-7, 2e-3)
    assert f["time"][-1] == pytest.approx(4.0)
    for name in out:
        if name != "T_clutch":
            assert tube(f, res, name) <= TUBE, name
    # the clutch torque jumps where the reset re-initialises phi and rings after lock-up
    # (~400 Hz): the tube is given a width of one output interval in time as well
    assert tube_tv(f, res, "T_clutch", 2e-3) <= TUBE
    assert energy_balance(f) < 1e-6
    # lock-up reached in the FMU run as in clutchsim's
    assert abs(f["w_slip_clutch"][-1]) < 1e-2
    # issue 41, item 4: at rtol 1e-6 as well, with the inputs set at every right-hand side
    # (FMPy sets them after each of CVode's steps only, a lag of one step: its speeds and
    # energies are then 3.4e-3 out in the ramps, the torque 1.5e-3; docs/fmu.md)
    f = simulate(path, scenario, out, 1e-6, 2e-3, inputs_in_rhs=True)
    assert f["time"][-1] == pytest.approx(4.0)
    for name in out:
        if name != "T_clutch":
            assert tube(f, res, name) <= TUBE, name
    assert tube_tv(f, res, "T_clutch", 2e-3) <= TUBE
    assert energy_balance(f) < 1e-5            # CVode's own error at 1e-6: 1.2e-6
    if fmi == "2":
        f = simulate(path, scenario, ["T_clutch"], 1e-6, 2e-3)
        assert tube_tv(f, res, "T_clutch", 2e-3) <= TUBE


#: model (6) with the event-free reset policy (the stop operator)
STOP = ["coupling[0].friction.overrides.reset='stop'"]


@pytest.mark.slow
def test_launch_fmu_of_model_6_with_the_stop_operator_has_no_clutch_indicator(tmp_path):
    """Issue 22: with the reset policy ``stop`` model (6) needs no event, so the FMU's only
    event indicator is the engine's stall.  It completes under FMPy's CVode (Model
    Exchange) and as co-simulation, with an energy balance below 1e-6, locks up, and stays
    in the 2e-3 tube of clutchsim's own run of the same scenario (sampled every 0.25 ms:
    the locked contact rings at ~330 Hz).  Without an event at lock-up CVode meets the
    tube from rtol 2e-8 (T_clutch: 4.9e-4; at 1e-7 3.2e-3 of its range, clamp 3.7e-4).
    In co-simulation the held inputs shift the lock-up, and the clutch torque's ringing
    in the 0.1 s after it differs by 2.7e-3 of its range (clamp: 2.6e-4); the speeds,
    energies and the torque elsewhere lie in the tube.  The policy is an option, not a
    tunable: it decides the indicators."""
    scenario = EXAMPLES / "launch.toml"
    path = tmp_path / "stop.fmu"
    info = export_fmu(scenario, path, "mykhailevych2020", kind="both", overrides=STOP)
    assert validate_fmu(str(path)) == []
    md = fmpy.read_model_description(str(path))
    assert md.numberOfEventIndicators == 1
    assert [e for e in info.event_indicators if e.startswith("clutch")] == []
    assert info.event_indicators[0].startswith("engine stalled")
    by = {v.name: v for v in md.modelVariables}
    assert by["clutch.friction.reset"].variability == "constant"
    assert float(by["clutch.friction.reset"].start) == 5.0        # RESET_POLICIES["stop"]
    assert by["clutch.friction.T_stat"].variability == "tunable"
    run = run_scenario(scenario, "mykhailevych2020", overrides=[*STOP, "solver.dt_out=2.5e-4"])
    res, t_lock = run.result, run.metrics["lockup_time_s"]
    assert res.status == "completed" and res.stats.events == 0
    smooth = ["omega_engine", "omega_disc", "omega_wheels", "w_slip_clutch", "E_kinetic",
              "E_spring", "theta_pressure_plate", *ENERGY]
    me = simulate(path, scenario, [*smooth, "T_clutch"], 2e-8, 2e-3)
    cs = simulate_cs(path, scenario, [*smooth, "T_clutch"], 1e-8, 2.5e-4)
    for f in (me, cs):
        assert f["time"][-1] == pytest.approx(4.0)
        for name in smooth:
            assert tube(f, res, name) <= TUBE, name
        assert energy_balance(f) < 1e-6
        assert abs(f["w_slip_clutch"][-1]) < 1e-2
    assert tube_tv(me, res, "T_clutch", 2e-3) <= TUBE
    ringing = (cs["time"] > t_lock) & (cs["time"] < t_lock + 0.1)
    assert tube_tv({k: cs[k][~ringing] for k in ("time", "T_clutch")}, res, "T_clutch",
                   1e-3) <= TUBE
    assert tube_tv({k: cs[k][ringing] for k in ("time", "T_clutch")}, res, "T_clutch",
                   1e-3) <= 1.5 * TUBE


def run_cli(capsys, *argv):
    code = main(list(argv))
    cap = capsys.readouterr()
    return code, cap.out, cap.err


def test_cli_writes_fmu_and_one_json_document(tmp_path, capsys):
    out = tmp_path / "sub" / "launch.fmu"
    code, stdout, err = run_cli(capsys, "fmu", str(EXAMPLES / "launch.toml"), "--model",
                                "mykhailevych2020", "--out", str(out), "--json")
    assert code == 0, err
    doc = json.loads(stdout)
    assert doc["path"] == str(out) and out.is_file()
    assert doc["fmi"] == "2.0" and doc["kind"] == "me" and doc["model"] == "mykhailevych2020"
    assert "omega_engine" in doc["states"] and "T_clutch" in doc["outputs"]
    assert doc["inputs"] == ["clutch_command", "throttle"]
    assert sorted(p.name for p in out.parent.iterdir()) == ["launch.fmu"]   # no leftovers


@pytest.mark.parametrize(("args", "message"), [
    (["--fmi", "4"], r"--fmi 4: this version writes FMI 2\.0, 3\.0 only"),
    (["--kind", "xy"], r"--kind xy: one of me, cs, both"),
    (["--model", "no-such-model"], r"no-such-model"),
])
def test_cli_refuses_bad_options(tmp_path, capsys, args, message):
    out = tmp_path / "x.fmu"
    code, stdout, err = run_cli(capsys, "fmu", str(EXAMPLES / "launch.toml"), *args,
                                "--out", str(out))
    assert code == 2, err
    assert stdout == ""
    assert pytest.importorskip("re").search(message, err), err
    assert "Traceback" not in err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.slow
@pytest.mark.parametrize(("example", "model", "element", "speeds", "dt_out"), [
    ("one_way_clutch", None, "oneWayClutch", ["omega_inertiaIn", "omega_inertiaOut"], 2.5e-4),
    ("lossy_gear_demo1", None, "gear", ["omega_Inertia1", "omega_Inertia2"], 1e-3),
    ("shift_1_2", "mykhailevych2020", "gearbox", ["omega_engine", "omega_wheels"], 1e-3),
])
def test_freewheel_lossy_gear_and_shift_fmus_switch_as_clutchsim(tmp_path, example, model,
                                                                   element, speeds, dt_out):
    """The other switching laws export too: a one-way clutch (Modelica OneWayClutch), a
    lossy gear that sticks (LossyGearDemo1) and a gearbox with losses that shifts (its
    bank of values switched at the shift's event): the FMU switches at clutchsim's times
    and its speeds lie in clutchsim's tube.  FMPy sets the inputs only at its root-function
    calls (docs/fmu.md): the one-way clutch's 3 Hz drive needs 0.25 ms output steps for
    that to stay inside the tube (1 ms: 2.07e-3 of the range).  Like Modelica's reference,
    the FMU under CVode locks the freewheel for 0.7 ms at 1.4993 s, where its slip only
    touches zero in clutchsim's run (the near-tangent case of docs/validation-modelica.md):
    that window is left out of the switch comparison.  In the shift the clutch disc rings
    at its contact mode after each engagement (model (6)), which a 1 ms grid samples out of
    phase: the disc speed is left out there, the synchroniser's W_sync is compared."""
    scenario = EXAMPLES / f"{example}.toml"
    skip = ((1.499, 1.5005),) if example == "one_way_clutch" else ()
    jumpy = ["W_sync", "ratio_gearbox"] if example == "shift_1_2" else []
    info, f, res = run_and_compare(tmp_path, scenario, model, 1e-8, dt_out,
                                   [*speeds, "E_kinetic", "W_friction"], jumpy, (element,),
                                   skip=skip)
    assert f"{element}: stop" in info.event_indicators
    if example == "shift_1_2":
        assert any("shift to gear 2" in e for e in info.event_indicators)
        w = np.interp(res.t, f["time"], f["omega_wheels"])
        assert np.max(np.abs(w - res["omega_wheels"])) <= TUBE * np.max(res["omega_wheels"])


def test_cli_without_c_compiler_says_what_it_looked_for(tmp_path, capsys, monkeypatch):
    monkeypatch.delenv("CC", raising=False)
    monkeypatch.setenv("PATH", str(tmp_path / "empty"))
    out = tmp_path / "launch.fmu"
    code, _, err = run_cli(capsys, "fmu", str(EXAMPLES / "launch.toml"), "--out", str(out))
    assert code == 2, err
    assert "no C compiler found" in err and "gcc" in err
    assert "apt-get install gcc" in err
    assert not out.exists()


def test_cli_with_a_cc_that_does_not_exist_refuses_rather_than_use_another(tmp_path, capsys,
                                                                           monkeypatch):
    """CC=/nonexistent/cc used to fall back silently to the cc on the PATH."""
    monkeypatch.setenv("CC", "/nonexistent/cc")
    out = tmp_path / "launch.fmu"
    code, _, err = run_cli(capsys, "fmu", str(EXAMPLES / "launch.toml"), "--out", str(out))
    assert code == 2, err
    assert "CC='/nonexistent/cc' is not an executable compiler" in err and "unset it" in err
    assert not out.exists()


def run_and_compare(tmp_path, scenario, model, rtol, dt_out, smooth, jumpy, elements,
                    fmi="2", skip=()):
    path = tmp_path / f"{model or 'plant'}.fmu"
    info = export_fmu(scenario, path, model, fmi=fmi)
    assert validate_fmu(str(path)) == []
    r = run_scenario(scenario, model)
    res = r.result
    assert res.status == "completed"
    f = simulate(path, scenario, [*smooth, *jumpy, *(f"{e}.{s}" for e in elements
                                                   for s in ("mode", "locked"))],
                 rtol, dt_out, record_events=True)
    assert f["time"][-1] == pytest.approx(sc_end(scenario))
    for name in smooth:
        assert tube(f, res, name) <= TUBE, name
    for name in jumpy:      # torques jump at the switches: a width in time of one interval
        assert tube_tv(f, res, name, dt_out) <= TUBE, name
    assert_same_switches(f, res, elements, skip=skip)
    return info, f, res


def sc_end(scenario):
    from clutchsim.scenario import load_scenario
    return load_scenario(scenario).t_end


@pytest.mark.slow
@pytest.mark.parametrize("fmi", ["2", "3"])
def test_coupled_clutches_fmu_switches_as_clutchsim_and_modelica(tmp_path, fmi):
    """Modelica's CoupledClutches (coulomb-robust: stick/slip with event iteration): three
    clutches, six event indicators; the FMU switches at clutchsim's times and its speeds lie
    in the tube of clutchsim's run and of the MSL reference."""
    scenario = EXAMPLES / "coupled_clutches.toml"
    clutches = ("clutch1", "clutch2", "clutch3")
    smooth = ["omega_J1", "omega_J2", "omega_J3", "omega_J4", "E_kinetic", "W_friction",
              *(f"w_slip_{c}" for c in clutches)]
    info, f, _ = run_and_compare(tmp_path, scenario, "coulomb-robust", 1e-8, 5e-4, smooth,
                                 [f"T_{c}" for c in clutches], clutches, fmi)
    assert info.event_indicators[:6] == tuple(f"{c}: {e}" for c in clutches
                                              for e in ("stop", "breakaway"))
    ref_path = shared_dir() / "reference" / "modelica" / "Modelica" / "Mechanics" / \
        "Rotational" / "Examples" / "CoupledClutches" / "CoupledClutches.csv"
    if not ref_path.exists():
        pytest.skip(f"Modelica reference results not found at {ref_path} "
                    "(set CLUTCHSIM_SHARED to the shared folder)")
    ref = pd.read_csv(ref_path).drop_duplicates("time", keep="last")
    w = ref["J1.w"].to_numpy()
    speeds = [w]
    for c in clutches:
        w = w + ref[f"{c}.w_rel"].to_numpy()
        speeds.append(w)
    for k, w_ref in enumerate(speeds):
        ours = np.interp(ref["time"], f["time"], f[f"omega_J{k + 1}"])
        assert np.max(np.abs(ours - w_ref)) / max(np.max(np.abs(w_ref)), 1.0) <= TUBE, k


@pytest.mark.slow
def test_launch_fmu_with_coulomb_robust_locks_as_clutchsim(tmp_path):
    smooth = ["omega_engine", "omega_disc", "omega_wheels", "w_slip_clutch",
              "theta_pressure_plate", "E_kinetic", "E_spring", *ENERGY]
    info, f, _ = run_and_compare(tmp_path, EXAMPLES / "launch.toml", "coulomb-robust", 1e-7,
                                 2e-3, smooth, ["T_clutch"], ("clutch",))
    assert [e for e in info.event_indicators if e.startswith("clutch")] == [
        "clutch: stop", "clutch: breakaway"]
    assert energy_balance(f) < 1e-6


@pytest.mark.slow
def test_simple_gear_shift_fmu_matches_modelica(tmp_path):
    """Modelica's SimpleGearShift (a planetary set shifted by a clutch and a brake): the
    FMU switches at the MSL reference's times (brake breakaway 2.04082 s, clutch stop
    2.11079 s) and its speeds lie in the tube of the reference result."""
    scenario = EXAMPLES / "simple_gear_shift.toml"
    _, f, _ = run_and_compare(tmp_path, scenario, "coulomb-robust", 1e-8, 1e-3,
                              ["omega_engine", "omega_load", "w_slip_clutch", "E_kinetic",
                               "W_friction"], [], ("clutch", "brake"))
    assert abs(switches(f, "brake")[-1] - 2.04082) <= SWITCH_TOL
    assert abs(switches(f, "clutch")[-1] - 2.11079) <= SWITCH_TOL
    ref_path = shared_dir() / "reference" / "modelica" / "Modelica" / "Mechanics" / \
        "Rotational" / "Examples" / "SimpleGearShift" / "SimpleGearShift.csv"
    if not ref_path.exists():
        pytest.skip(f"Modelica reference results not found at {ref_path} "
                    "(set CLUTCHSIM_SHARED to the shared folder)")
    ref = pd.read_csv(ref_path).drop_duplicates("time", keep="last")
    for ours, theirs in (("omega_engine", "engine.w"), ("omega_load", "load.w")):
        w = np.interp(ref["time"], f["time"], f[ours])
        r = ref[theirs].to_numpy()
        assert np.max(np.abs(w - r)) / max(np.max(np.abs(r)), 1.0) <= TUBE, ours


@pytest.mark.slow
def test_cosimulation_fmu_at_2_ms_follows_the_native_run_within_1e_3(tmp_path):
    """Issue 41: the FMI 2 co-simulation FMU of the default launch at a 2 ms communication
    step within 1e-3 of the native run.  It can interpolate its inputs
    (``canInterpolateInputs``): given each step's input slopes
    (``fmi2SetRealInputDerivatives``) it follows the commands' ramps within the step as
    the native run does, and its speeds stay within 3e-5 of their range (T_clutch 2.7e-3
    in value, 6e-5 within 2 ms in time, where the locked contact rings).  Held inputs, as
    FMPy's simulate_fmu gives them, lag each ramp by half a step: 1.1e-3 to 1.4e-3 on the
    speeds, 3e-2 on T_clutch.  Bad derivatives are refused: an order above 1, a value
    reference that is not an input."""
    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Slave
    scenario = EXAMPLES / "launch.toml"
    path = tmp_path / "cs.fmu"
    export_fmu(scenario, path, "mykhailevych2020", kind="cs")
    assert validate_fmu(str(path)) == []
    md = fmpy.read_model_description(str(path))
    assert md.coSimulation.canInterpolateInputs
    res = run_scenario(scenario, "mykhailevych2020").result
    speeds = ["omega_engine", "omega_disc", "omega_wheels"]
    f = simulate_cs_slopes(path, scenario, [*speeds, "T_clutch"], 1e-6, 2e-3)
    assert f["time"][-1] == pytest.approx(4.0)
    for name in speeds:
        assert tube(f, res, name) <= 1e-4, name
    assert tube_tv(f, res, "T_clutch", 2e-3) <= 1e-3
    held = simulate_cs(path, scenario, speeds, 1e-6, 2e-3)
    assert max(tube(held, res, n) for n in speeds) > 1e-3      # why the slopes matter
    md = read_model_description(str(path))
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=extract(str(path)),
                    modelIdentifier=md.coSimulation.modelIdentifier, instanceName="bad")
    fmu.instantiate()
    u = next(v.valueReference for v in md.modelVariables if v.causality == "input")
    y = next(v.valueReference for v in md.modelVariables if v.causality == "output")
    for vrs, order in (([u], [2]), ([y], [1])):
        with pytest.raises(Exception, match="fmi2SetRealInputDerivatives"):
            fmu.setRealInputDerivatives(vrs, order, [1.0])
    fmu.freeInstance()


@pytest.mark.slow
@pytest.mark.parametrize("fmi", ["2", "3"])
def test_cosimulation_fmu_with_its_own_rosenbrock_solver(tmp_path, fmi):
    """--kind both: the same FMU for Model Exchange and for co-simulation, where its own
    ROS2 solver (exact Jacobian, events located by bisection) integrates each
    communication step; in FMI 3 without event mode (the FMU handles its events inside
    fmi3DoStep, as in FMI 2).  FMPy holds the inputs over a communication step (0.25 ms
    here; with 0.5 ms the damper's stored energy is off by 2.4e-3 of its range, with 1 ms
    the slip by 2.3e-3; the solver's tolerance changes neither)."""
    scenario = EXAMPLES / "launch.toml"
    path = tmp_path / "launch.fmu"
    info = export_fmu(scenario, path, "mykhailevych2020", fmi=fmi, kind="both")
    assert info.kind == "both" and validate_fmu(str(path)) == []
    md = fmpy.read_model_description(str(path))
    assert md.fmiVersion == f"{fmi}.0"
    assert md.modelExchange is not None and md.coSimulation is not None
    with zipfile.ZipFile(path) as zf:
        assert f"sources/fmi{fmi}_me.c" in zf.namelist() and "sources/rosenbrock.c" in \
            zf.namelist()
        if fmi == "3":
            assert b'hasEventMode="false"' in zf.read("modelDescription.xml")
    res = run_scenario(scenario, "mykhailevych2020").result
    smooth = ["omega_engine", "omega_disc", "omega_wheels", "w_slip_clutch", "E_kinetic",
              "E_spring", "theta_pressure_plate", *ENERGY]
    f = simulate_cs(path, scenario, [*smooth, "T_clutch"], 1e-8, 2.5e-4)
    assert f["time"][-1] == pytest.approx(4.0)
    for name in smooth:
        assert tube(f, res, name) <= TUBE, name
    assert tube_tv(f, res, "T_clutch", 1e-3) <= TUBE
    assert energy_balance(f) < 1e-6
    # the same FMU as Model Exchange
    g = simulate(path, scenario, ["omega_disc"], 1e-7, 2e-3)
    assert tube(g, res, "omega_disc") <= TUBE


@pytest.mark.slow
def test_cosimulation_coupled_clutches_switches_within_a_step(tmp_path):
    scenario = EXAMPLES / "coupled_clutches.toml"
    clutches = ("clutch1", "clutch2", "clutch3")
    path = tmp_path / "cc.fmu"
    export_fmu(scenario, path, "coulomb-robust", kind="cs")
    assert validate_fmu(str(path)) == []
    res = run_scenario(scenario, "coulomb-robust").result
    smooth = ["omega_J1", "omega_J2", "omega_J3", "omega_J4", "E_kinetic", "W_friction",
              *(f"w_slip_{c}" for c in clutches)]
    dt = 2.5e-4
    f = simulate_cs(path, scenario, [*smooth, *(f"{c}.{s}" for c in clutches
                                                for s in ("mode", "locked"))], 1e-8, dt)
    for name in smooth:
        assert tube(f, res, name) <= TUBE, name
    for c in clutches:       # each switch seen at the first communication point after it
        ours = [e.t for e in res.events if e.name.startswith(f"{c}:") and e.action == "reset"]
        moved = (np.diff(f[f"{c}.locked"]) != 0) | (np.diff(f[f"{c}.mode"]) != 0)
        seen = f["time"][1:][moved]
        assert len(seen) == len(ours), (c, seen, ours)
        assert np.all((seen >= np.array(ours) - 1e-9) & (seen <= np.array(ours) + dt + SWITCH_TOL)), c


@pytest.mark.slow
@pytest.mark.parametrize("fmi", ["2", "3"])
def test_stall_ends_the_fmu_run_where_the_engine_speed_falls_below_its_stall_speed(tmp_path,
                                                                                 fmi):
    """The clutch dumped at 5 % throttle stalls the engine: the FMU's stall indicator ends
    the run with an error status, as Model Exchange (fmi2NewDiscreteStates /
    fmi3UpdateDiscreteStates) where the engine speed reaches the stall speed on clutchsim's
    own trajectory, and as co-simulation (fmi2DoStep / fmi3DoStep, FMI 3 with
    terminateSimulation) within a communication step of that time."""
    sc = load_scenario(EXAMPLES / "launch.toml", overrides=[
        "inputs.throttle=0.05", "inputs.clutch_command=ramp(0.2, 0.05, 1.0)",
        "scenario.expect_lockup=false", "scenario.t_end=0.5", "solver.dt_out=1e-4"])
    path = tmp_path / "stall.fmu"
    info = export_fmu(sc, path, "mykhailevych2020", fmi=fmi, kind="both")
    stall = next(e for e in info.event_indicators if e.startswith("engine stalled"))
    res = run_scenario(sc, "mykhailevych2020").result
    w = res["omega_engine"]
    i = int(np.argmax(w < 41.89))             # the first sample below the stall speed
    t_stall = float(np.interp(41.89, [w[i], w[i - 1]], [res.t[i], res.t[i - 1]]))
    assert 0.25 < t_stall < 0.3
    dt = 5e-4
    for typ in ("ModelExchange", "CoSimulation"):
        rec = {}

        def keep(t, recorder, rec=rec):
            rec["r"] = recorder
            return True
        with pytest.raises(fmpy.fmi1.FMICallException, match="status 3"):
            fmpy.simulate_fmu(str(path), fmi_type=typ, relative_tolerance=1e-7,
                              output_interval=dt, output=["omega_engine"], record_events=True,
                              step_finished=keep, input=input_table(sc, dt=dt / 2,
                                                                    names=list(info.inputs)))
        f = rec["r"].result()
        if typ == "ModelExchange":          # stopped at the located event
            assert f["time"][-1] == pytest.approx(t_stall, abs=SWITCH_TOL), stall
            assert f["omega_engine"][-1] == pytest.approx(41.89, abs=1e-6)
        else:       # the step that fails holds the stall; the inputs, held over each
            # step, move it by less than a step (0.286730 s here)
            assert t_stall - dt <= f["time"][-1] < t_stall + dt


def test_a_value_the_equations_read_only_through_a_derived_one_is_a_constant(tmp_path):
    """The vehicle's grade feeds its grade force ``f_grade`` when the plant is built; the
    equations read ``f_grade``.  A tunable ``vehicle.grade`` set in an importer would change
    nothing: it is a constant that says which value to set instead."""
    path = tmp_path / "launch.fmu"
    info = export_fmu(EXAMPLES / "launch.toml", path, "mykhailevych2020")
    for name in ("vehicle.grade", "vehicle.rolling", "vehicle.cd_area"):
        assert name in info.constants and name not in info.parameters
    for name in ("vehicle.f_grade", "vehicle.roll", "vehicle.c_aero", "vehicle.v_eps"):
        assert name in info.parameters
    md = fmpy.read_model_description(str(path))
    grade = next(v for v in md.modelVariables if v.name == "vehicle.grade")
    assert grade.variability == "constant"
    assert "feeds vehicle.f_grade, vehicle.roll" in grade.description
