"""Physics checks of every run of a network plant: friction dissipates, modes agree with slips.

The energy balance is not a check of physics: the books record whatever work the friction
elements do, created work included.  These checks look at what the elements did, on the
run's rows (output grid, and the rows the integrator writes at every event, before and
after each reset), with the solver's tolerances:

``mode_against_slip``
    A hybrid stick/slip element (coulomb-robust) that slides (mode ±1, unlocked) has a
    slip of the sign of its mode: ``mode·w >= 0``.
``slipping_while_stuck``
    A hybrid element in its stuck mode (mode 0) has zero slip, locked or not.
``stick_over_capacity``
    A locked element carries at most its static capacity: ``|τ| <= capacity``.
``negative_power``
    An element whose model is declared passive (:attr:`FrictionModel.passive`: memoryless,
    the force has the sign of the slip) never delivers power: ``τ·w >= 0``.
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

from dataclasses import dataclass

import numpy as np

__all__ = ["FrictionCheck", "Invariants", "Violation"]


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
    hybrid: bool        # coulomb-robust: mode state and lock flag
    passive: bool
    mode: int
    locked: int
    torque: int
    slip: int
    capacity: int


@dataclass(frozen=True)
class Invariants:
    """The physics checks of one plant layout (see the module docstring).  Called with a
    run's rows: ``check(ts, ys, outs, rtol, atol) -> [Violation, ...]``."""

    elements: tuple[FrictionCheck, ...]
    speeds: tuple[int, ...]
    w_friction: int
    all_passive: bool
    speed_unit: str
    effort_unit: str

    def __call__(self, ts, ys, outs, rtol: float, atol: float) -> list[Violation]:
        if ts.shape[0] == 0 or not self.elements:
            return []
        # a row followed by another at the same instant is the left limit before a reset
        # (the integrator writes one before and one after each reset): the event that
        # resets it is where the element leaves a state it may no longer hold
        last = np.ones(ts.shape[0], dtype=bool)
        last[:-1] = ts[1:] != ts[:-1]
        found: list[Violation] = []
        sp = ys[:, list(self.speeds)] if self.speeds else np.zeros((ts.shape[0], 1))
        w_scale = 1.0 + float(np.max(np.abs(sp))) if sp.size else 1.0
        if not np.isfinite(w_scale):
            return []
        w_soft = 100.0 * (atol + rtol * w_scale)
        w_hard = max(1e-3 * w_scale, 10.0 * w_soft)
        su, eu = self.speed_unit, self.effort_unit
        for c in self.elements:
            w = outs[:, c.slip]
            tau = outs[:, c.torque]
            if c.hybrid:
                mode = ys[:, c.mode]
                locked = ys[:, c.locked] > 0.5
                sliding = (~locked) & (mode != 0.0)
                self._worst(found, last, c.name, "mode_against_slip", ts,
                            np.where(sliding, -mode * w, 0.0), w_soft, w_hard, su,
                            lambda i: f"mode {mode[i]:+.0f} with slip {w[i]:.6g} {su}")
                self._worst(found, last, c.name, "slipping_while_stuck", ts,
                            np.where(mode == 0.0, np.abs(w), 0.0), w_soft, w_hard, su,
                            lambda i: f"stuck mode with slip {w[i]:.6g} {su}")
                cap = outs[:, c.capacity]
                t_scale = 1.0 + float(np.max(np.abs(cap)))
                t_soft = 100.0 * (atol + rtol * t_scale)
                t_hard = max(1e-3 * t_scale, 10.0 * t_soft)
                self._worst(found, last, c.name, "stick_over_capacity", ts,
                            np.where(locked, np.abs(tau) - np.abs(cap), 0.0), t_soft, t_hard,
                            eu, lambda i: f"locked with torque {tau[i]:.6g} {eu}, capacity "
                                          f"{cap[i]:.6g} {eu}")
            if c.passive:
                # slip against the force, where the power is negative
                against = np.where(tau * w < 0.0, np.abs(w), 0.0)
                self._worst(found, last, c.name, "negative_power", ts, against, w_soft, w_hard, su,
                            lambda i: f"torque {tau[i]:.6g} {eu} against slip {w[i]:.6g} "
                                      f"{su}: power {tau[i] * w[i]:.6g} W")
        if self.all_passive and self.w_friction >= 0 and ts.shape[0] > 1:
            wf = ys[:, self.w_friction]
            e_scale = 1.0 + float(np.max(np.abs(wf)))
            e_soft = 100.0 * (atol + rtol * e_scale)
            drop = np.maximum.accumulate(wf) - wf
            self._worst(found, last, "friction", "friction_work_decreases", ts, drop, e_soft,
                        max(1e-3 * e_scale, 10.0 * e_soft), "J",
                        lambda i: f"W_friction {wf[i]:.6g} J after a maximum of "
                                  f"{float(np.max(wf[:i + 1])):.6g} J")
        return found

    @staticmethod
    def _worst(found, last, name, invariant, ts, x, soft, hard, unit, detail) -> None:
        """Record the worst row of ``x`` (the violation per row, <= 0 where none) when it
        exceeds ``soft``: the first row past ``hard`` if any (where it went wrong), else
        the largest."""
        x = np.where(last, np.nan_to_num(x, nan=0.0), 0.0)
        over = np.flatnonzero(x > soft)
        if over.size == 0:
            return
        past = over[x[over] > hard]
        i = int(past[0]) if past.size else int(over[np.argmax(x[over])])
        found.append(Violation(name, invariant, float(ts[i]), float(x[i]), soft, hard, unit,
                               detail(i)))


def build_invariants(plan) -> Invariants:
    """The checks of ``plan``'s layout (after its module is rendered: the output names)."""
    dom = plan.domain
    out = {n: i for i, n in enumerate(plan.output_names)}
    elements = []
    for c in plan.fes:
        model = getattr(c, "model", None)
        if model is None or getattr(c, "lossy", False):
            continue
        need = (f"{dom.effort}_{c.name}", f"{dom.slip}_{c.name}", f"capacity_{c.name}")
        if any(n not in out for n in need):
            continue
        hybrid = model.hybrid and (c.name, "locked") in plan.state_index
        elements.append(FrictionCheck(
            c.name, hybrid, bool(getattr(model, "passive", False)),
            plan.state_index[(c.name, "z0")] if hybrid else -1,
            plan.state_index[(c.name, "locked")] if hybrid else -1,
            out[need[0]], out[need[1]], out[need[2]]))
    # every element that books into W_friction (lossy gears and bearing losses too) must be
    # passive for the total to be monotone
    all_passive = (bool(elements) and len(elements) == len(plan.fes)
                   and all(e.passive for e in elements))
    w_fric = plan.state_names.index("W_friction") if "W_friction" in plan.state_names else -1
    return Invariants(tuple(elements), tuple(range(plan.asm.n_v)), w_fric, all_passive,
                      dom.speed_unit, dom.effort_unit)
