"""Physics checks of every run of a network plant: friction dissipates, modes agree with slips.

The energy balance is not a check of physics: the books record whatever work the friction
elements do, created work included.  These checks look at what the elements did, on the
run's rows (output grid, and the rows the integrator writes at every event, before and
after each reset), with the solver's tolerances:

``mode_against_slip``
    A hybrid stick/slip element (coulomb-robust) that slides (mode ±1, unlocked) has a
    slip of the sign of its mode: ``mode·w >= 0``, where its capacity is not zero (with
    none it has no force in either mode: a brake at zero command whose stop was decided
    by the stick force of a naive neighbour in its sliding mode, at zero slip and without
    a solution there, kept mode -1 while its slip went to +3e-5 rad/s; fuzzed networks).
    When the capacity rises again with a mode against the slip, its force does work
    against the slip, and the check sees it.  A freewheel
    (:attr:`FrictionModel.forward_only`: the one-way clutch) that is not locked never
    slides backwards: ``w >= 0``.  A lossy gear's loss element (mode ±1 rolling forward
    or backward, 0 stuck) is checked as a hybrid element.
``slipping_while_stuck``
    A hybrid element in its stuck mode (mode 0) has zero slip, locked or not.
``stick_over_capacity``
    A locked element carries at most its static capacity: ``|τ| <= capacity`` (a stuck
    lossy gear holds any torque: not checked).
``negative_power``
    An element whose model is declared passive (:attr:`FrictionModel.passive`: memoryless,
    the force has the sign of the slip) never delivers power: ``τ·w >= 0``; nor does a
    lossy gear's loss (``L·w >= 0``).
``friction_work_decreases``
    When every friction element is passive, the total friction work ``W_friction`` never
    decreases.

Each check measures its violation in a unit of its own (rad/s or m/s of slip against the
mode or the force, N·m or N over the capacity, J of friction work lost) and compares it
with two limits.  Below ``soft`` it is round-off and event-location tolerance; between
``soft`` and ``hard`` the run gets a warning with the element, the time and the values;
above ``hard`` the result is wrong and the run's outcome is ``invariant_violated``.

``soft`` is 100 times the solver's error tolerance at the run's scale (``atol + rtol·X``,
``X`` the largest speed, capacity or work of the run); ``hard`` is 1e-3 of that scale
(at least ten times ``soft``).  The located event is where they matter: an element that
stops is found within the event tolerance of the true instant, where its slip has just
crossed zero.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from .._jit import jit

__all__ = ["CHECKS", "FrictionCheck", "Invariants", "Violation", "build_invariants", "scan"]


@dataclass(frozen=True)
class Violation:
    """One broken invariant: the element, the check, where and by how much."""

    element: str
    invariant: str
    t: float
    value: float
    soft: float
    hard: float
    unit: str
    detail: str

    @property
    def fatal(self) -> bool:
        """Beyond the hard limit: the result is wrong."""
        return self.value > self.hard

    @property
    def text(self) -> str:
        return (f"{self.element}: {self.invariant.replace('_', ' ')} at t = {self.t:.9g} s "
                f"({self.detail}; {self.value:.3g} {self.unit} against a tolerance of "
                f"{self.soft:.3g} {self.unit})")


@dataclass(frozen=True)
class FrictionCheck:
    """Where the checks read one friction element: state indices (``-1``: none) and output
    indices of its torque, slip, static capacity and stick torque."""

    name: str
    hybrid: bool        # coulomb-robust or a lossy gear: mode state and lock flag
    passive: bool
    mode: int
    locked: int
    torque: int
    slip: int
    capacity: int       # -1: none (a lossy gear holds any torque when stuck)
    forward_only: bool = False  # a freewheel: lock flag, the slip never negative while free


#: the checks, in the order of the rows of a scan's table (:func:`scan`)
CHECKS = ("mode_against_slip", "slipping_while_stuck", "stick_over_capacity",
          "negative_power", "friction_work_decreases")
N_CHECKS = len(CHECKS)
#: columns of a scan's table: row, time, violation, soft and hard limits, two values there
R_ROW, R_T, R_VALUE, R_SOFT, R_HARD, R_A, R_B = range(7)
N_R = 7
#: columns of the element table: hybrid, passive, mode, locked (states), torque, slip,
#: capacity (outputs), forward only
E_HYBRID, E_PASSIVE, E_MODE, E_LOCKED, E_TORQUE, E_SLIP, E_CAP, E_FORWARD = range(8)
N_E = 8


@jit
def _record(tab, k, i, t, x, soft, hard, a, b):
    """Keep row ``i`` as check ``k``'s worst so far: the first row past ``hard`` wins (where
    it went wrong), else the largest violation past ``soft``."""
    if not x > soft:
        return
    old = tab[k, R_VALUE]
    if old > tab[k, R_HARD] and tab[k, R_ROW] >= 0:
        return                       # the first fatal row is kept
    if x > hard or tab[k, R_ROW] < 0 or x > old:
        tab[k, R_ROW], tab[k, R_T], tab[k, R_VALUE] = i, t, x
        tab[k, R_SOFT], tab[k, R_HARD], tab[k, R_A], tab[k, R_B] = soft, hard, a, b


@jit
def scan(ts, ys, outs, el, speeds, w_fric, all_passive, rtol, atol, tab):
    """The checks of the module docstring over a run's rows, compiled (single runs and a
    sweep's batch share it).  ``el`` (m, N_E): the element table (``E_*``); ``speeds``:
    the speed states; ``w_fric``: the state of ``W_friction`` (-1: none).  Writes ``tab``
    (``(m + 1)·N_CHECKS``, ``N_R``): per element and check (then the total friction work)
    the worst row, ``-1`` in ``R_ROW`` where the check passed."""
    n = ts.shape[0]
    m = el.shape[0]
    for r in range(tab.shape[0]):
        tab[r, R_ROW] = -1.0
        tab[r, R_VALUE] = 0.0
        tab[r, R_HARD] = 0.0
    if n == 0:
        return
    w_scale = 0.0
    for i in range(n):
        for j in speeds:
            w_scale = max(w_scale, abs(ys[i, j]))
    w_scale += 1.0
    if not math.isfinite(w_scale):
        return
    w_soft = 100.0 * (atol + rtol * w_scale)
    w_hard = max(1e-3 * w_scale, 10.0 * w_soft)
    for e in range(m):
        o = e * N_CHECKS
        c_scale = 0.0
        has_cap = el[e, E_CAP] >= 0      # a lossy gear has no capacity: it holds any torque
        for i in range(n):
            if has_cap:
                c_scale = max(c_scale, abs(outs[i, el[e, E_CAP]]))
        c_scale += 1.0
        t_soft = 100.0 * (atol + rtol * c_scale)
        t_hard = max(1e-3 * c_scale, 10.0 * t_soft)
        for i in range(n):
            # a row followed by another at the same instant is the left limit before a
            # reset (the integrator writes one before and one after each): the event that
            # resets it is where the element leaves a state it may no longer hold
            if i + 1 < n and ts[i + 1] == ts[i]:
                continue
            w = outs[i, el[e, E_SLIP]]
            tau = outs[i, el[e, E_TORQUE]]
            if el[e, E_HYBRID]:
                mode = ys[i, el[e, E_MODE]]
                locked = ys[i, el[e, E_LOCKED]] > 0.5
                # a sliding element's mode is the direction of its force; with no
                # capacity it has no force, and its mode is not physics (below)
                free = has_cap and outs[i, el[e, E_CAP]] == 0.0
                if not locked and mode != 0.0 and not free:
                    _record(tab, o, i, ts[i], -mode * w, w_soft, w_hard, mode, w)
                if mode == 0.0:
                    _record(tab, o + 1, i, ts[i], abs(w), w_soft, w_hard, mode, w)
                if locked and has_cap:
                    cap = outs[i, el[e, E_CAP]]
                    _record(tab, o + 2, i, ts[i], abs(tau) - abs(cap), t_soft, t_hard, tau,
                            cap)
            if el[e, E_FORWARD] and not ys[i, el[e, E_LOCKED]] > 0.5:
                # a = 2: the freewheel's row (no mode state), named so in the text
                _record(tab, o, i, ts[i], -w, w_soft, w_hard, 2.0, w)
            if el[e, E_PASSIVE] and tau * w < 0.0:
                _record(tab, o + 3, i, ts[i], abs(w), w_soft, w_hard, tau, w)
    if all_passive and w_fric >= 0 and n > 1:
        e_scale = 0.0
        for i in range(n):
            e_scale = max(e_scale, abs(ys[i, w_fric]))
        e_scale += 1.0
        e_soft = 100.0 * (atol + rtol * e_scale)
        e_hard = max(1e-3 * e_scale, 10.0 * e_soft)
        top = ys[0, w_fric]
        for i in range(n):
            top = max(top, ys[i, w_fric])
            _record(tab, m * N_CHECKS + 4, i, ts[i], top - ys[i, w_fric], e_soft, e_hard,
                    ys[i, w_fric], top)


@dataclass(frozen=True)
class Invariants:
    """The physics checks of one plant layout (see the module docstring).  Called with a
    run's rows: ``check(ts, ys, outs, rtol, atol) -> [Violation, ...]``; :attr:`arrays`
    and :meth:`violations` are the same checks for a compiled loop that runs many
    variants (:func:`scan` on each, the table read back here)."""

    elements: tuple[FrictionCheck, ...]
    speeds: tuple[int, ...]
    w_friction: int
    all_passive: bool
    speed_unit: str
    effort_unit: str

    @cached_property
    def arrays(self) -> tuple:
        """``(el, speeds, w_fric, all_passive, table rows)``: :func:`scan`'s arguments (made
        once per layout: every run of the plant reads them)."""
        el = np.array([[c.hybrid, c.passive, c.mode, c.locked, c.torque, c.slip, c.capacity,
                        c.forward_only] for c in self.elements],
                      dtype=np.int64).reshape(-1, N_E)
        return (el, np.array(self.speeds, dtype=np.int64), int(self.w_friction),
                bool(self.all_passive), (len(self.elements) + 1) * N_CHECKS)

    def __call__(self, ts, ys, outs, rtol: float, atol: float) -> list[Violation]:
        if ts.shape[0] == 0 or not self.elements:
            return []
        el, speeds, w_fric, all_passive, rows = self.arrays
        tab = np.empty((rows, N_R))
        scan(ts, ys, outs, el, speeds, w_fric, all_passive, float(rtol), float(atol), tab)
        return self.violations(tab)

    def violations(self, tab) -> list[Violation]:
        """The violations a :func:`scan` table holds, earliest first."""
        if not (tab[:, R_ROW] >= 0).any():
            return []
        su, eu = self.speed_unit, self.effort_unit
        words = {
            0: lambda a, b: (f"free freewheel sliding backwards, slip {b:.6g} {su}" if a == 2
                             else f"mode {a:+.0f} with slip {b:.6g} {su}"),
            1: lambda a, b: f"stuck mode with slip {b:.6g} {su}",
            2: lambda a, b: f"locked with torque {a:.6g} {eu}, capacity {b:.6g} {eu}",
            3: lambda a, b: f"torque {a:.6g} {eu} against slip {b:.6g} {su}: power "
                            f"{a * b:.6g} W",
            4: lambda a, b: f"W_friction {a:.6g} J after a maximum of {b:.6g} J"}
        units = (su, su, eu, su, "J")
        found = []
        for r in range(tab.shape[0]):
            if tab[r, R_ROW] < 0:
                continue
            e, k = divmod(r, N_CHECKS)
            name = self.elements[e].name if e < len(self.elements) else "friction"
            found.append(Violation(name, CHECKS[k], float(tab[r, R_T]),
                                   float(tab[r, R_VALUE]), float(tab[r, R_SOFT]),
                                   float(tab[r, R_HARD]), units[k],
                                   words[k](tab[r, R_A], tab[r, R_B])))
        return sorted(found, key=lambda v: v.t)


def build_invariants(plan) -> Invariants:
    """The checks of ``plan``'s layout (after its module is rendered: the output names)."""
    dom = plan.domain
    out = {n: i for i, n in enumerate(plan.output_names)}
    elements = []
    for c in plan.fes:
        model = getattr(c, "model", None)
        if model is None:
            continue
        if getattr(c, "lossy", False):
            # a lossy gear's loss element: rolling (mode ±1) with its slip, stuck (mode 0)
            # at zero slip, its loss L·w >= 0 (the laws are continuous in the torque and
            # dissipate in both power-flow directions); it holds any torque when stuck
            need = (f"T_loss_{c.name}", f"{dom.slip}_{c.name}")
            if any(n not in out for n in need) or (c.name, "locked") not in plan.state_index:
                continue
            elements.append(FrictionCheck(
                c.name, True, True, plan.state_index[(c.name, "z0")],
                plan.state_index[(c.name, "locked")], out[need[0]], out[need[1]], -1))
            continue
        need = (f"{dom.effort}_{c.name}", f"{dom.slip}_{c.name}", f"capacity_{c.name}")
        if any(n not in out for n in need):
            continue
        has_lock = (c.name, "locked") in plan.state_index
        hybrid = model.lockable and has_lock
        forward = model.forward_only and has_lock
        elements.append(FrictionCheck(
            c.name, hybrid, bool(getattr(model, "passive", False)),
            plan.state_index[(c.name, "z0")] if hybrid else -1,
            plan.state_index[(c.name, "locked")] if hybrid or forward else -1,
            out[need[0]], out[need[1]], out[need[2]], forward_only=forward))
    # every element that books into W_friction (lossy gears too) must be passive for the
    # total to be monotone
    all_passive = (bool(elements) and len(elements) == len(plan.fes)
                   and all(e.passive for e in elements))
    w_fric = plan.state_names.index("W_friction") if "W_friction" in plan.state_names else -1
    return Invariants(tuple(elements), tuple(range(plan.asm.n_v)), w_fric, all_passive,
                      dom.speed_unit, dom.effort_unit)
