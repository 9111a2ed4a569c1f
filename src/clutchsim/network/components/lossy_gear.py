"""A gear with mesh efficiency and bearing friction that can stick (Modelica ``LossyGear``),
and the gearbox: selectable ratios, a final drive, scheduled shifts and the same losses.

Both are an ideal gear ``ω_a − ω_s = ratio·(ω_b − ω_s)`` plus a *loss element*: a
switching element on the slip ``w = ω_a − ω_s`` whose torque ``L`` [N·m] (the loss referred
to flange a) acts as ``−L`` on flange a and ``+L`` on the support.  Flange a takes ``T_a``
from its side and flange b delivers ``ratio·(T_a − L)``.  While the gear rolls, ``L``
depends on the direction of the power flow, decided by the sign of ``T_a ∓ τ_bf,a``
(Pelchen et al. 2002)::

    forward  (w > 0):  L = (1 − η1)·T_a + τ_bf1     if T_a − τ_bf,a >= 0 (a drives b)
                       L = (1 − 1/η2)·T_a + τ_bf2   otherwise            (b drives a)
    backward (w < 0):  L = (1 − 1/η2)·T_a − τ_bf2   if T_a + τ_bf,a >= 0
                       L = (1 − η1)·T_a − τ_bf1     otherwise

with ``τ_bf,a = (τ_bf1 − τ_bf2)/(η1 − 1/η2)`` (``τ_bf1/2`` when both efficiencies are 1),
which makes ``L`` continuous in ``T_a``.  ``T_a`` itself depends on ``L`` through the
accelerations; the generated plant solves that linear loop in closed form
(:func:`clutchsim.network._kernels.lossy_solve`).  At ``w = 0`` the gear *sticks* (a
locked element, like a brake) while the torque it holds stays between the laws' backward
and forward values at ``|w| = 0`` (Modelica's ``tauLossMin_m``/``tauLossMax_p``); beyond
them it rolls.  The loss power ``L·w >= 0`` is booked in ``W_friction``.

References
----------
Pelchen C., Schweiger C., Otter M., "Modeling and simulating the efficiency of gearboxes
and of planetary gearboxes", 2nd International Modelica Conference, 2002, pp. 257-266;
Modelica Standard Library 4.x, ``Modelica.Mechanics.Rotational.Components.LossyGear``.
"""

from __future__ import annotations

import numpy as np

from ..component import Component
from ..spec import Param, table_entry
from .ideal_gear import IdealGear

#: columns of a loss table
LOSS_COLUMNS = ("speed", "eta_mf1", "eta_mf2", "tau_bf1", "tau_bf2")
#: what each column after ``speed`` [rad/s] gives, and its unit
LOSS_COLUMN_DOCS = {"eta_mf1": ("efficiency, power flowing from a to b", "-"),
                    "eta_mf2": ("efficiency, power flowing from b to a", "-"),
                    "tau_bf1": ("bearing friction torque, power flowing from a to b", "N·m"),
                    "tau_bf2": ("bearing friction torque, power flowing from b to a", "N·m")}


class _LossModel:
    """What the generated plant reads of a loss element (the role a friction model plays
    for a clutch): one state ``mode`` (+1 rolling forward, −1 backward, 0 stuck), the
    events ``stop`` and ``breakaway``, and its table as the packed ``model`` block."""

    name = "lossy-gear"
    code = -1
    uses_stick_force = True
    #: the capabilities a friction model declares (FrictionModel): its force is solved from
    #: the torque it transmits, so the plant locks and frees it as its own (the element's
    #: ``lockable``), not as a stick/slip model
    lockable = False
    jumps = False
    smooth_at_events = False
    n_states = 1
    n_events = 2

    def __init__(self, table):
        self.table = table

    def state_names(self):
        return ("mode",)

    def state_units(self, domain="rotational"):
        return ("-",)

    def event_names(self):
        return ("stop", "breakaway")

    def event_directions(self):
        return np.array([-1, -1])

    def pack(self):
        return np.concatenate([np.asarray(c, dtype=float) for c in self.table])


def check_loss_table(owner: str, rows) -> tuple:
    """The rows ``(speed, eta_mf1, eta_mf2, tau_bf1, tau_bf2)`` as five columns, or a
    ValueError naming ``owner``, the entry, its value and the rule."""
    rows = [tuple(float(v) for v in r) for r in rows]
    if not rows:
        raise ValueError(f"{owner}: loss_table needs at least one row")
    for i, r in enumerate(rows):
        if len(r) != 5:
            raise ValueError(f"{owner}: loss_table row {i} has {len(r)} entries; each row is "
                             f"({', '.join(LOSS_COLUMNS)})")
        w, e1, e2, b1, b2 = r
        if not all(np.isfinite(r)):
            raise ValueError(f"{owner}: loss_table row {i} has non-finite entries")
        if i == 0 and w < 0.0:
            raise ValueError(f"{owner}: loss_table speed[0] = {w:g} rad/s must be >= 0 (the "
                             "table is read at |w|)")
        if i > 0 and w <= rows[i - 1][0]:
            raise ValueError(f"{owner}: loss_table speed[{i}] = {w:g} rad/s must be greater "
                             f"than speed[{i - 1}] = {rows[i - 1][0]:g} rad/s")
        for c, v in (("eta_mf1", e1), ("eta_mf2", e2)):
            if not 0.0 < v <= 1.0:
                raise ValueError(f"{owner}: loss_table {c}[{i}] = {v:g} must be in (0, 1] "
                                 "(an efficiency of 0 cannot transmit power)")
        for c, v in (("tau_bf1", b1), ("tau_bf2", b2)):
            if v < 0.0:
                raise ValueError(f"{owner}: loss_table {c}[{i}] = {v:g} N·m must be >= 0")
    return tuple(tuple(r[k] for r in rows) for k in range(5))


class LossyGear(Component):
    """A gear with losses that can stick (see the module docstring).

    ``loss_table``: rows ``(speed [rad/s], eta_mf1 [-], eta_mf2 [-], tau_bf1 [N·m],
    tau_bf2 [N·m])``, read at ``|w|`` and held outside.  A table without losses (all rows
    ``(w, 1, 1, 0, 0)``) makes an ideal gear with no loss element.  Outputs:
    ``T_<name>`` [N·m], the torque passed on at flange b, ``T_loss_<name>`` [N·m], the
    loss ``L``, and ``P_<name>`` [W], the loss power.
    """

    kind = "lossy_gear"
    title = "gear with mesh efficiency and bearing friction that can stick"
    flanges = ("a", "b", "support")
    grounded = ("support",)
    params = IdealGear.params   # the ratio, as the ideal gear declares it
    lockable = True
    lossy = True
    side_a = "support"
    side_b = "a"
    #: the flange the gear drives (the ratio's flange b)
    out_flange = "b"

    def __init__(self, name, loss_table=((0.0, 1.0, 1.0, 0.0, 0.0),), locked0=None,
                 **values):
        super().__init__(name, **values)
        self.loss_columns = check_loss_table(self.label, loss_table)
        self.model = _LossModel(self.loss_columns)
        self.locked0 = locked0
        self.heat = ()
        self.has_drag = False

    @property
    def friction(self) -> bool:
        """A loss element exists (the table has losses)."""
        c = self.loss_columns
        return not (all(v == 1.0 for v in c[1] + c[2]) and all(v == 0.0 for v in c[3] + c[4]))

    def gear_ratio(self) -> float:
        """``ω_a/ω_b`` [-] now."""
        return self.ratio

    def options(self):
        return (len(self.loss_columns[0]), self.friction)

    def described_values(self):
        speed, *cols = self.loss_columns
        return {f"loss_table.{name}": table_entry(f"{doc} over the speed of flange a", speed,
                                                  "rad/s", col, unit)
                for (name, (doc, unit)), col in zip(LOSS_COLUMN_DOCS.items(), cols)}

    def constraints(self):
        r = self.gear_ratio()
        return [{"a": 1.0, self.out_flange: -r, "support": r - 1.0}]

    def slip(self):
        return {"a": 1.0, "support": -1.0}

    def heat_shares(self):
        return ()

    def scale_partials_of(self, e_index):
        return []

    def pack(self):
        d = dict(self.values)
        if self.friction:
            d["model"] = self.model.pack()
        return d

    def state_layout(self):
        if not self.friction:
            return []
        return [("z0", f"{self.name}.mode", "-"), ("locked", f"{self.name}.locked", "-")]

    def initial_state(self, ctx):
        if not self.friction:
            return []
        w = ctx.speed(self.name, "a") - ctx.speed(self.name, "support")
        locked = bool(self.locked0) if self.locked0 is not None else w == 0.0
        return [0.0 if locked else (1.0 if w >= 0.0 else -1.0), 1.0 if locked else 0.0]

    def emit(self, e):
        e.output(f"T_{self.name}", "N·m", f"-{e.constraint_torque(0, self.out_flange)}")
        if not self.friction:
            return
        i = e.g.plan.fe_index[self.name]
        e.line(f"sc{i} = 1.0")
        e.output(f"T_loss_{self.name}", "N·m", f"fT{i}")
        e.output(f"w_slip_{self.name}", "rad/s", f"s{i}")
        e.output(f"T_stick_{self.name}", "N·m", f"Fe{i}")
        e.output(f"P_{self.name}", "W", f"fT{i} * s{i}")


class Gearbox(LossyGear):
    """A rigid gearbox: selectable ratios times a final drive, scheduled shifts, and the
    losses of :class:`LossyGear` with a speed-independent law (``efficiency`` with power
    from a to b, ``efficiency_reverse`` back, a ``drag_torque`` at flange a).

    A shift at ``t`` changes the ratio; an ideal synchroniser brings the two sides to the
    new ratio in an instant, conserving the angular momentum of everything it joins (the
    kinetic energy it removes is booked as ``W_sync``).  Open the clutch around a shift.
    Output ``ratio_<name>`` [-]: the overall ratio of the engaged gear.
    """

    kind = "gearbox"
    title = "gearbox with selectable ratios, final drive, shifts and mesh losses"
    params = (
        Param("gear", "-", "gear engaged at the start (1-based)", default=1.0, low=1.0),
        Param("final_drive", "-", "final drive ratio multiplied into every gear",
              default=1.0, low=0.0, strict=True, high=100.0),
        Param("efficiency", "-", "mesh efficiency with power from flange a to b",
              default=1.0, low=0.0, high=1.0, strict=True),
        Param("efficiency_reverse", "-", "mesh efficiency with power from b back to a "
              "(default: efficiency)", default=1.0, low=0.0, high=1.0, strict=True),
        Param("drag_torque", "N·m", "speed-independent drag referred to flange a",
              default=0.0, low=0.0, high=1e6),
    )

    def __init__(self, name, ratios, shifts=(), **values):
        rs = tuple(float(r) for r in ratios)
        if not rs or any(not np.isfinite(r) or r <= 0.0 for r in rs):
            raise ValueError(f"gearbox {name!r}: ratios = {list(ratios)!r} must list at least "
                             "one gear, each ratio > 0")
        self.ratios = rs
        Component.__init__(self, name, **values)
        if "efficiency_reverse" not in values:
            self.values["efficiency_reverse"] = self.efficiency
        self._check_gear(self.gear, "gear")
        sh = []
        for t, g in shifts:
            t = float(t)
            if not np.isfinite(t) or t <= 0.0:
                raise ValueError(f"{self.label}: shift time {t:g} s must be > 0")
            self._check_gear(g, "shifts")
            sh.append((t, int(g)))
        self.shifts = tuple(sorted(sh))
        eta, rev, drag = self.efficiency, self.efficiency_reverse, self.drag_torque
        self.loss_columns = ((0.0,), (eta,), (rev,), (drag,), (drag,))
        self.model = _LossModel(self.loss_columns)
        self.locked0 = None
        self.heat = ()
        self.has_drag = False

    def _check_gear(self, g, key):
        if isinstance(g, bool) or float(g) != int(g) or not 1 <= int(g) <= len(self.ratios):
            raise ValueError(f"{self.label}: {key}: gear {g!r} does not exist; this gearbox "
                             f"has {len(self.ratios)} gears (1..{len(self.ratios)})")

    def gear_ratio(self) -> float:
        return self.ratios[int(self.gear) - 1] * self.final_drive

    def options(self):
        return (len(self.ratios), self.friction, len(self.shifts))

    def described_values(self):
        # its losses are the scalar parameters (efficiency, drag_torque): no loss table
        out = {"ratios": {"value": ", ".join(f"{r:g}" for r in self.ratios), "unit": "-",
                          "description": "gear ratios ω_a/ω_b of gears 1, 2, ... (times "
                          "final_drive)", "values": list(self.ratios)}}
        if self.shifts:
            out["shifts"] = {"value": ", ".join(f"gear {g} at {t:g} s" for t, g in self.shifts),
                             "unit": "s", "description": "scheduled shifts (time, gear)",
                             "values": [list(s) for s in self.shifts]}
        return out

    def schedule(self) -> tuple:
        """``(time [s], values)`` at which this component's values change (shifts)."""
        return tuple((t, {"gear": float(g)}) for t, g in self.shifts)

    def format_values(self) -> dict:
        out = dict(self.values)
        for j, (t, g) in enumerate(self.shifts):
            out[f"shift_time{j}"], out[f"shift_gear{j}"] = t, g
        return out

    def pack(self):
        d = super().pack()
        d["ratio_now"] = self.gear_ratio()
        for j, (t, _g) in enumerate(self.shifts):
            d[f"shift_time{j}"] = t
        return d

    def emit(self, e):
        super().emit(e)
        e.output(f"ratio_{self.name}", "-", e.par("ratio_now"))
        e.output(f"gear_{self.name}", "-", e.par("gear"))
        for j in range(len(self.shifts)):
            e.event(f"{self.name}: shift to gear {{shift_gear{j}}} at {{shift_time{j}:g}} s",
                    1, f"t - {e.par(f'shift_time{j}')}", "bank")
