"""``clutchsim run`` on networks that are not launches: outputs named by the scenario, the
summary of any network (docs/outputs.md), one figure, no nulls, no empty keys, no warnings
of the plotting library (the subprocess runs with ``-W error``)."""

import json
import math
import subprocess
import sys
from pathlib import Path

import pytest

from clutchsim.scenario.run import expects_lockup, is_launch

REPO = Path(__file__).resolve().parents[2]

#: the keys of one run of a network, of its records and of its energies (docs/outputs.md)
RUN_KEYS = {"completed", "outcome", "message", "warnings", "t_end_s", "steps", "rhs_evals",
            "events", "min_step_s", "wall_s", "energy_balance_rel", "speeds", "energies",
            "friction_elements", "temperatures", "located_events"}
SPEED_KEYS = {"name", "unit", "initial", "final", "min", "max"}
ENERGY_KEYS = {"work_in_J", "friction_J", "damping_J", "road_J", "grade_J", "impacts_J",
               "heat_J", "kinetic_initial_J", "kinetic_final_J", "stored_initial_J",
               "stored_final_J"}
FRICTION_KEYS = {"name", "kind", "model", "work_J", "peak_power_W", "drag_work_J", "lockups",
                 "releases", "lockup_times_s", "locked_at_end"}
EVENT_KEYS = {"name", "element", "count", "first_s", "last_s"}

NETWORKS = {"elasto_gap": "ElastoGap", "coupled_clutches": "CoupledClutches",
            "one_way_clutch": "OneWayClutch", "sign_convention": "SignConvention",
            "test_speed_rotational": "TestSpeedRotational",
            "simple_gear_shift": "SimpleGearShift"}


def _run(*args):
    return subprocess.run([sys.executable, "-W", "error", "-m", "clutchsim", "run", *args],
                          cwd=REPO, capture_output=True, text=True, timeout=600, check=False)


def _walk(obj, path="$"):
    """Every (path, key, value) of a JSON document."""
    if isinstance(obj, dict):
        for k, v in obj.items():
            yield path, k, v
            yield from _walk(v, f"{path}.{k}")
    elif isinstance(obj, list):
        for i, v in enumerate(obj):
            yield path, i, v
            yield from _walk(v, f"{path}[{i}]")


@pytest.fixture(scope="module")
def outputs(tmp_path_factory):
    """Each example run once: ``{stem: (directory, stdout document, stderr)}``."""
    base = tmp_path_factory.mktemp("networks")
    done = {}
    for stem in NETWORKS:
        out = base / stem
        p = _run(f"examples/{stem}.toml", "--out", str(out), "--json")
        assert p.returncode == 0, p.stderr
        done[stem] = (out, json.loads(p.stdout), p.stderr)
    return done


@pytest.mark.parametrize("stem", sorted(NETWORKS))
def test_a_network_run_has_its_own_summary_and_figure(outputs, stem):
    out, doc, _ = outputs[stem]
    name = NETWORKS[stem]
    assert json.loads((out / "summary.json").read_text()) == doc     # --json: the summary
    assert set(doc) == {"kind", "scenario", "file", "runs", "parameters", "failed"}
    assert doc["kind"] == "run" and doc["scenario"] == name and doc["failed"] == []
    assert list(doc["runs"]) == [name]                 # named by the scenario, no model key
    run = doc["runs"][name]
    assert set(run) == RUN_KEYS, set(run) ^ RUN_KEYS
    for path, key, value in _walk(doc):
        assert value is not None, f"{path}.{key} is null"
        assert key != "", f"{path} has an empty key"
        if isinstance(value, float):
            assert math.isfinite(value), f"{path}.{key} = {value}"
    assert all(set(r) == SPEED_KEYS for r in run["speeds"]) and run["speeds"]
    assert set(run["energies"]) == ENERGY_KEYS
    assert all(set(r) == FRICTION_KEYS for r in run["friction_elements"])
    assert all(set(r) == EVENT_KEYS for r in run["located_events"])
    # the figures: one of the network, none of a launch
    pngs = sorted(p.name for p in out.glob("*.png"))
    assert pngs == [f"network_{name}.png"], pngs
    assert (out / pngs[0]).stat().st_size > 20_000
    # physics: the energy account closes, each speed lies within its range
    e = run["energies"]
    residual = (e["work_in_J"] - (e["kinetic_final_J"] - e["kinetic_initial_J"])
                - (e["stored_final_J"] - e["stored_initial_J"]) - e["heat_J"] - e["grade_J"])
    scale = max(abs(e["work_in_J"]), e["kinetic_initial_J"], e["kinetic_final_J"], 1e-12)
    assert abs(residual) / scale < 1e-6 and run["energy_balance_rel"] < 1e-6
    assert e["heat_J"] == pytest.approx(e["friction_J"] + e["damping_J"] + e["road_J"]
                                        + e["impacts_J"])
    for r in run["speeds"]:
        assert r["min"] <= min(r["initial"], r["final"]) <= max(r["initial"], r["final"]) \
            <= r["max"]
    assert sum(r["count"] for r in run["located_events"]) == run["events"]


def test_sign_convention_summary_is_the_analytic_motion(outputs):
    """Three masses of 1 kg under 1 N from rest: v(1 s) = 1 m/s each, so the forces put in
    3 × ½·1·1² = 1.5 J, all of it kinetic; no friction, no events."""
    run = outputs["sign_convention"][1]["runs"]["SignConvention"]
    assert {r["name"] for r in run["speeds"]} == {"mass1", "mass2", "mass3"}
    for r in run["speeds"]:
        assert r["unit"] == "m/s"
        assert r["initial"] == 0.0 and r["final"] == pytest.approx(1.0, rel=1e-9)
    assert run["energies"]["work_in_J"] == pytest.approx(1.5, rel=1e-9)
    assert run["energies"]["kinetic_final_J"] == pytest.approx(1.5, rel=1e-9)
    assert run["friction_elements"] == [] and run["located_events"] == []


def test_one_way_clutch_lockups_are_its_stop_events(outputs):
    run = outputs["one_way_clutch"][1]["runs"]["OneWayClutch"]
    (fe,) = run["friction_elements"]
    assert fe["name"] == "oneWayClutch" and fe["kind"] == "one_way_clutch"
    stops = next(r for r in run["located_events"] if r["name"] == "oneWayClutch: stop")
    assert fe["lockups"] == stops["count"] == len(fe["lockup_times_s"]) >= 2
    assert fe["lockup_times_s"][0] == stops["first_s"]
    assert fe["lockup_times_s"][-1] == stops["last_s"]
    assert fe["work_J"] == pytest.approx(run["energies"]["friction_J"], rel=1e-9)


def test_coupled_clutches_friction_work_adds_up(outputs):
    run = outputs["coupled_clutches"][1]["runs"]["CoupledClutches"]
    fes = {r["name"]: r for r in run["friction_elements"]}
    assert set(fes) == {"clutch1", "clutch2", "clutch3"}
    assert sum(r["work_J"] for r in fes.values()) == pytest.approx(
        run["energies"]["friction_J"], rel=1e-9)
    # clutch3 is commanded from 0.9 s: it cannot lock before; J4 starts at rest
    assert all(t > 0.9 for t in fes["clutch3"]["lockup_times_s"])
    j4 = next(r for r in run["speeds"] if r["name"] == "J4")
    assert j4["initial"] == 0.0 and j4["max"] > 0.0
    assert run["warnings"] == []       # not a launch: no "this launch has no vehicle"


def test_a_shift_that_expects_lockup_without_vehicle_or_engine_warns_nothing(outputs):
    """SimpleGearShift sets ``expect_lockup = true`` (its clutch locks at the shift) and has
    neither a vehicle nor an engine: no launch, so no "this launch has no vehicle"."""
    run = outputs["simple_gear_shift"][1]["runs"]["SimpleGearShift"]
    clutch = next(r for r in run["friction_elements"] if r["name"] == "clutch")
    assert clutch["lockups"] >= 1 and clutch["locked_at_end"]
    assert run["warnings"] == []


def test_the_report_shows_the_network_summary(outputs):
    from clutchsim.report.gather import gather
    data = gather(outputs["coupled_clutches"][0])
    titles = [t.title for t in data.tables]
    for part in ("speeds", "energies", "friction_elements", "located_events"):
        assert any(t.endswith(part) for t in titles), (part, titles)
    for t in (t for t in data.tables if "runs" in t.title):
        for row in t.rows:
            assert all(v is not None and v != [] for v in row), (t.title, row)
    assert [f.name for f in data.figures] == ["network_CoupledClutches.png"]
    assert data.solver is not None and not data.failed


@pytest.mark.parametrize(("kinds", "clutch", "launch"), [
    ({"clutch": "clutch", "vehicle": "vehicle", "engine": "engine"}, "clutch", True),
    ({"clutch": "clutch", "engine": "engine"}, "clutch", True),      # on a test rig
    ({"lockup": "clutch", "vehicle": "vehicle"}, "lockup", True),
    ({"clutch1": "clutch", "J1": "inertia"}, "clutch1", False),       # CoupledClutches
    ({"b": "brake", "vehicle": "vehicle", "engine": "engine"}, "b", False),
    ({"owc": "one_way_clutch", "engine": "engine"}, "owc", False),
    ({"m": "mass", "f": "force"}, "clutch", False),                   # no such element
])
def test_the_launch_rule(kinds, clutch, launch):
    assert is_launch(kinds, clutch) is launch


def test_lockup_is_expected_by_default_in_a_launch_only():
    from clutchsim.scenario import load_scenario
    cc = load_scenario(REPO / "examples" / "coupled_clutches.toml")
    kinds = {"clutch1": "clutch", "J1": "inertia"}
    assert not expects_lockup(cc, kinds)
    assert expects_lockup(cc, {**kinds, "vehicle": "vehicle"})
    forced = load_scenario(REPO / "examples" / "coupled_clutches.toml",
                           overrides=["scenario.expect_lockup=true"])
    assert expects_lockup(forced, kinds)


def test_models_compared_on_a_network_are_its_keys(tmp_path):
    """Two models on CoupledClutches: one run, time series and figure per model, keyed by
    the model's name (not by the scenario's)."""
    out = tmp_path / "two"
    p = _run("examples/coupled_clutches.toml", "--model", "coulomb-robust", "--model",
             "mykhailevych2020", "--out", str(out), "--json")
    assert p.returncode == 0, p.stderr
    doc = json.loads(p.stdout)
    assert list(doc["runs"]) == ["coulomb-robust", "mykhailevych2020"]
    for model, run in doc["runs"].items():
        assert set(run) == RUN_KEYS
        assert {fe["model"] for fe in run["friction_elements"]} >= {model}
        assert (out / f"network_{model}.png").stat().st_size > 20_000
        assert (out / f"timeseries_{model}.csv").is_file()
    assert not list(out.glob("launch_*.png")) and not (out / "comparison.png").exists()
    smooth = {fe["name"]: fe for fe in doc["runs"]["mykhailevych2020"]["friction_elements"]}
    assert smooth["clutch1"]["model"] == "mykhailevych2020"


def test_compare_is_refused_on_a_network_that_is_not_a_launch(tmp_path):
    out = tmp_path / "cmp"
    p = _run("examples/coupled_clutches.toml", "--set",
             'scenario.compare="launch.toml"', "--out", str(out))
    assert p.returncode == 2, p.stderr
    lines = [ln for ln in p.stderr.splitlines() if ln.strip() and "NumExpr" not in ln]
    assert "scenario.compare" in lines[-1] and "not a launch" in lines[-1], lines
    assert not out.exists() and not Path(str(out) + ".partial").exists()


def test_a_launch_keeps_its_launch_summary(tmp_path):
    """The default launch: ``models`` keyed by the friction model, the launch metrics, the
    launch figure (docs/outputs.md, "A launch")."""
    out = tmp_path / "launch"
    p = _run("--model", "coulomb-robust", "--set", "scenario.t_end=0.3", "--out", str(out),
             "--json")
    assert p.returncode == 0, p.stderr
    doc = json.loads(p.stdout)
    assert set(doc) == {"kind", "scenario", "file", "models", "parameters", "failed"}
    m = doc["models"]["coulomb-robust"]
    assert {"lockup_time_s", "slip_energy_J", "engine_dip_rpm", "vdv_mps175",
            "energy_balance_rel"} <= set(m)
    assert not RUN_KEYS - {"t_end_s", "speeds", "energies", "friction_elements",
                           "temperatures", "located_events"} - set(m)
    assert (out / "launch_coulomb-robust.png").is_file()
    assert not list(out.glob("network_*.png"))
