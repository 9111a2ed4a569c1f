"""Modelica reference examples (MSL 4.x, Dymola DASSL) under the strict criterion of issue 34.

CoupledClutches, OneWayClutch, OneWayClutchDisengaged and LossyGearDemo1/2/3 run from the
scenario files in ``examples/`` and every signal of each reference's
``comparisonSignals.txt`` is compared by the shared harness ``_modelica.py``: values within
1e-3 of the signal's range, mode switches within 1e-3 s (the historic bounds, MSL's 2e-3
tube and our 1e-4 s on located switches, hold as well).  OneWayClutch's freewheel locks
for 3.2 µs at 1.5 s (a dip of its relative speed to -2.4e-10 rad/s inside one step): the
integrator's valley search finds it (``tests/core/test_narrow_dip_events.py``).
"""

import dataclasses

import numpy as np
import pytest
from _modelica import (
    CASES,
    HISTORIC_TUBE,
    SIGNAL_TOL,
    _compare_modes,
    compare,
    derived_mode,
    reference_mode,
    sample,
    switches,
)

#: the located mode switches match to this (the historic bound of these tests) [s]
LOCATED_SWITCH_TOL = 1e-4
#: ... except the freewheel's 3.2-µs lock of OneWayClutch at 1.4999986 s, which Dymola
#: locates at 1.4997028 s (its DASSL error, 1e-5 rad/s, on a dip 2.4e-10 rad/s deep)
LOOSER = {("one_way_clutch", "oneWayClutch (stuck/sliding)"): 5e-4}


@pytest.mark.parametrize("example", list(CASES))
def test_every_comparison_signal_matches_modelica(example):
    report = compare(CASES[example])
    assert report.result.status == "completed", report.result.message
    assert report.metrics["energy_balance_rel"] <= 1e-8
    assert not report.failures, "\n".join(report.failures) + "\n" + report.table()
    for row in report.rows:
        if row.kind == "value":
            assert row.error <= min(SIGNAL_TOL, HISTORIC_TUBE), row
        else:
            assert row.error <= LOOSER.get((example, row.signal), LOCATED_SWITCH_TOL), row


def test_a_signal_without_a_mapping_fails():
    case = CASES["lossy_gear_demo3"]
    signals = dict(case.signals)
    del signals["Inertia2.phi"]
    report = compare(dataclasses.replace(case, signals=signals))
    assert report.failures == [
        "Inertia2.phi: no mapping to our result (a signal we cannot express fails)"]


def test_a_wrong_mapping_or_mode_fails():
    """A flipped sign fails its value check; a mode read from the wrong element fails its
    switch sequence."""
    case = CASES["coupled_clutches"]
    signals = dict(case.signals)
    signals["clutch2.w_rel"] = {"omega_J2": 1.0, "omega_J3": -1.0}
    signals["clutch3.mode"] = signals["clutch2.mode"]
    failures = compare(dataclasses.replace(case, signals=signals)).failures
    assert [f.split(":")[0] for f in failures] == ["clutch3.mode", "clutch2.w_rel"]


def test_sampling_takes_the_side_of_an_event():
    """Rows written twice at an event: the left limit from the left, the right limit from
    the right; between rows, linear."""
    t = np.array([0.0, 1.0, 1.0, 2.0])
    y = np.array([0.0, 1.0, 5.0, 6.0])
    assert sample(t, y, np.array([1.0]), False)[0] == 1.0
    assert sample(t, y, np.array([1.0]), True)[0] == 5.0
    assert sample(t, y, np.array([0.5, 1.5]), True).tolist() == [0.5, 5.5]


def test_switches_merge_one_instant_and_keep_their_interval():
    t = np.array([0.0, 1.0, 1.0, 1.0, 2.0, 3.0, 4.0, 4.0, 4.0 + 5e-13, 4.0 + 5e-13])
    m = np.array([-1, -1, 0, 1, 1, 2, 2, -1, -1, 2])
    # -1 -> 0 -> +1 at one instant is one switch; 1 -> 2 between rows 2 s and 3 s; a
    # switch undone 5e-13 s later is dropped, and reported when asked
    undone = []
    assert switches(t, m, undone) == [(1.0, 1.0, -1, 1), (2.0, 3.0, 1, 2)]
    assert undone == [4.0]
    row, _ = _compare_modes("m", "mode", switches(t, m), switches(t, m, []), undone)
    assert not row.ok and "undo themselves" in row.detail


def test_reference_mode_in_effect_and_derived():
    """A sliding mode held at a residual speed between two events is stuck; a stretch that
    moves keeps its mode."""
    t = np.array([0.0, 0.5, 1.0, 1.0, 1.5, 2.0])
    slip = np.array([0.0, 5e-11, 5e-11, 5e-11, 0.3, 0.6])
    assert reference_mode(t, np.ones(6), slip).tolist() == [0, 0, 0, 1, 1, 1]
    assert derived_mode(t, slip).tolist() == [0, 0, 0, 1, 1, 1]
