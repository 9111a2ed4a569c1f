"""One strict comparison with the Modelica reference results (issue 34), shared by
``tests/driveline/test_modelica.py`` and ``tests/network/test_modelica_network.py``.

Contract
--------
For a :class:`Case` (an example scenario and the MSL 4.x reference folder it reproduces),
:func:`compare` runs the scenario with ``outputs.angles = true`` and checks **every** signal
named in the reference's ``comparisonSignals.txt`` (``time`` aside; the one-instant Boolean
flags ``startForward``/``startBackward`` are excluded, as the reference README says):

* a continuous signal ``x``: ``max |sim − ref| / range(ref) ≤ SIGNAL_TOL`` (1e-3) over every
  row of the reference, where ``range = max(ref) − min(ref)``.  Our signal is interpolated
  linearly, on the matching side of an event: the reference writes each event instant twice
  (left, then right limit), and so do we; the left row is compared with our left limit, the
  right row with our right limit.  Around each matched mode switch the reference
  times are first mapped onto ours (CSV-compare's "aligned event times"): the switch
  instant goes to ours, linearly within twice their difference (at most SWITCH_TOL) of it,
  so that a signal that jumps at the event (a mass hitting its stop) is compared on the
  same side; rows farther away keep their time.
* a ``mode`` signal (−1 backward sliding, 0 stuck, +1 forward sliding, 2 free): the
  sequence of switches must be the same, each within SWITCH_TOL (1e-3 s).  Ours is read as
  2 where the element's capacity ``capacity_<element>`` is ≤ 0 (Modelica: normal force ≤ 0),
  else 0 where ``<element>.locked``, else ``<element>.mode``.  The reference's mode is read
  "in effect": a sliding mode (±1) held over a whole stretch between two event instants at a
  relative speed that never leaves |w| ≤ W_SMALL is stuck (0).  Dymola keeps ±1 at a
  residual 5e-11 rad/s when two stuck elements share one holding torque (LossyGearDemo2; the
  MSL documentation calls that split not unique).  Switches at one instant (−1 → 0 → +1 at
  an impact) or closer than CLUSTER_S count as one.
* a reference without a mode column for its switching element (the one-way clutches) gets
  a derived mode: stuck where its relative speed stays within W_SMALL between two events,
  else the sign of that speed; compared in the same way (``Case.derived``).

A signal without a mapping is a failure, never a skip (:attr:`Report.failures`).  When the
shared reference folder is absent the test is skipped with the path it looked for.
"""

from dataclasses import dataclass, field
from itertools import pairwise

import numpy as np
import pandas as pd
import pytest
from _dl_paths import EXAMPLES, shared_dir

from clutchsim.scenario import run_scenario

SIGNAL_TOL = 1e-3     # max |sim − ref| / range(ref)
SWITCH_TOL = 1e-3     # s, a mode switch or contact crossing
HISTORIC_TUBE = 2e-3  # MSL's own CSV-compare tube (the looser, historic bound)
W_SMALL = 1e-8        # rad/s or m/s: a reference relative speed regarded as rest
CLUSTER_S = 1e-6      # s: switches closer than this are one switch
EXCLUDED = ("startForward", "startBackward")   # one-instant flags; README: do not compare


@dataclass(frozen=True)
class Mode:
    """A mode signal: our element and (optional) the reference's relative speed of it, a
    linear combination ``{reference column: factor}``."""

    element: str
    slip: dict | None = None
    free: bool = True      # our element is free (2) while its capacity is 0


@dataclass(frozen=True)
class Case:
    """An example scenario against one MSL reference.

    ``signals`` maps each Modelica comparison signal to ``{our column: factor}`` (a linear
    combination of our result columns) or to a :class:`Mode`; ``derived`` adds mode checks
    that the reference has no column for (name -> :class:`Mode` with its ``slip``).
    """

    reference: str                     # e.g. "Rotational/Examples/CoupledClutches"
    example: str                       # examples/<example>.toml
    signals: dict
    derived: dict = field(default_factory=dict)
    model: str | None = None

    @property
    def name(self) -> str:
        return self.reference.rsplit("/", 1)[1]


@dataclass
class Row:
    signal: str
    kind: str          # "value", "mode" or "derived mode"
    error: float       # relative error, or the largest switch-time error [s]
    limit: float
    detail: str = ""

    @property
    def ok(self) -> bool:
        return bool(self.error <= self.limit) and not self.detail.startswith("FAIL")


@dataclass
class Report:
    case: Case
    rows: list
    unmapped: list
    result: object = None
    metrics: dict = field(default_factory=dict)

    @property
    def failures(self) -> list:
        return ([f"{s}: no mapping to our result (a signal we cannot express fails)"
                 for s in self.unmapped]
                + [f"{r.signal}: {r.kind} error {r.error:.3g} > {r.limit:g} {r.detail}"
                   for r in self.rows if not r.ok])

    def table(self) -> str:
        lines = [f"{self.case.name} ({self.case.example}.toml)"]
        for r in self.rows:
            unit = " s" if "mode" in r.kind else ""
            lines.append(f"  {r.signal:28s} {r.kind:12s} {r.error:9.2e}{unit} "
                         f"(limit {r.limit:g}) {'ok' if r.ok else 'FAIL'} {r.detail}")
        lines += [f"  {s:28s} UNMAPPED" for s in self.unmapped]
        return "\n".join(lines)


def reference_dir(case: Case):
    return shared_dir() / "reference" / "modelica" / "Modelica" / "Mechanics" / case.reference


def load_reference(case: Case):
    """``(reference frame with its duplicated event rows, comparison signal names)``;
    skips when the shared folder is absent."""
    folder = reference_dir(case)
    csv = folder / f"{case.name}.csv"
    names = folder / "comparisonSignals.txt"
    if not csv.exists() or not names.exists():
        pytest.skip(f"Modelica reference results not found at {folder} "
                    "(set CLUTCHSIM_SHARED to the shared folder)")
    signals = [s.strip() for s in names.read_text().splitlines() if s.strip()]
    signals = [s for s in signals if s != "time" and not s.endswith(EXCLUDED)]
    return pd.read_csv(csv), signals


def combine(table, terms: dict) -> np.ndarray:
    """``Σ factor · table[column]`` (a result or a reference frame)."""
    return sum(f * np.asarray(table[c], dtype=float) for c, f in terms.items())


def sample(t, y, tq, right):
    """``y`` (recorded at ``t``, nondecreasing, events written twice) interpolated at ``tq``
    from the right (``right``) or the left of an event instant."""
    i = np.searchsorted(t, tq, side="right" if right else "left")
    i = np.clip(i, 1, len(t) - 1)
    t0, t1 = t[i - 1], t[i]
    dt = t1 - t0
    w = np.where(dt > 0, (tq - t0) / np.where(dt > 0, dt, 1.0), 1.0 if right else 0.0)
    w = np.clip(w, 0.0, 1.0)
    return y[i - 1] + w * (y[i] - y[i - 1])


def _sides(t):
    """Per row: True for the right-hand row of a duplicated (event) instant or a plain
    row, False for the left-hand row."""
    right = np.ones(len(t), dtype=bool)
    dup = np.flatnonzero(np.diff(t) == 0)
    right[dup] = False
    return right


def switches(t, values, cancelled=None):
    """``[(t_lo, t_hi, from, to)]``: each switch lies in ``[t_lo, t_hi]`` — one instant for a
    located event (written twice), the output interval otherwise (the capacity of a clutch
    leaving 0 on a ramp).  Switches closer than CLUSTER_S are merged (an impact's −1 → 0 →
    +1 at one instant is −1 → +1); one that ends where it began is dropped, and its time
    appended to the list ``cancelled`` when one is given."""
    out = []
    for i in np.flatnonzero(values[1:] != values[:-1]) + 1:
        s = (float(t[i - 1]), float(t[i]), int(values[i - 1]), int(values[i]))
        if out and s[0] - out[-1][1] <= CLUSTER_S:
            s = (out[-1][0], s[1], out[-1][2], s[3])
            out.pop()
        if s[2] != s[3]:
            out.append(s)
        elif cancelled is not None:
            cancelled.append(s[0])
    return out


def _segments(t):
    """Row slices between the event instants (each event's left row closes a slice)."""
    starts = np.concatenate(([0], np.flatnonzero(np.diff(t) == 0) + 1, [len(t)]))
    return [slice(a, b) for a, b in pairwise(starts)]


def reference_mode(t, mode, slip):
    """The reference's mode in effect (see the module docstring): a ±1 stretch between two
    event instants whose relative speed stays within W_SMALL is stuck."""
    mode = np.asarray(mode, dtype=float).copy()
    if slip is None:
        return mode
    for seg in _segments(t):
        if np.max(np.abs(slip[seg])) <= W_SMALL:
            m = mode[seg]
            m[np.abs(m) == 1] = 0.0
    return mode


def derived_mode(t, slip):
    """A mode from a relative speed alone, per stretch between two event instants: 0 if it
    stays within W_SMALL, else the sign of its largest value (a direction changes only at
    an event)."""
    mode = np.zeros(len(t))
    for seg in _segments(t):
        s = slip[seg]
        k = int(np.argmax(np.abs(s)))
        mode[seg] = 0.0 if abs(s[k]) <= W_SMALL else np.sign(s[k])
    return mode


def our_mode(res, element, free=True):
    mode = np.where(res[f"{element}.locked"] > 0.5, 0.0, res[f"{element}.mode"])
    cap = f"capacity_{element}"
    if free and cap in res.signals:
        mode = np.where(res[cap] <= 0.0, 2.0, mode)
    return mode


def _compare_modes(name, kind, ref_sw, our_sw, our_cancelled=()):
    """``(Row, anchors [(t_ref, t_ours)])``: the same switches, each pair of intervals at
    most SWITCH_TOL apart; the pairs located to one instant (within CLUSTER_S) on both sides
    are the anchors of the time warp.  Our switches that undo themselves within CLUSTER_S
    (``our_cancelled``) fail: Dymola's event iteration writes such pairs, a located event
    of ours must not (a spurious event at round-off level)."""
    if our_cancelled:
        return Row(name, kind, np.inf, SWITCH_TOL,
                   f"FAIL our switches undo themselves within {CLUSTER_S} s at "
                   f"{[round(x, 9) for x in our_cancelled]}"), []
    if [s[2:] for s in ref_sw] != [s[2:] for s in our_sw]:
        shown = [(round(s[1], 7), *s[2:]) for s in ref_sw], \
            [(round(s[1], 7), *s[2:]) for s in our_sw]
        return Row(name, kind, np.inf, SWITCH_TOL,
                   f"FAIL sequence differs: reference {shown[0]} ours {shown[1]}"), []
    errs = [max(0.0, b[0] - a[1], a[0] - b[1]) for a, b in zip(ref_sw, our_sw)]
    anchors = [(a[0], b[0]) for a, b in zip(ref_sw, our_sw)
               if a[1] - a[0] <= CLUSTER_S and b[1] - b[0] <= CLUSTER_S]
    return Row(name, kind, max(errs, default=0.0), SWITCH_TOL, f"{len(ref_sw)} switches"), \
        anchors


def warp(t, anchors, t_end):
    """Reference times mapped onto ours around each matched switch: ``t_ref`` goes to
    ``t_ours``, linearly within ``2·|t_ours − t_ref|`` of it; farther rows keep their time
    (a switch that Dymola locates early does not shift the trajectory before it)."""
    pts = [(0.0, 0.0)]
    for a, b in sorted(anchors):
        d = 2.0 * abs(b - a)
        if d == 0.0:
            continue
        for x, y in ((a - d, a - d), (a, b), (a + d, a + d)):
            if x > pts[-1][0] and y > pts[-1][1]:
                pts.append((x, y))
    if t_end > pts[-1][0]:
        pts.append((t_end, t_end))
    xa, xb = np.array(pts).T
    return np.interp(t, xa, xb)


def compare(case: Case, overrides=()) -> Report:
    """Run ``case`` and compare it with its reference (see the module docstring)."""
    ref, names = load_reference(case)
    run = run_scenario(EXAMPLES / f"{case.example}.toml", case.model,
                       overrides=["outputs.angles=true", *overrides])
    res = run.result
    t_ref = ref["time"].to_numpy()
    rows, anchors = [], []
    for name in names:
        spec = case.signals.get(name)
        if isinstance(spec, Mode):
            slip = combine(ref, spec.slip) if spec.slip else None
            undone = []
            row, anc = _compare_modes(
                name, "mode", switches(t_ref, reference_mode(t_ref, ref[name], slip)),
                switches(res.t, our_mode(res, spec.element, spec.free), undone), undone)
            rows.append(row)
            anchors += anc
    for name, spec in case.derived.items():
        undone = []
        row, anc = _compare_modes(
            name, "derived mode", switches(t_ref, derived_mode(t_ref, combine(ref, spec.slip))),
            switches(res.t, our_mode(res, spec.element, spec.free), undone), undone)
        rows.append(row)
        anchors += anc
    tw = warp(t_ref, anchors, float(t_ref[-1]))
    right = _sides(t_ref)
    for name in names:
        spec = case.signals.get(name)
        if spec is None or isinstance(spec, Mode):
            continue
        r = ref[name].to_numpy(dtype=float)
        y = combine(res, spec)
        ours = np.where(right, sample(res.t, y, tw, True), sample(res.t, y, tw, False))
        span = float(np.max(r) - np.min(r))
        err = np.abs(ours - r)
        k = int(np.argmax(err))
        rows.append(Row(name, "value", float(err[k] / (span if span > 0 else 1.0)), SIGNAL_TOL,
                        f"range {span:.3g}, worst at t = {t_ref[k]:.6g} s"))
    unmapped = [n for n in names if n not in case.signals]
    return Report(case, rows, unmapped, res, run.metrics)


def assert_strict(case: Case) -> Report:
    """:func:`compare`, failing with the whole per-signal table on any violation."""
    report = compare(case)
    assert report.result.status == "completed", report.result.message
    assert not report.failures, "\n".join(report.failures) + "\n" + report.table()
    return report


def rel(a: str, b: str) -> dict:
    """``{b: 1, a: −1}``: Modelica's ``flange_b − flange_a`` of two of our columns."""
    return {b: 1.0, a: -1.0}


#: the reference cases: Modelica comparison signal -> our columns
CASES = {
    "coupled_clutches": Case(
        "Rotational/Examples/CoupledClutches", "coupled_clutches", {
            "J1.phi": {"phi_J1": 1.0}, "J1.w": {"omega_J1": 1.0},
            "clutch1.phi_rel": rel("phi_J1", "phi_J2"),
            "clutch1.w_rel": rel("omega_J1", "omega_J2"),
            "clutch2.phi_rel": rel("phi_J2", "phi_J3"),
            "clutch2.w_rel": rel("omega_J2", "omega_J3"),
            "clutch3.phi_rel": rel("phi_J3", "phi_J4"),
            "clutch3.w_rel": rel("omega_J3", "omega_J4"),
            "clutch1.mode": Mode("clutch1", {"clutch1.w_rel": 1.0}),
            "clutch2.mode": Mode("clutch2", {"clutch2.w_rel": 1.0}),
            "clutch3.mode": Mode("clutch3", {"clutch3.w_rel": 1.0}),
        }, model="coulomb-robust"),
    "one_way_clutch": Case(
        "Rotational/Examples/OneWayClutch", "one_way_clutch", {
            "inertiaIn.phi": {"phi_inertiaIn": 1.0}, "inertiaIn.w": {"omega_inertiaIn": 1.0},
            "oneWayClutch.phi_rel": rel("phi_inertiaIn", "phi_inertiaOut"),
            "oneWayClutch.w_rel": rel("omega_inertiaIn", "omega_inertiaOut"),
        }, derived={"oneWayClutch (stuck/sliding)": Mode(
            "oneWayClutch", {"oneWayClutch.w_rel": 1.0}, free=False)}),
    "lossy_gear_demo1": Case(
        "Rotational/Examples/LossyGearDemo1", "lossy_gear_demo1", {
            "Inertia2.phi": {"phi_Inertia2": 1.0}, "Inertia2.w": {"omega_Inertia2": 1.0},
            "gear.mode": Mode("gear", {"Inertia2.w": 2.0}),     # w_a = ratio · w_b
        }),
    "lossy_gear_demo2": Case(
        "Rotational/Examples/LossyGearDemo2", "lossy_gear_demo2", {
            "Inertia2.phi": {"phi_Inertia2": 1.0}, "Inertia2.w": {"omega_Inertia2": 1.0},
            "gear.mode": Mode("gear", {"Inertia2.w": 2.0}),
            "bearingFriction.mode": Mode("bearingFriction", {"Inertia2.w": 2.0}),
        }),
    "lossy_gear_demo3": Case(
        "Rotational/Examples/LossyGearDemo3", "lossy_gear_demo3", {
            "Inertia2.phi": {"phi_Inertia2": 1.0}, "Inertia2.w": {"omega_Inertia2": 1.0},
            "gear.mode": Mode("gear", {"Inertia2.w": 1.0}),
        }),
}
CASES["one_way_clutch_disengaged"] = Case(
    "Rotational/Examples/OneWayClutchDisengaged", "one_way_clutch_disengaged",
    CASES["one_way_clutch"].signals, CASES["one_way_clutch"].derived)

#: the cases that run as networks (tests/network)
NETWORK_CASES = {
    "simple_gear_shift": Case(
        "Rotational/Examples/SimpleGearShift", "simple_gear_shift", {
            "engine.phi": {"phi_engine": 1.0}, "engine.w": {"omega_engine": 1.0},
            "load.phi": {"phi_load": 1.0}, "load.w": {"omega_load": 1.0},
            # the ring has no inertia (no angle state): ring = ((1 + r)·carrier − sun)/r with
            # r = 1.5, so phi_rel = ring − sun = (5/3)·(phi_load − phi_engine)
            "clutch.phi_rel": {"phi_load": 5.0 / 3.0, "phi_engine": -5.0 / 3.0},
            "clutch.w_rel": {"w_slip_clutch": 1.0},
            "clutch.mode": Mode("clutch", {"clutch.w_rel": 1.0}),
            # the brake holds the ring: its speed = sun + clutch.w_rel
            "brake.mode": Mode("brake", {"engine.w": 1.0, "clutch.w_rel": 1.0}),
        }),
    "elastic_bearing": Case(
        "Rotational/Examples/ElasticBearing", "elastic_bearing", {
            "load.phi": {"phi_load": 1.0}, "load.w": {"omega_load": 1.0},
            "shaft.phi": {"phi_shaft": 1.0}, "shaft.w": {"omega_shaft": 1.0},
            # the mount from the ground (flange_a) to the housing (flange_b)
            "springDamper.phi_rel": {"phi_bearing": 1.0},
            "springDamper.w_rel": {"omega_housing": 1.0},
        }),
    "translational_friction": Case(
        "Translational/Examples/Friction", "translational_friction", {
            **{f"{m}.{q}": {f"{q}_{m}": 1.0} for m in ("mass", "stop1", "stop2")
               for q in ("s", "v")},
            "stop1.mode": Mode("stop1", {"stop1.v": 1.0}),
            "stop2.mode": Mode("stop2", {"stop2.v": 1.0}),
            "supportFriction.mode": Mode("friction", {"mass.v": 1.0}),
        }),
}
