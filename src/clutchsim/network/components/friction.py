"""Friction elements with any clutchsim friction model: a clutch and a brake.

The element's slip is ``w = ω_b − ω_a`` (clutch) or ``w = ω_flange − ω_support`` (brake);
its torque ``τ`` is the friction model's force in the direction of ``w`` (the sliding side
``b`` sees ``−τ``, side ``a`` ``+τ``).  The model's force parameters are the capacity at
full actuation; the capacity multiplier is ``scale = act(u)·μ(θ)/μ_ref·μ(|w|)/μ_ref``
(>= 0), where ``act`` is the command (COM in [0, 1]; with ``clamp_reference`` > 0 a clamp
force [N] divided by it, e.g. a release system's signal) or, with ``clamp_table``, the
normalised clamp force of a diaphragm-spring characteristic at the position the input
gives, scaled by ``1 + installed_shift`` (lining wear moves the spring's engaged,
installed position from 1 to ``1 + installed_shift``; the open clutch stays at 0); ``μ(θ)`` is read at the first heat node's temperature.  With a ``wear`` law
(:class:`~clutchsim.network.wear.WearLaw`) the element has a quadrature state
``wear_<name>`` [m], the axial lining wear, starting at ``wear0``.  coulomb-robust elements lock
and free (a state ``<name>.locked``); the generated plant solves their stick torques.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ...friction.base import FrictionModel
from ..component import Component
from ..spec import Param, check_table, table_entry
from ..wear import WearLaw
from ._faults import FaultPhase
from ._laws import signal_arg

#: the tables of a friction element and the least value each may hold: a clamp force
#: and a friction coefficient's factor are never negative (the one place these rules live:
#: the chain's friction elements read them too)
TABLE_LOW = {"clamp_table": 0.0, "mu_temperature": 0.0, "mu_slip": 0.0}
#: what each table is: (its argument, the argument's unit, what the table gives)
TABLE_DOCS = {"clamp_table": ("actuator position", "-", "normalised clamp force [-]"),
              "mu_temperature": ("temperature", "°C", "friction factor μ(θ)/μ_ref [-]"),
              "mu_slip": ("slip speed", "rad/s", "friction factor μ(|w|)/μ_ref [-]")}


def _table(owner, key, tab):
    return None if tab is None else check_table(owner, key, tab[0], tab[1],
                                                low=TABLE_LOW[key])


#: a capacity factor from which a fault is "stuck locked" (the element seizes: whatever it
#: carries, it holds; ``docs/components.md``, faults)
FAULT_LOCKED = 1e3


#: the faults a friction clutch or brake can have (``docs/components.md``, faults)
FRICTION_FAULT_KEYS = ("fault_time", "fault_capacity_factor", "fault_drag", "fault_temperature",
                       "fault_input")


class _FrictionElement(FaultPhase, Component):
    friction = True
    #: the keys of the faults it can have (``docs/components.md``, faults)
    fault_keys: tuple = ()
    params = (Param("drag", "N·m", "drag torque of the open element, drag·tanh(w/1 rad/s)",
                    default=0.0, low=0.0, high=1e6),
              Param("installed_shift", "-", "lining wear's shift of the diaphragm spring's "
                    "installed position: clamp_table is read at command·(1 + installed_shift)",
                    default=0.0, low=-1.0, strict=True),
              Param("wear0", "m", "axial lining wear at the start (with a wear law)",
                    default=0.0, low=0.0),
              Param("clamp_reference", "N", "clamp load at which the friction model's force "
                    "parameters hold; > 0: the command is a clamp force [N] (a release "
                    "system's or an actuator's signal) read as command/clamp_reference; 0: "
                    "the command is the normalised actuation [-]", default=0.0, low=0.0),
              Param("fault_time", "s", "time at which the fault (fault_capacity_factor) "
                    "strikes", default=0.0, low=0.0),
              Param("fault_capacity_factor", "-", "fault: the capacity's factor from "
                    "fault_time on (1: no fault; 0: stuck open, no torque; below 1: capacity "
                    "loss; FAULT_LOCKED or more: stuck locked, a rigid joint)", default=1.0,
                    low=0.0, high=1e9),
              Param("fault_drag", "N·m", "fault: drag torque added from fault_time on "
                    "(a dragging clutch, a binding brake): drag + fault_drag", default=0.0,
                    low=0.0, high=1e6),
              Param("fault_temperature", "°C", "fault trigger: > 0, the fault strikes when "
                    "the temperature of the element's first heat node first rises past it "
                    "(a signal-triggered fault, instead of at fault_time); 0: at fault_time",
                    default=0.0, low=0.0, high=2000.0))
    side_a = "a"
    side_b = "b"
    #: the element reads its actuation from an input signal (False: always fully applied)
    commanded = True

    #: its input signals beside the command (the scenario builder checks they exist)
    signal_keys = ("fault_input",)

    def __init__(self, name, model, command, clamp_table=None, mu_temperature=None,
                 mu_slip=None, heat=(), locked0=None, z0=None, runout=None, wear=None,
                 fault_input=None, **values):
        super().__init__(name, **values)
        o = self.label
        self.fault_input = signal_arg(o, "fault_input", fault_input, optional=True)
        self.runout = None
        if runout is not None:
            amp, order = (float(v) for v in runout)
            if not 0.0 <= amp < 1.0:
                raise ValueError(f"{o}: runout amplitude = {amp:g} must be in [0, 1) (a "
                                 "fraction of the clamp load)")
            if not order > 0.0:
                raise ValueError(f"{o}: runout order = {order:g} must be > 0")
            self.runout = (amp, order)
        if not isinstance(model, FrictionModel):
            raise TypeError(f"{o}: model must be a clutchsim friction model")
        if self.commanded and (not isinstance(command, str) or not command):
            raise ValueError(f"{o}: command = {command!r} must name an input signal")
        self.model = model
        self.command = command
        self.clamp_table = _table(o, "clamp_table", clamp_table)
        self.mu_temperature = _table(o, "mu_temperature", mu_temperature)
        self.mu_slip = _table(o, "mu_slip", mu_slip)
        shares = []
        for node, s in heat:
            s = float(s)
            if not 0.0 <= s <= 1.0:
                raise ValueError(f"{o}: heat share {s:g} for {node!r} must be in [0, 1]")
            shares.append((str(node), s))
        if len(shares) > 2:
            raise ValueError(f"{o}: heat goes to at most 2 thermal nodes")
        if sum(s for _, s in shares) > 1.0 + 1e-12:
            raise ValueError(f"{o}: heat shares sum to {sum(s for _, s in shares):g} > 1")
        if self.mu_temperature is not None and not shares:
            raise ValueError(f"{o}: mu_temperature needs a thermal node (heat)")
        self.heat = tuple(shares)
        if wear is not None and not isinstance(wear, WearLaw):
            raise TypeError(f"{o}: wear must be a clutchsim.network.wear.WearLaw")
        if wear is not None and not shares:
            raise ValueError(f"{o}: a wear law needs a thermal node (heat): its rate reads "
                             "the first heat node's temperature")
        self.wear = wear
        self.locked0 = locked0
        self.z0 = None if z0 is None else tuple(float(v) for v in z0)
        self.check_fault()

    def described_values(self):
        model = self.model
        domain = self.domain or "rotational"
        out = {"friction.model": {"value": model.name, "unit": "",
                                  "description": "friction model"}}
        for f in dataclasses.fields(model):
            if getattr(model, f.name) is None:      # an option not in use
                continue
            kind_doc = model.parameter_info.get(f.name)
            out[f"friction.{f.name}"] = {
                "value": getattr(model, f.name),
                "unit": model.unit_of(f.name, domain) if kind_doc else "",
                "description": kind_doc[1] if kind_doc else "option of the friction model"}
        for key, (arg, unit, what) in TABLE_DOCS.items():
            tab = getattr(self, key)
            if tab is not None:
                out[key] = table_entry(f"{arg} → {what}", tab[0], unit, tab[1], "-")
        if self.runout is not None:
            out["runout.amplitude"] = {"value": self.runout[0], "unit": "-",
                                       "description": "clamp load runout, a fraction of the "
                                       "clamp load"}
            out["runout.order"] = {"value": self.runout[1], "unit": "-",
                                   "description": "runout order (cycles per revolution of "
                                   "the slip angle)"}
        for node, share in self.heat:
            out[f"heat.{node}"] = {"value": share, "unit": "-",
                                   "description": f"share of the friction heat into {node!r}"}
        if self.wear is not None:
            for f in dataclasses.fields(self.wear):
                if getattr(self.wear, f.name) is None:     # theta_crit: no critical rise
                    continue
                out[f"wear.{f.name}"] = {"value": getattr(self.wear, f.name),
                                         "unit": WearLaw.UNITS[f.name],
                                         "description": "wear law"}
        return out

    # the flags below decide the generated equations; read from the values each time, they
    # follow a with_values (a flag set once in __init__ did not: a copy with a fault
    # changed by with_values kept the equations of the fault it had)
    @property
    def has_fault(self) -> bool:
        v = self.values
        return v.get("fault_capacity_factor", 1.0) != 1.0 or v.get("fault_drag", 0.0) > 0.0

    @property
    def has_drag(self) -> bool:
        return self.values.get("drag", 0.0) != 0.0 or self.values.get("fault_drag", 0.0) > 0.0

    @property
    def fault_trigger(self) -> str:
        """What strikes its fault: ``"time"`` (``fault_time``), ``"temperature"`` (its
        first heat node rising past ``fault_temperature``) or ``"input"`` (the signal
        ``fault_input`` rising past 0.5)."""
        if getattr(self, "fault_input", None):
            return "input"
        return "temperature" if self.values.get("fault_temperature", 0.0) > 0.0 else "time"

    @property
    def fault_triggered(self) -> bool:
        """Is its fault struck by a signal (its time unknown before the run)?"""
        return self.fault_trigger != "time"

    def check_fault(self) -> None:
        """A signal-triggered fault: a fault to trigger, one trigger, a heat node."""
        if not self.fault_triggered:
            return
        v, o = self.values, self.label
        key = "fault_input" if self.fault_trigger == "input" else "fault_temperature"
        what = (f"fault_input = {self.fault_input!r}" if key == "fault_input" else
                f"fault_temperature = {v['fault_temperature']:g} °C")
        others = [f"fault_time = {v['fault_time']:g} s"] if v["fault_time"] > 0.0 else []
        if key == "fault_input" and v.get("fault_temperature", 0.0) > 0.0:
            others.append(f"fault_temperature = {v['fault_temperature']:g} °C")
        why = ("sets no fault to trigger (fault_capacity_factor 1, fault_drag 0)"
               if not self.has_fault else
               f"and {' and '.join(others)} are {len(others) + 1} triggers: a fault has one"
               if others else
               "needs a thermal node (heat) whose temperature triggers it"
               if key == "fault_temperature" and not self.heat else None)
        if why is not None:
            err = ValueError(f"{o}: {what} {why}")
            err.key = key                   # the scenario key it concerns (scenario/build.py)
            raise err

    def schedule(self) -> tuple:
        """Its fault: from ``fault_time`` on the capacity's factor (``_faults.py``)."""
        if not self.has_fault:
            return ()
        change = {"fault_phase": 1}
        if self.values["fault_drag"] > 0.0:
            change["drag"] = self.values["drag"] + self.values["fault_drag"]
        # a temperature-triggered fault has no time: its event strikes it (``None``)
        return ((None if self.fault_triggered else self.values["fault_time"], change),)

    def fault_description(self) -> str | None:
        """What fails and when (None: no fault), for the outputs' events and the report."""
        if not self.has_fault:
            return None
        f, drag = self.values["fault_capacity_factor"], self.values["fault_drag"]
        what = [] if f == 1.0 else [
            "stuck open (no torque)" if f == 0.0 else "stuck locked" if f >= FAULT_LOCKED
            else f"capacity x {f:g}"]
        if drag > 0.0:
            what.append(f"drag +{drag:g} N·m")
        if self.fault_trigger == "temperature":
            return (f"{', '.join(what)} when {self.heat[0][0]} first exceeds "
                    f"{self.values['fault_temperature']:g} °C")
        if self.fault_trigger == "input":
            return f"{', '.join(what)} when {self.fault_input} first rises past 0.5"
        return f"{', '.join(what)} at {self.values['fault_time']:g} s"

    @property
    def reads_force(self) -> bool:
        """Is its command a clamp force [N] (``clamp_reference`` > 0)?"""
        return self.commanded and self.values.get("clamp_reference", 0.0) > 0.0

    def input_ranges(self):
        # COM, the normalised actuation of seed eqs. 1-2 (not a pedal position read through
        # a clamp table, nor a clamp force [N]); below 0 it is an open clutch (the capacity
        # is clipped at 0, as the normalised normal force of Modelica's clutches, whose
        # CoupledClutches example drives one with a cosine)
        if self.commanded and not self.reads_force and self.clamp_table is None:
            what = "its actuation COM (1 fully engaged, 0 or below open)"
            return {self.command: (-1.0, 1.0, "-", what)}
        return {}

    @property
    def lockable(self) -> bool:
        """Does the plant lock and free it (a stick/slip model whose stuck mode the plant
        locks, declared by the model: :attr:`FrictionModel.lockable`)?"""
        return self.model.lockable

    def options(self):
        tabs = tuple(None if getattr(self, k) is None else len(getattr(self, k)[0])
                     for k in ("clamp_table", "mu_temperature", "mu_slip"))
        # the model's events follow its options (model (6)'s reset policy stop has none)
        return (self.model.name, self.model.code, self.model.n_states,
                self.model.event_names(), len(self.model.pack()), self.command, tabs,
                tuple(n for n, _ in self.heat), self.has_drag, self.runout is not None,
                self.wear is not None, self.reads_force, self.has_fault,
                self.has_fault and self.fault_trigger,
                self.fault_input if self.has_fault else None)

    def slip(self):
        return {self.side_b: 1.0, self.side_a: -1.0}

    def heat_shares(self):
        """(thermal node, name of its share in :meth:`pack`) per heat path."""
        return tuple((node, f"share{k}") for k, (node, _s) in enumerate(self.heat))

    def inputs(self):
        fault = (self.fault_input,) if self.has_fault and self.fault_input else ()
        return ((self.command,) if self.commanded else ()) + fault

    def check_network(self, net):
        for node, _ in self.heat:
            try:
                other = net.component(node)
            except ValueError:
                other = None
            if other is None or not getattr(other, "thermal", False):
                names = [c.name for c in net.components if getattr(c, "thermal", False)]
                raise ValueError(f"{self.label}: heat goes to thermal node {node!r}, which "
                                 f"does not exist (nodes: {', '.join(names) or 'none'})")

    def pack(self):
        d = dict(self.values)
        d["model"] = self.model.pack()
        d["capacity"] = self.model.static_capacity()
        for k, (_node, share) in enumerate(self.heat):
            d[f"share{k}"] = share
        for key in ("clamp_table", "mu_temperature", "mu_slip"):
            tab = getattr(self, key)
            if tab is not None:
                d[key] = np.concatenate([tab[0], tab[1]])
        if self.runout is not None:
            d["runout_amplitude"], d["runout_order"] = self.runout
        if self.has_fault:
            d["fault_now"] = self.values["fault_capacity_factor"] if self.fault_phase else 1.0
            d["fault_on"] = float(self.fault_phase > 0)
        if self.wear is not None:
            d.update(self.wear.pack())
        return d

    def state_layout(self):
        names = self.model.state_names()
        units = self.model.state_units(self.domain)
        out = [(f"z{i}", f"{self.name}.{n}", u) for i, (n, u) in enumerate(zip(names, units))]
        if self.lockable:
            out.append(("locked", f"{self.name}.locked", "-"))
        if self.runout is not None:
            out.append(("runout", f"angle_{self.name}", "rad"))
        return out

    def _slip0(self, ctx) -> float:
        return ctx.speed(self.name, self.side_b) - ctx.speed(self.name, self.side_a)

    def _locked0(self, ctx) -> bool:
        if not self.lockable:
            return False
        if self.locked0 is not None:
            return bool(self.locked0)
        # at zero slip it sticks, whatever its capacity (Modelica PartialFriction: it starts
        # sliding only when the torque that holds it exceeds the capacity, which the
        # break-away event decides at t0; with capacity 0 any torque does, in its direction)
        return self._slip0(ctx) == 0.0

    def initial_state(self, ctx):
        if self.z0 is not None:
            z = np.asarray(self.z0, dtype=float)
        else:
            z = self.model.initial_state()
            w = self._slip0(ctx)
            if self.lockable and not self._locked0(ctx) and w != 0.0:
                z = np.array([np.sign(w)])
        vals = list(z)
        if self.lockable:
            vals.append(1.0 if self._locked0(ctx) else 0.0)
        if self.runout is not None:
            vals.append(0.0)
        return vals

    def _command(self, e) -> str:
        """The command's expression: the input signal's value (``1.0`` for an element that
        is always applied); a wet clutch reads its pressure above the kiss point.  Its
        derivative by the signal is :meth:`_command_slope`."""
        return e.u(self.command) if self.commanded else "1.0"

    def _command_slope(self, e) -> str:
        """The derivative of :meth:`_command` by its signal (1; a limited-slip
        differential's clamp force reads the signal through its ramps)."""
        return "1.0"

    def emit(self, e):
        i = e.g.plan.fe_index[self.name]
        s, sc = f"s{i}", f"sc{i}"
        x = self._command(e)
        # dx: d(scale)/d(command) so far (the command may be another component's signal,
        # whose partials are chained in below)
        dx = e.tmp("dscx")
        if self.reads_force:
            x = e.let("xn", f"{x} / {e.par('clamp_reference')}")
            e.line(f"{dx} = 1.0 / {e.par('clamp_reference')}")
        else:
            e.line(f"{dx} = 1.0")
        self._partials = []
        if self.clamp_table is not None:
            act, dact = e.lookup("clamp_table", f"{x} * (1.0 + {e.par('installed_shift')})",
                                 "act")
            e.line(f"{dx} = {dx} * {dact} * (1.0 + {e.par('installed_shift')})")
        else:
            act = x
        e.line(f"{sc} = {act} if {act} > 0.0 else 0.0")
        e.line(f"{dx} = {dx} if {act} > 0.0 else 0.0")
        dth = None
        if self.mu_temperature is not None:
            mt, dmt = e.lookup("mu_temperature", e.theta(self.heat[0][0]), "mt")
            dth = e.let("dsc_th", f"{sc} * {dmt}")
            e.line(f"{sc} = {sc} * {mt}")
            e.line(f"{dx} = {dx} * {mt}")
        dsl = None
        if self.mu_slip is not None:
            ms, dms = e.lookup("mu_slip", f"abs({s})", "ms")
            dsl = e.let("dsc_s", f"{sc} * {dms} * (1.0 if {s} >= 0.0 else -1.0)")
            if dth is not None:
                e.line(f"{dth} = {dth} * {ms}")
            e.line(f"{sc} = {sc} * {ms}")
            e.line(f"{dx} = {dx} * {ms}")
        e.line(f"{dx} = {dx} if {sc} > 0.0 else 0.0")
        e.line(f"{sc} = max({sc}, 0.0)")
        if self.runout is not None:
            # pressure-plate runout: the clamp load oscillates at `order` per turn of side b
            arg = e.let("ro_arg", f"{e.par('runout_order')} * {e.x('runout')}")
            fac = e.let("ro_fac", f"1.0 + {e.par('runout_amplitude')} * math.sin({arg})")
            dro = e.let("dsc_ro", f"{sc} * {e.par('runout_amplitude')} * "
                                  f"{e.par('runout_order')} * math.cos({arg})")
            for d in (dth, dsl, dx):
                if d is not None:
                    e.line(f"{d} = {d} * {fac}")
            e.line(f"{sc} = {sc} * {fac}")
            self._partials.append((e.kx("runout"), dro))
            e.deriv("runout", e.w(self.side_b))
            e.dderiv("runout", e.kw(self.side_b), "1.0")
        if self.has_fault:
            # a fault: the capacity's factor from fault_time on (a scheduled value change at
            # a located time event; the lock and break-away tests see the new capacity)
            fac = e.par("fault_now")
            for d in (dth, dsl, dx):
                if d is not None:
                    e.line(f"{d} = {d} * {fac}")
            for k, (key, d) in enumerate(self._partials):
                self._partials[k] = (key, f"({d}) * {fac}")
            e.line(f"{sc} = {sc} * {fac}")
            if self.fault_triggered:
                # the first heat node's temperature rising past fault_temperature, or the
                # input past 0.5, once: fault_on (1 from the fault on) lowers the function
                # out of reach after it
                level = (f"{e.theta(self.heat[0][0])} - {e.par('fault_temperature')}"
                         if self.fault_trigger == "temperature" else
                         f"{e.u(self.fault_input)} - 0.5")
                trigger = f"{level} - 1e6 * {e.par('fault_on')}"
            else:
                trigger = f"t - {e.par('fault_time')}"
            e.event(f"{self.name}: fault, {{fault_description}}", 1, trigger, "bank")
            e.output(f"fault_{self.name}", "-", e.par("fault_on"))
        if self.commanded:
            self._partials += e.chain(self.command, f"{dx} * {self._command_slope(e)}")
        if dth is not None:
            self._partials.append((e.ktheta(self.heat[0][0]), dth))
        if dsl is not None:
            for fl, coef in self.slip().items():
                self._partials.append((e.kw(fl), f"{coef!r} * {dsl}"))
        T, Fe = f"fT{i}", f"Fe{i}"
        d = e.domain
        names = ([f"{d.effort}_{self.name}"] if self.side_a == "support" else
                 [f"{d.effort}_{self.name}", f"{d.effort}_friction_{self.name}"])
        for nm in names:
            e.output(nm, d.effort_unit, T)
        e.output(f"{d.slip}_{self.name}", d.speed_unit, s)
        e.output(f"capacity_{self.name}", d.effort_unit, f"{sc} * {e.par('capacity')}")
        e.output(f"{d.effort}_stick_{self.name}", d.effort_unit, Fe)
        e.output(f"P_{self.name}", "W", f"{T} * {s}")

    def scale_partials_of(self, e_index):
        return list(getattr(self, "_partials", []))


class Clutch(_FrictionElement):
    """A friction clutch between flanges a and b (any friction model)."""

    kind = "clutch"
    title = "friction clutch (any friction model)"
    flanges = ("a", "b")
    fault_keys = FRICTION_FAULT_KEYS


class Brake(_FrictionElement):
    """A friction brake from ``flange`` to ``support`` (grounded when unconnected)."""

    kind = "brake"
    title = "friction brake (any friction model)"
    flanges = ("flange", "support")
    fault_keys = FRICTION_FAULT_KEYS
    grounded = ("support",)
    side_a = "support"
    side_b = "flange"
