"""Durability runs (clutchsim.studies.durability, ``clutchsim durability``): the accelerated mode
against the full cycle-by-cycle run, the end of life, the energy balance of every run,
the clamp force after wear, and bad duty files."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from clutchsim.scenario import ScenarioError
from clutchsim.studies.durability import load_duty, run_durability

REPO = Path(__file__).resolve().parents[2]
EXAMPLES = REPO / "examples"
#: accelerated against full on the 200-cycle case: wear within this fraction (measured
#: 0.14 % with 18 of the 200 cycles simulated)
ACCEL_TOL = 0.005

HOT = ('"thermal[0].ambient=45", "thermal[1].ambient=45", "thermal[0].theta0=120", '
       '"thermal[1].theta0=120"')


def _duty(tmp_path, sets=HOT, rest=20.0, count=1, manoeuvre="launch", extra="",
          scenario=EXAMPLES / "launch_wear.toml"):
    f = tmp_path / "duty.toml"
    f.write_text(f"""[duty]
name = "test duty"
cycles = 200
model = "coulomb-robust"
clamp_force = 4000.0

[[manoeuvre]]
name = "launch"
scenario = "{scenario}"
set = [{sets}]
rest = {rest}
{extra}
[[cycle]]
manoeuvre = "{manoeuvre}"
count = {count}
""")
    return f


@pytest.fixture(scope="module")
def two_hundred(tmp_path_factory):
    """The 200-cycle case (one hot launch and 20 s of cooling per cycle, starting at
    120 °C in 45 °C air: the temperatures fall over the first cycles), full and
    accelerated."""
    duty = load_duty(_duty(tmp_path_factory.mktemp("d")))
    return run_durability(duty, accelerated=False), run_durability(duty, accelerated=True)


def test_accelerated_agrees_with_the_full_run_on_200_cycles(two_hundred):
    full, acc = two_hundred
    assert full.simulated_cycles == 200 and acc.simulated_cycles <= 20
    assert acc.wear_m == pytest.approx(full.wear_m, rel=ACCEL_TOL)
    assert acc.clamp_force_end_N == pytest.approx(full.clamp_force_end_N, rel=ACCEL_TOL)
    # the thermal run-in is visible: the first cycle wears more than the last (hotter)
    d = np.diff(np.concatenate([[0.0], full.history["wear_m"]]))
    assert d[0] > d[-1] * 1.01


def test_energy_balance_of_every_run(two_hundred):
    for res in two_hundred:
        assert res.max_energy_balance_rel <= 1e-6


def test_clamp_force_and_capacity_follow_the_table_at_the_shifted_position(two_hundred):
    full, _ = two_hundred
    from clutchsim.scenario import load_scenario
    net = load_scenario(EXAMPLES / "launch_wear.toml").network("coulomb-robust")
    fe = net.component("clutch")
    xs, ys = fe.clamp_table
    f = np.interp(1.0 + fe.wear.shift * full.wear_m, xs, ys)
    assert full.clamp_force_end_N == pytest.approx(4000.0 * f, rel=1e-12)
    assert full.capacity_end_Nm == pytest.approx(240.0 * f, rel=1e-12)



def test_worn_out_clutch_is_a_reported_end_of_life(tmp_path):
    """A facing 2e4 times less resistant wears the 1.5 mm reserve in some tens of cycles:
    both modes stop there and report the life (agreeing to two cycles)."""
    f = _duty(tmp_path, sets='"coupling[0].wear.k_w=6e-9"', rest=60.0)
    full = run_durability(f, accelerated=False)
    acc = run_durability(f, accelerated=True)
    assert full.life_cycles is not None and 10 < full.life_cycles < 200
    assert full.wear_m >= 1.5e-3 and full.simulated_cycles == full.life_cycles
    assert abs(acc.life_cycles - full.life_cycles) <= 2
    assert acc.summary()["life_cycles"] == acc.life_cycles
    for res in (full, acc):
        assert res.outcome == "end_of_life" and res.end_of_life["criterion"] == "wear_reserve"
        assert res.end_of_life["cycle"] == res.life_cycles == res.cycles_done


def test_wear_that_makes_a_manoeuvre_fail_is_the_end_of_life(tmp_path):
    """The 5 % start at 35 % throttle stalls the engine once the wear has moved the engaged
    position far enough (the same pedal clamps earlier and harder), while a new lining
    completes it: the end of life (criterion "engagement": the capacity has not fallen),
    with the curve so far and the state there; exit status 0 with the outputs written."""
    f = _duty(tmp_path, sets='"coupling[0].wear.k_w=6e-9", "vehicle.grade=5"', rest=40.0)
    res = run_durability(f, accelerated=True)
    eol = res.end_of_life
    assert res.outcome == "end_of_life" and res.failure is None, res.summary()
    assert eol["criterion"] == "engagement" and "stalled" in eol["message"]
    assert res.life_cycles == eol["cycle"] == res.cycles_done + 1 < res.cycles
    assert 0.0 < res.wear_m < 1.5e-3 and eol["wear_mm"] == pytest.approx(res.wear_m * 1e3)
    assert eol["clamp_force_N"] == res.clamp_force_end_N > 4000.0
    assert eol["capacity_Nm"] == res.capacity_end_Nm >= 240.0
    h = res.history
    assert h["cycle"][-1] == res.cycles_done and np.all(np.diff(h["wear_m"]) > 0)
    out = tmp_path / "o"
    p = _cli(str(f), "--out", str(out), "--json", "--no-plots")
    assert p.returncode == 0, p.stderr
    doc = json.loads(p.stdout)
    assert doc == json.loads((out / "summary.json").read_text())
    assert doc["outcome"] == "end_of_life" and doc["life_cycles"] == res.life_cycles
    assert "end of life in cycle" in p.stderr and "engagement" in p.stderr
    rows = (out / "durability.csv").read_text().splitlines()
    assert len(rows) == 2 + len(h["cycle"])


def test_a_failure_not_due_to_wear_keeps_the_finished_cycles_and_exits_1(tmp_path):
    """A lining that grabs when hot (μ ×1.6 from 40 to 50 °C) with no rest between launches:
    the temperature climbs until the 5 % start stalls the engine, with a new lining too, so
    the study fails (not an end of life): exit status 1, the finished cycles written."""
    text = (EXAMPLES / "launch_wear.toml").read_text()
    hot = tmp_path / "grabby.toml"
    hot.write_text("\n".join(
        "mu_temperature = { theta = [20.0, 40.0, 50.0], factor = [1.0, 1.0, 1.6] }"
        if line.startswith("mu_temperature") else line for line in text.splitlines()))
    f = _duty(tmp_path, sets='"vehicle.grade=5"', rest=0.0, scenario=hot)
    out = tmp_path / "o"
    p = _cli(str(f), "--out", str(out), "--json", "--no-plots", "--full")
    assert p.returncode == 1, p.stderr
    doc = json.loads(p.stdout)
    assert doc["outcome"] == "failed" and doc["life_cycles"] is None
    assert doc["end_of_life"] is None and doc["failure"]["manoeuvre"] == "launch"
    assert "stalled" in doc["failure"]["message"]
    assert 1 <= doc["cycles_done"] == doc["failure"]["cycle"] - 1 < 200
    assert json.loads((out / "summary.json").read_text()) == doc
    rows = (out / "durability.csv").read_text().splitlines()
    assert len(rows) == 2 + doc["cycles_done"]
    err = [ln for ln in p.stderr.splitlines() if ln.strip()]
    assert "also fails with a new lining" in err[-1] and str(out) in err[-1]


@pytest.mark.parametrize("name", ["passenger_car", "hot_climate"])
def test_example_duty_cycles_load(name):
    duty = load_duty(EXAMPLES / "durability" / f"{name}.toml")
    assert duty.sequence == (("level_launch", 6), ("grade_launch", 3), ("hill_start", 1))
    hill = duty.manoeuvres["hill_start"].scenario
    assert hill.data["vehicle"]["grade"] == 12
    hot = name == "hot_climate"
    assert hill.data["thermal"][0]["ambient"] == (45 if hot else 20)


def test_duty_naming_a_missing_manoeuvre_names_file_and_line(tmp_path):
    f = _duty(tmp_path, manoeuvre="lanch")
    with pytest.raises(ScenarioError) as exc:
        load_duty(f)
    msg = str(exc.value)
    line = f.read_text().splitlines().index('manoeuvre = "lanch"') + 1
    assert f"{f}:{line}:" in msg and "cycle[0].manoeuvre" in msg
    assert "'lanch' is not a manoeuvre" in msg and "did you mean 'launch'" in msg


def test_bad_wear_reserve_in_a_manoeuvre_is_reported_with_its_file(tmp_path):
    f = _duty(tmp_path, sets='"coupling[0].wear.reserve=5e-3"')
    with pytest.raises(ScenarioError) as exc:
        load_duty(f)
    assert "reserve = 0.005" in str(exc.value) and "lining = 0.003" in str(exc.value)


def _cli(*args):
    return subprocess.run([sys.executable, "-m", "clutchsim", "durability", *args],
                          cwd=REPO, capture_output=True, text=True, timeout=900, check=False)


def test_cli_json_and_outputs(tmp_path):
    out = tmp_path / "dur"
    p = _cli(str(_duty(tmp_path)), "--cycles", "30", "--out", str(out), "--json")
    assert p.returncode == 0, p.stderr
    doc = json.loads(p.stdout)
    for k in ("kind", "cycles", "simulated_cycles", "wear_mm", "clamp_force_end_N",
              "capacity_end_Nm", "life_cycles", "wall_s"):
        assert k in doc, k
    assert doc["kind"] == "durability" and doc["cycles"] == 30 and doc["life_cycles"] is None
    assert doc["outcome"] == "completed" and doc["cycles_done"] == 30
    assert doc["wear_mm"] > 0
    for name in ("durability.csv", "durability.png", "summary.json", "command.txt"):
        assert (out / name).exists(), name
    rows = (out / "durability.csv").read_text().splitlines()
    assert rows[0].startswith("cycle,wear_m") and rows[1].startswith("-,m")


def test_cli_bad_duty_exit_2_one_line(tmp_path):
    f = _duty(tmp_path, manoeuvre="nope")
    p = _cli(str(f), "--out", str(tmp_path / "o"))
    lines = [ln for ln in p.stderr.splitlines() if ln.strip()]
    assert p.returncode == 2 and len(lines) == 1 and "cycle[0].manoeuvre" in lines[0]
    assert not (tmp_path / "o").exists()
