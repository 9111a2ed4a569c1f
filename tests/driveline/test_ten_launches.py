"""Ten hill starts in a row: heat builds up, mu(theta) fades, energy is conserved."""

import numpy as np
import pytest
from _dl_paths import EXAMPLES

from clutchsim.analysis.launch_metrics import energy_balance
from clutchsim.scenario import load_scenario, run_scenario

PERIOD = 12.0        # s between launches (examples/ten_launches.toml)
SHARE = 0.47         # heat share of each metal face


@pytest.fixture(scope="module")
def ten():
    sc = load_scenario(EXAMPLES / "ten_launches.toml")
    return sc, run_scenario(sc, "coulomb-robust")


def test_ten_launches_complete_with_energy_balance(ten):
    _, r = ten
    m = r.metrics
    assert m["completed"], m["message"]
    assert m["energy_balance_rel"] <= 1e-8
    assert not m["engine_stalled"]
    assert len(_lock_ups(r.result)) == 10                    # every launch locks up


def _lock_ups(res):
    """Time of the first clutch lock after the start of each launch, relative to it [s]."""
    lk = res["clutch.locked"] > 0.5
    on = res.t[1:][lk[1:] & ~lk[:-1]]          # rows on both sides of every event
    out = []
    for k in range(10):
        t = on[(on >= k * PERIOD) & (on < (k + 1) * PERIOD)]
        if t.size:
            out.append(float(t[0]) - k * PERIOD)
    return out


def test_temperature_builds_up_launch_after_launch(ten):
    _, r = ten
    res = r.result
    surf = res["theta_pressure_plate_surface"]
    bulk = res["theta_pressure_plate"]
    peaks, rises, starts = [], [], []
    for k in range(10):
        sel = (res.t >= k * PERIOD) & (res.t < (k + 1) * PERIOD)
        peaks.append(np.max(surf[sel]))
        starts.append(bulk[sel][0])
        rises.append(np.max(surf[sel]) - surf[sel][0])
    assert np.all(np.diff(peaks) > 5.0)                       # K: monotone build-up
    assert np.all(np.diff(starts) > 5.0)
    # a hard launch heats the friction surface by tens of kelvin
    assert min(rises) > 20.0 and max(rises) < 100.0
    # the surface layer leads the bulk during slip and relaxes towards it afterwards
    assert np.max(surf - bulk) > 20.0
    assert abs(surf[-1] - bulk[-1]) < 5.0


def test_capacity_falls_with_mu_theta(ten):
    sc, r = ten
    res = r.result
    table = sc.data["coupling"][0]["mu_temperature"]
    surf = res["theta_pressure_plate_surface"]
    cmd = sc.inputs["clutch_command"](res.t)
    full = cmd >= 1.0 - 1e-12
    factor = res["capacity_clutch"][full] / 240.0            # capacity / T_stat at COM = 1
    # the capacity follows mu(theta) of the lining temperature ...
    expected = np.interp(surf[full], table["theta"], table["factor"])
    assert np.allclose(factor, expected, rtol=1e-9)
    # ... and falls once the surface passes 200 °C in the last launches
    assert np.max(surf) > 210.0
    assert np.min(factor) < 0.97
    first = factor[res.t[full] < PERIOD]
    assert np.all(first == 1.0)
    # the hotter clutch needs longer to lock up
    locks = _lock_ups(res)
    assert locks[-1] > locks[0] + 0.01


def test_heat_into_the_thermal_network_is_conserved(ten):
    sc, r = ten
    res = r.result
    nodes = {t["name"]: t for t in sc.data["thermal"]}
    stored = sum(t["capacity"] * (res[f"theta_{n}"][-1] - res[f"theta_{n}"][0])
                 for n, t in nodes.items())
    convected = sum(t.get("conductance", 0.0)
                    * np.trapezoid(res[f"theta_{n}"] - t.get("ambient", 20.0), res.t)
                    for n, t in nodes.items())
    # the clutch's friction work (W_friction also holds the service brake's)
    heat_in = 2 * SHARE * np.trapezoid(np.abs(res["P_clutch"]), res.t)
    assert heat_in < energy_balance(res)["W_friction"]
    assert stored + convected == pytest.approx(heat_in, rel=2e-3)
