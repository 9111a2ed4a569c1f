"""The FMU of a network with the wet multi-plate clutch (``wet_clutch_engagement.toml``:
the open pack's film-shrinkage drag and mist, the oil node's viscosity, the piston's
engagement to lock-up).  The printed C equals the compiled plant on random states
(right-hand side, outputs, Jacobian, events, resets), the FMU passes FMPy's compliance
checks, and FMPy's run of it (CVode) follows clutchsim's run in the 2e-3 tube, with the
drag's work and the oil's temperature, locks where clutchsim locks, and closes its energy
balance below 1e-6."""

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
from clutchsim.fmu.export import _plant_of
from clutchsim.scenario import load_scenario, run_scenario

pytest.importorskip("fmpy", reason="FMPy (the dev extra) runs the exported FMUs")
from fmpy.validation import validate_fmu

pytestmark = pytest.mark.skipif(shutil.which("cc") is None and shutil.which("gcc") is None,
                                reason="no C compiler on this machine")


def test_fmu_of_a_wet_clutch_runs_as_clutchsim(tmp_path):
    sc = load_scenario(EXAMPLES / "wet_clutch_engagement.toml")
    path = tmp_path / "wet.fmu"
    info = export_fmu(sc, path, None)
    assert validate_fmu(str(path)) == []
    assert {"pack: stop", "pack: breakaway"} <= set(info.event_indicators)
    plan, _, system, _ = _plant_of(sc, None)
    worst, _, checked_lock = c_plant_difference(plan, system, k=30)
    assert worst <= 1e-12 and checked_lock
    res = run_scenario(sc, None).result
    assert res.status == "completed"
    signals = ["omega_shaft", "omega_load", "theta_oil", "theta_plates", "W_drag_pack",
               "T_drag_pack", "capacity_pack"]
    f = simulate(path, sc, [*signals, "E_kinetic", "E_spring", *ENERGY, "pack.locked"],
                 1e-8, 1e-4, record_events=True)
    assert f["time"][-1] == pytest.approx(sc.t_end)
    # (the drag's peak is a kink at the film's critical speed: clutchsim's output grid,
    # interpolated across it, is compared with a width in time of one output interval)
    for name in [*signals, *ENERGY]:
        assert (tube_tv(f, res, name, 5e-4) if name == "T_drag_pack"
                else tube(f, res, name)) <= TUBE, name
    assert f["W_drag_pack"][-1] == pytest.approx(res["W_drag_pack"][-1], rel=TUBE)
    t = f["time"]
    theirs = t[1:][(np.diff(f["pack.locked"]) != 0) & (np.diff(t) == 0)]
    ours = [e.t for e in res.events if e.name in ("pack: stop", "pack: breakaway")
            and e.t > 0.0]
    assert len(theirs) == len(ours) == 1
    assert abs(theirs[0] - ours[0]) <= SWITCH_TOL
    assert energy_balance(f) < 1e-6
