"""The static characteristic of a clutch's release system: cushion spring in series with
the diaphragm (lever) spring, a touch point, an optional play.

The engagement travel ``x`` [m] (a signal: an electromechanical actuator's position, a pedal
map; counted from the open clutch in the engaging direction) first closes the air gap: up
to the *touch point* ``x_tp`` the linings carry nothing.  Beyond it the same clamp force
``F`` passes through the cushion (lining) spring, compressed by ``c(F)``, and the diaphragm
(lever) spring as seen at the bearing, deflected by ``d(F)``: the travels add,
``x − x_tp = c(F) + d(F)``.  Both characteristics are tables of force against deflection,
starting at (0, 0), with forces strictly increasing (monotone: a spring that gives way
would make the composition multi-valued).  The composed table ``F(x − x_tp)`` is built once
per parameter set (:meth:`ReleaseSystem.pack`): every force level of either table, each
with its two deflections interpolated and added.  It is held at its last force beyond its
last travel (the stops of the pressure plate).

Hysteresis (optional, ``hysteresis`` > 0): a play of that width on the travel, the
Preisach *play operator* written as a state ``x_e`` the integrator carries,
``dx_e/dt = (x − x_e ∓ h/2)/t_play`` outside the band ``|x − x_e| <= h/2`` and 0 inside:
engaging reads the characteristic at ``x − h/2``, releasing at ``x + h/2``: a band of
travel hysteresis, a simple form for the friction in the fingers' pivots and on the
bearing's sleeve.  The force is ``F(x_e − x_tp)``; ``t_play`` is small against the
actuation, and the band is continuous, so the integrator needs no event for it.

Signal ``<name>.clamp_force`` [N]: a clutch reads it as its command with ``clamp_reference``.
"""

from __future__ import annotations

import numpy as np

from ..component import Component
from ..spec import Param, table_entry
from ._laws import signal_arg


def monotone_spring(owner: str, key: str, xs, fs, xname: str) -> tuple[np.ndarray, np.ndarray]:
    """A spring characteristic (deflections, forces) as arrays, or a ValueError naming
    ``owner``, ``key``, the entry, its value and the rule: at least 2 points, equal
    lengths, starting at (0, 0), deflections and forces strictly increasing."""
    x = np.asarray(xs, dtype=float).ravel()
    f = np.asarray(fs, dtype=float).ravel()
    if x.size < 2 or x.size != f.size:
        raise ValueError(f"{owner}: {key} needs at least 2 points and equal lengths (got "
                         f"{x.size} and {f.size})")
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(f))):
        raise ValueError(f"{owner}: {key} has non-finite entries")
    if x[0] != 0.0 or f[0] != 0.0:
        raise ValueError(f"{owner}: {key} must start at {xname} = 0 m, force = 0 N (got "
                         f"{x[0]:g} m, {f[0]:g} N)")
    for arr, name, unit, what in ((x, xname, "m", "deflection"), (f, "force", "N", "force")):
        for i in range(1, arr.size):
            if not arr[i] > arr[i - 1]:
                raise ValueError(f"{owner}: {key}.{name}[{i}] = {arr[i]:g} {unit} must be "
                                 f"greater than {key}.{name}[{i - 1}] = {arr[i - 1]:g} {unit} "
                                 f"(the characteristic must be monotone: the {what} "
                                 "strictly increasing)")
    return x, f


def series(cushion, spring) -> tuple[np.ndarray, np.ndarray]:
    """(travel, force) of two springs in series (same force, deflections add), at every
    force level of either table up to the smaller of their largest forces."""
    (xc, fc), (xs, fs) = cushion, spring
    top = min(fc[-1], fs[-1])
    f = np.unique(np.concatenate([fc[fc <= top], fs[fs <= top]]))
    return np.interp(f, fc, xc) + np.interp(f, fs, xs), f


class ReleaseSystem(Component):
    """Clamp force against engagement travel (see the module docstring)."""

    kind = "release_system"
    title = "release system: cushion spring in series with the diaphragm spring, touch point"
    flanges = ()
    signal_keys = ("travel",)
    params = (
        Param("touch_point", "m", "engagement travel at which the linings start to carry "
              "load", default=0.0, low=0.0),
        Param("hysteresis", "m", "width of the play on the travel (0: none)", default=0.0,
              low=0.0),
        Param("t_play", "s", "time constant of the play state (small against the "
              "actuation)", default=1e-3, low=0.0, strict=True),
    )

    def __init__(self, name, travel: str, cushion, spring=None, **values):
        super().__init__(name, **values)
        self.travel = signal_arg(self.label, "travel", travel, "the engagement travel [m]")
        self.cushion = monotone_spring(self.label, "cushion", *cushion, "compression")
        self.spring = (None if spring is None else
                       monotone_spring(self.label, "spring", *spring, "deflection"))
        self.characteristic = (self.cushion if self.spring is None
                               else series(self.cushion, self.spring))
        # the play's state carries the characteristic's input: its force follows from it
        self.feedthrough = not self.has_play

    @property
    def has_play(self) -> bool:
        return self.hysteresis > 0.0

    def options(self):
        return (self.travel, len(self.characteristic[0]), self.has_play)

    def described_values(self):
        out = {"cushion": table_entry("cushion spring: compression → force", self.cushion[0],
                                      "m", self.cushion[1], "N")}
        if self.spring is not None:
            out["spring"] = table_entry("diaphragm spring: deflection → force",
                                        self.spring[0], "m", self.spring[1], "N")
        return out

    def inputs(self):
        return (self.travel,)

    def input_units(self):
        return {self.travel: "m"}

    def signals(self):
        return {"clamp_force": "N"}

    def pack(self):
        d = dict(self.values)
        d["characteristic"] = np.concatenate(self.characteristic)
        return d

    def clamp_force(self, x) -> np.ndarray:
        """The static characteristic without play: clamp force [N] at travel ``x`` [m]."""
        xt, f = self.characteristic
        return np.interp(np.asarray(x, dtype=float) - self.touch_point, xt, f)

    def state_layout(self):
        return [("xe", f"{self.name}.travel_played", "m")] if self.has_play else []

    def initial_state(self, ctx):
        return [ctx.input0.get(self.travel, 0.0)] if self.has_play else []

    def _force(self, e, x):
        return e.lookup("characteristic", f"{x} - {e.par('touch_point')}", "f")

    def emit_signals(self, e):
        if self.has_play:
            f, df = self._force(e, e.x("xe"))
            e.signal("clamp_force", f)
            e.dsignal("clamp_force", e.kx("xe"), df)

    def emit(self, e):
        P = e.par
        x = e.u(self.travel)
        if not self.has_play:
            f, df = self._force(e, x)
            e.signal("clamp_force", f)
            for key, d in e.chain(self.travel, df):
                e.dsignal("clamp_force", key, d)
            return
        xe = e.x("xe")
        gap = e.let("gap", f"{x} - {xe}")
        half = e.let("half", f"0.5 * {P('hysteresis')}")
        e.deriv("xe", f"(({gap} - {half}) if {gap} > {half} else (({gap} + {half}) if "
                      f"{gap} < -{half} else 0.0)) / {P('t_play')}")
        g = e.let("g", f"1.0 if ({gap} > {half} or {gap} < -{half}) else 0.0")
        e.dderiv("xe", e.kx("xe"), f"-{g} / {P('t_play')}")
        for key, d in e.chain(self.travel, f"{g} / {P('t_play')}"):
            e.dderiv("xe", key, d)
