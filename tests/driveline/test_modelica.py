"""Modelica reference examples (MSL 4.x, Dymola DASSL, CSV-compare tube 2e-3).

CoupledClutches, OneWayClutch, OneWayClutchDisengaged and LossyGearDemo1/2/3 run from the
scenario files in ``examples/`` and are compared with the published reference results:
the times at which the switching element locks and frees, and the speeds (relative
deviation over the whole run, within the tube 2e-3 of the signal's range).
"""

import numpy as np
import pandas as pd
import pytest
from _dl_paths import EXAMPLES, shared_dir

from clutchsim.scenario import run_scenario

REF = shared_dir() / "reference" / "modelica" / "Modelica" / "Mechanics" / "Rotational" / "Examples"

#: reference mode switches of CoupledClutches (README of the reference folder)
SWITCHES = {
    "clutch1": [("stop", 0.7916582843), ("breakaway", 0.8311085061), ("stop", 0.9068491375),
                ("breakaway", 1.0002958599)],
    "clutch2": [("stop", 0.7096214638)],
    "clutch3": [("stop", 1.1439696304)],
}
TUBE = 2e-3
SWITCH_TOL = 1e-4     # s


def reference(name):
    path = REF / name / f"{name}.csv"
    if not path.exists():
        pytest.skip(f"Modelica reference results not found at {path} "
                    "(set CLUTCHSIM_SHARED to the shared folder)")
    return pd.read_csv(path)


def reference_speeds(path):
    ref = pd.read_csv(path).drop_duplicates("time", keep="last")
    w1 = ref["J1.w"].to_numpy()
    w2 = w1 + ref["clutch1.w_rel"].to_numpy()     # J2.w = J1.w + clutch1.w_rel, ...
    w3 = w2 + ref["clutch2.w_rel"].to_numpy()
    w4 = w3 + ref["clutch3.w_rel"].to_numpy()
    return ref["time"].to_numpy(), (w1, w2, w3, w4)


def test_coupled_clutches_robust_matches_modelica(modelica_csv):
    r = run_scenario(EXAMPLES / "coupled_clutches.toml", "coulomb-robust")
    res = r.result
    assert res.status == "completed", res.message
    for clutch, expected in SWITCHES.items():
        # before its command steps up an element is free (Modelica mode 2): its
        # zero-capacity break-away at the first torque is not a mode switch there
        t_on = {"clutch1": 0.0, "clutch2": 0.4, "clutch3": 0.9}[clutch]
        got = [(e.name.split(": ")[1], e.t) for e in res.events
               if e.name.startswith(clutch + ":") and t_on < e.t < 1.25]
        assert [k for k, _ in got] == [k for k, _ in expected], (clutch, got)
        for (_, t_got), (_, t_ref) in zip(got, expected):
            assert abs(t_got - t_ref) < SWITCH_TOL, (clutch, t_got, t_ref)
    t_ref, speeds = reference_speeds(modelica_csv)
    for k, w_ref in enumerate(speeds, start=1):
        w = np.interp(t_ref, res.t, res[f"omega_J{k}"])
        # tube 2e-3 relative to the signal's range, away from event instants
        assert np.max(np.abs(w - w_ref)) <= TUBE * max(np.max(np.abs(w_ref)), 1.0), k


def stuck_switches(t, w, tol=1e-8):
    """[(kind, time)] where |w| comes to rest ('lock', first row at rest) and leaves it
    ('release', last row at rest); event rows of the reference appear twice."""
    rest = np.abs(w) <= tol
    out = []
    for i in range(1, len(w)):
        if rest[i] and not rest[i - 1]:
            out.append(("lock", float(t[i])))
        elif rest[i - 1] and not rest[i]:
            out.append(("release", float(t[i - 1])))
    return rest[0], out


def our_switches(res, element):
    """[(kind, time)] from the element's lock flag (outputs are recorded on both sides of
    every event)."""
    lk = res[f"{element}.locked"] > 0.5
    out = []
    for i in range(1, len(lk)):
        if lk[i] != lk[i - 1]:
            out.append(("lock" if lk[i] else "release", float(res.t[i])))
    return bool(lk[0]), out


#: example -> (reference name, element, reference slip signal, speeds: ours <- reference)
CASES = {
    "one_way_clutch": ("OneWayClutch", "oneWayClutch", "oneWayClutch.w_rel",
                       {"inertiaIn": ("inertiaIn.w",), "inertiaOut": ("inertiaIn.w",
                                                                       "oneWayClutch.w_rel")}),
    "one_way_clutch_disengaged": ("OneWayClutchDisengaged", "oneWayClutch",
                                  "oneWayClutch.w_rel",
                                  {"inertiaIn": ("inertiaIn.w",),
                                   "inertiaOut": ("inertiaIn.w", "oneWayClutch.w_rel")}),
    "lossy_gear_demo1": ("LossyGearDemo1", "gear", "Inertia2.w", {"Inertia2": ("Inertia2.w",)}),
    "lossy_gear_demo2": ("LossyGearDemo2", "gear", "Inertia2.w", {"Inertia2": ("Inertia2.w",)}),
    "lossy_gear_demo3": ("LossyGearDemo3", "gear", "Inertia2.w", {"Inertia2": ("Inertia2.w",)}),
}

#: reference lock/release pairs that our run lacks: at 1.4997-1.5000 s the OneWayClutch
#: reference locks for 3 ms because its relative speed reaches zero just before the drive
#: torque changes sign at 1.5 s; ours only touches zero at 1.5 s (a double root, minimum
#: -2e-10 rad/s, that the event detection does not resolve), within the 2e-5 rad/s speed
#: deviation; see docs/validation-modelica.md
NEAR_TANGENT = {"one_way_clutch": [(1.4997, 1.5001)]}


@pytest.mark.parametrize("example", list(CASES))
def test_switching_examples_match_modelica(example):
    ref_name, element, slip_col, speeds = CASES[example]
    ref_all = reference(ref_name)
    r = run_scenario(EXAMPLES / f"{example}.toml")
    res = r.result
    assert res.status == "completed", res.message
    assert r.metrics["energy_balance_rel"] <= 1e-8
    # lock / release instants of the element
    _rest0, expected = stuck_switches(ref_all["time"].to_numpy(), ref_all[slip_col].to_numpy())
    for lo, hi in NEAR_TANGENT.get(example, []):
        expected = [(k, t) for k, t in expected if not lo <= t <= hi]
        w = res[f"w_slip_{element}"][(res.t >= lo) & (res.t <= hi)]
        assert -1e-8 < np.min(w) < 1e-4     # a touch of zero slip, no backward slip
    locked0, got = our_switches(res, element)
    if expected and expected[0] == ("release", 0.0):   # starts stuck, frees at t = 0
        expected = expected[1:]
        assert got[:1] == [("release", 0.0)] or not locked0, got
        got = got[1:] if got[:1] == [("release", 0.0)] else got
    assert [k for k, _ in got] == [k for k, _ in expected], (got, expected)
    for (_, t_got), (_, t_ref) in zip(got, expected):
        assert abs(t_got - t_ref) < SWITCH_TOL, (t_got, t_ref)
    # speeds inside the tube
    ref = ref_all.drop_duplicates("time", keep="last")
    t_ref = ref["time"].to_numpy()
    for node, cols in speeds.items():
        w_ref = sum(ref[c].to_numpy() for c in cols)
        w = np.interp(t_ref, res.t, res[f"omega_{node}"])
        assert np.max(np.abs(w - w_ref)) <= TUBE * np.max(np.abs(w_ref)), node


def test_lossy_gear_mode_sequence_matches_modelica():
    """gear.mode of LossyGearDemo1: -1 rolling backward, 0 stuck, +1 forward."""
    ref = reference("LossyGearDemo1")
    res = run_scenario(EXAMPLES / "lossy_gear_demo1.toml").result
    mode = res["gear.mode"]
    ref_seq = [int(m) for i, m in enumerate(ref["gear.mode"]) if i == 0
               or m != ref["gear.mode"].iloc[i - 1]]
    our_seq = [int(m) for i, m in enumerate(mode) if i == 0 or m != mode[i - 1]]
    assert our_seq == ref_seq == [0, -1, 0, 1, 0, -1]
    # the loss power is never negative: the gear only dissipates
    assert np.min(res["P_gear"]) >= -1e-9
