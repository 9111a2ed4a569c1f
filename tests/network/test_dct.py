"""Dual-clutch transmission as a network (examples/dct_upshift.toml): launch on clutch 1,
clutch-to-clutch 1 -> 2 upshift with overlapping commands, its torque phase and inertia
phase, the kinematics of the pre-selected gears and the energy balance."""

import numpy as np
import pytest
from _dl_paths import EXAMPLES

from clutchsim.scenario import run_scenario

R1, R2, FD = 3.6, 2.1, 4.1


@pytest.fixture(scope="module")
def shift():
    r = run_scenario(EXAMPLES / "dct_upshift.toml")
    assert r.result.status == "completed", r.result.message
    return r


def test_both_pre_selected_gears_turn_with_the_output(shift):
    res = shift.result
    assert np.allclose(res["omega_shaft_odd"] * R2, res["omega_shaft_even"] * R1, rtol=1e-12)


def test_torque_phase_then_inertia_phase(shift):
    """Torque phase, from the start of the overlap (3.0 s) to clutch 1's break-away: the
    engine stays on the first-gear shaft (clutch 1 holds) while clutch 2 slips at its
    sliding capacity and the output torque r1·FD·T1 + r2·FD·T2 drops towards the second
    gear's (the vehicle's acceleration falls).  Inertia phase, from the break-away to
    clutch 2's lock-up: the engine is pulled down from the first-gear to the second-gear
    speed while clutch 2 carries its capacity, and the acceleration rises again."""
    res = shift.result
    t = res.t
    ev = {e.name: e.t for e in res.events if e.t > 2.0}
    t_b, t_lock = ev["clutch1: breakaway"], ev["clutch2: stop"]
    assert 3.0 < t_b < 3.25 < t_lock < 3.8
    torque = (t >= 3.0) & (t < t_b)
    assert np.allclose(res["omega_engine"][torque], res["omega_shaft_odd"][torque], rtol=1e-9)
    assert np.allclose(res["T_friction_clutch2"][torque], -res["capacity_clutch2"][torque] *
                       300.0 / 330.0, rtol=1e-9)
    a = res["a_vehicle"]
    i0, ib = np.searchsorted(t, 3.0), np.searchsorted(t, t_b)
    assert a[ib] < 0.5 * a[i0]                        # the torque hole
    inertia = (t > t_b) & (t < t_lock)
    w = res["omega_engine"][inertia]
    assert w[0] > 0.95 * res["omega_shaft_odd"][inertia][0]
    assert np.all(np.diff(w[np.searchsorted(t[inertia], 3.3):]) < 0.0)
    k = np.searchsorted(t, t_lock)
    assert res["omega_engine"][k + 1] == pytest.approx(res["omega_shaft_even"][k + 1],
                                                       rel=1e-9)
    assert np.max(a[inertia]) > 2.0 * a[ib]           # the inertia torque
    after = t > t_lock + 0.01
    assert np.allclose(res["omega_engine"][after], res["omega_shaft_even"][after], rtol=1e-9)


def test_shift_metrics_and_energy_balance(shift):
    m = shift.metrics
    assert m["energy_balance_rel"] < 1e-6
    assert m["lockup_time_s"] == pytest.approx(
        min(e.t for e in shift.result.events if e.name == "clutch2: stop"), abs=1e-3)
    assert m["slip_energy_J"] > 0 and m["vdv_mps175"] > 0


def test_component_figure_shows_both_clutches(shift, tmp_path):
    from clutchsim.plot._style import save_png
    from clutchsim.plot.components import component_panels, plot_components
    panels = component_panels(shift.result)
    assert [p[0] for p in panels] == ["friction elements: torque passed on"]
    assert [line[0] for line in panels[0][2]] == ["T_friction_clutch1", "T_friction_clutch2"]
    fig, ax = plot_components(shift.result)
    assert ax.shape == (1, 1) and len(ax[0, 0].lines) == 2
    assert save_png(fig, tmp_path / "c.png").stat().st_size > 1000
    with pytest.raises(TypeError, match="unknown keyword"):
        plot_components(shift.result, colour="red")


def test_two_clutches_commanded_onto_the_same_shaft_are_refused(tmp_path):
    """Both DCT clutches onto the odd input shaft: a clear error naming both clutches and
    the shafts, with the file and the component's line."""
    from clutchsim.scenario import ScenarioError, load_scenario
    text = (EXAMPLES / "dct_upshift.toml").read_text()
    bad = tmp_path / "dct_bad.toml"
    bad.write_text(text.replace('["clutch2.b", "shaft_even.a"],',
                                '["clutch2.b", "shaft_odd.a"],'))
    with pytest.raises(ScenarioError) as info:
        load_scenario(bad).network()
    msg = str(info.value)
    assert "dct_bad.toml" in msg and "clutch 'clutch2'" in msg and "clutch 'clutch1'" in msg
    assert "two clutches commanded onto the same shaft" in msg
