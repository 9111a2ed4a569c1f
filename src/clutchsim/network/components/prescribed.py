"""Prescribed-motion sources (Modelica ``Sources.Speed``, ``Position``, ``Accelerate``,
``Move`` and ``ConstantSpeed``, rotational and translational).

A source drives the node of its ``flange`` along a motion it prescribes, whatever the
torques on that node: the node is a *moving ground*.  The assembly eliminates it from the
free speeds as it eliminates the ground (a relation ``w_flange = 0`` in ``G``), and the plant
reads its speed from the source's own speed state (a constant for ``constant_speed``), so
the speed is never a solution of the dynamics and a partial derivative by it is one by that
state (:meth:`~clutchsim.network.plant.Plan.speed_key`).  Each source owns the position
and speed states ``phi_<name>``/``omega_<name>`` (``s_<name>``/``v_<name>`` in the
translational domain): ``dφ/dt = ω``, ``dω/dt = a`` with the acceleration ``a`` of its law.

The torque it applies (output ``T_<name>``, ``F_<name>``) is what holds that motion,
``τ = J_node·a − Σ τ_other`` (the inertia at its node times the prescribed acceleration,
minus every other torque on the node), and it books ``τ·ω`` as input power, so the energy
balance closes.  The rules of a prescribed node (:meth:`Assembly._prescribed`): one source
per node, not the ground, no rigid part and no friction element at the node.

The laws (``ω_c = 2π·f_crit``):

* ``speed``: ``a = (ω_ref − ω)·ω_c`` (MSL's first-order filter), ``ω(0) = ω_ref(0)``;
  ``exact = 1``: ``a`` = the input ``derivative`` (dω_ref/dt: clutchsim's input signals
  carry no derivatives, MSL differentiates the reference symbolically), ``ω(0) = ω_ref(0)``,
  so ``ω`` is ``ω_ref`` to the integration tolerance;
* ``position``: MSL's critically damped second-order (Bessel) filter,
  ``a = ((φ_ref − φ)·ω_c − af·ω)·ω_c/bf`` with ``af = 1.3617``, ``bf = 0.6180``,
  ``φ(0) = φ_ref(0)``, ``ω(0) = w0``;
* ``accelerate``: ``a = a_ref``, ``φ(0) = phi0``, ``ω(0) = w0``;
* ``move``: the three inputs ``position``, ``speed`` and ``acceleration`` (MSL ``Move``'s
  ``u``): ``a`` = the acceleration input, ``φ(0)``, ``ω(0)`` = the first two at the start
  (consistent inputs, ``speed = d position/dt``, ``acceleration = d speed/dt``, give MSL's
  motion to the integration tolerance; MSL takes the angle and speed from the inputs at
  every instant);
* ``constant_speed``: ``ω = w_fixed`` (a parameter), ``a = 0``; only ``φ`` is a state.
"""

from __future__ import annotations

from typing import ClassVar

from ..component import Component
from ..spec import DOMAINS, Param
from ._laws import signal_arg

#: MSL Position's Bessel filter coefficients (s and s² terms)
BESSEL_AF, BESSEL_BF = 1.3617, 0.6180


def _units(domain: str) -> tuple[str, str, str]:
    """(position, speed, acceleration) units of a domain."""
    return ("rad", "rad/s", "rad/s²") if domain == "rotational" else ("m", "m/s", "m/s²")


class PrescribedMotion(Component):
    """A prescribed-motion source (see the module docstring); subclasses give the law."""

    flanges = ("flange",)
    prescribed_flange = "flange"
    #: scenario keys naming its input signals (in the order of :meth:`inputs`)
    signal_keys: tuple[str, ...] = ()

    def __init__(self, name, **values):
        sig = {k: values.pop(k) for k in list(values) if k in self.signal_keys}
        super().__init__(name, **values)
        self.signal_names = {}
        for k in self.signal_keys:
            v = sig.get(k)
            if v is None and self._needs(k):
                raise ValueError(f"{self.label}: {k} = ... (an input signal) is required "
                                 f"({self.signal_docs[k][0]})")
            if signal_arg(self.label, k, v, optional=True) is not None:
                self.signal_names[k] = v

    def _needs(self, key: str) -> bool:
        return self.signal_docs[key][1]

    def options(self):
        return tuple(sorted(self.signal_names.items()))

    def inputs(self):
        return tuple(self.signal_names[k] for k in self.signal_keys if k in self.signal_names)

    def input_units(self):
        pos, spd, acc = _units(self.domain)
        unit = {"position": pos, "speed": spd, "acceleration": acc, "derivative": acc}
        return {n: unit.get(self.input_kind.get(k, k), spd)
                for k, n in self.signal_names.items()}

    #: what each signal key is (position, speed, acceleration)
    input_kind: ClassVar[dict] = {}

    def constraints(self):
        # the prescribed node leaves the free speeds, as the ground does (its speed is
        # substituted by the plant: Plan.node_speed)
        return [{"flange": 1.0}]

    def state_layout(self):
        d = DOMAINS[self.domain]
        pos, spd, _ = _units(self.domain)
        out = [("phi", f"{d.position}_{self.name}", pos)]
        if self.speed_state() is not None:
            out.append(("w", f"{d.speed}_{self.name}", spd))
        return out

    def speed_state(self) -> str | None:
        """The state that is the node's speed (None: a constant)."""
        return "w"

    def speed_of(self, plan) -> str:
        """The node's speed as an expression of the states and values."""
        return f"y[{plan.state_index[(self.name, 'w')]}]"

    def initial_state(self, ctx):
        phi0, w0 = self.start(ctx.input0)
        return [phi0, w0] if self.speed_state() is not None else [phi0]

    def start(self, u0: dict) -> tuple[float, float]:
        """(position, speed) at the start, from the inputs' values then."""
        raise NotImplementedError

    def law(self, e) -> tuple[str, list]:
        """The prescribed acceleration and its partials ``[(key, expr)]``."""
        raise NotImplementedError

    def _sig(self, e, key):
        return e.u(self.signal_names[key])

    def emit(self, e):
        d = DOMAINS[self.domain]
        a, da = self.law(e)
        a = e.let("a", a)
        if self.speed_state() is not None:
            w = e.x("w")
            e.deriv("w", a)
            for key, expr in da:
                e.dderiv("w", key, expr)
            e.deriv("phi", w)
            e.dderiv("phi", e.kx("w"), "1.0")
            dw = [(e.kx("w"), "1.0")]
        else:
            w = self.speed_of(e.g.plan)
            e.deriv("phi", w)
            dw = []
        # the torque that holds the motion: J·a minus every other torque on the node
        others, dothers = e.applied("flange")
        tsum = e.let("tsum", " + ".join(f"({t})" for t in others) or "0.0")
        jn = e.node_inertia("flange")
        tau = e.let("tau", f"{jn} * {a} - {tsum}")
        e.power("in", f"{tau} * {w}")
        for key, expr in da:
            e.dpower("in", key, f"{jn} * ({expr}) * {w}")
        for key, expr in dothers:
            e.dpower("in", key, f"-({expr}) * {w}")
        for key, expr in dw:
            e.dpower("in", key, f"{tau} * {expr}")
        e.output(f"{d.effort}_{self.name}", d.effort_unit, tau)
        e.output(f"a_{self.name}", _units(self.domain)[2], a)


def _params(domain: str, *which: str) -> tuple[Param, ...]:
    pos, spd, _ = _units(domain)
    p, w = ("phi", "w") if domain == "rotational" else ("s", "v")
    table = {
        "f_crit": Param("f_crit", "Hz", "cut-off frequency of the filter", default=50.0,
                        low=0.0, strict=True),
        "exact": Param("exact", "-", "1: follow the reference exactly (needs its derivative "
                       "as an input); 0: through the filter", default=0.0, low=0.0, high=1.0),
        "p0": Param(f"{p}0", pos, "initial position", default=0.0),
        "w0": Param(f"{w}0", spd, "initial speed", default=0.0),
        "fixed": Param(f"{w}_fixed", spd, "the fixed speed"),
    }
    return tuple(table[k] for k in which)


class _Speed(PrescribedMotion):
    signal_keys = ("input", "derivative")
    input_kind: ClassVar[dict] = {"input": "speed", "derivative": "acceleration"}

    def _needs(self, key):
        return key == "input" or (key == "derivative" and self.values.get("exact", 0) > 0.5)

    def __init__(self, name, **values):
        super().__init__(name, **values)
        if self.exact < 0.5 and "derivative" in self.signal_names:
            raise ValueError(f"{self.label}: derivative = {self.signal_names['derivative']!r} "
                             "is read only with exact = 1 (the filter follows the speed)")

    def start(self, u0):
        return self.values[self.params[2].name], float(u0.get(self.signal_names["input"], 0.0))

    def law(self, e):
        if self.exact > 0.5:
            return self._sig(e, "derivative"), list(e.du(self.signal_names["derivative"]))
        wc = e.let("wc", f"2.0 * math.pi * {e.par('f_crit')}")
        u = self._sig(e, "input")
        return f"({u} - {e.x('w')}) * {wc}", [(e.kx("w"), f"-{wc}"),
                                               *e.chain(self.signal_names["input"], wc)]


class Speed(_Speed):
    """Prescribed speed ``ω_ref(t)`` (Modelica ``Speed``): filtered or exact (module
    docstring)."""

    kind = "speed"
    title = "prescribed speed (Modelica Speed: filtered, or exact with its derivative)"
    params = _params("rotational", "f_crit", "exact", "p0")
    signal_docs: ClassVar[dict] = {"input": ("Input signal: the reference speed [rad/s].", True),
                   "derivative": ("Input signal: dω_ref/dt [rad/s²], with exact = 1.", False)}


class TranslationalSpeed(_Speed):
    """Prescribed velocity ``v_ref(t)`` (Modelica translational ``Speed``)."""

    kind = "translational_speed"
    title = "prescribed velocity (Modelica Speed: filtered, or exact with its derivative)"
    domain = "translational"
    params = _params("translational", "f_crit", "exact", "p0")
    signal_docs: ClassVar[dict] = {"input": ("Input signal: the reference velocity [m/s].", True),
                   "derivative": ("Input signal: dv_ref/dt [m/s²], with exact = 1.", False)}


class _Position(PrescribedMotion):
    signal_keys = ("input",)
    input_kind: ClassVar[dict] = {"input": "position"}

    def start(self, u0):
        return float(u0.get(self.signal_names["input"], 0.0)), self.values[self.params[1].name]

    def law(self, e):
        wc = e.let("wc", f"2.0 * math.pi * {e.par('f_crit')}")
        phi, w, u = e.x("phi"), e.x("w"), self._sig(e, "input")
        k = e.let("k", f"{wc} / {BESSEL_BF!r}")
        return (f"(({u} - {phi}) * {wc} - {BESSEL_AF!r} * {w}) * {k}",
                [(e.kx("phi"), f"-{wc} * {k}"), (e.kx("w"), f"-{BESSEL_AF!r} * {k}"),
                 *e.chain(self.signal_names["input"], f"{wc} * {k}")])


class Position(_Position):
    """Prescribed angle ``φ_ref(t)`` through MSL's second-order filter (Modelica
    ``Position``; an exact angle is :class:`Move`)."""

    kind = "position"
    title = "prescribed angle (Modelica Position, filtered)"
    params = _params("rotational", "f_crit", "w0")
    signal_docs: ClassVar[dict] = {"input": ("Input signal: the reference angle [rad].", True)}


class TranslationalPosition(_Position):
    """Prescribed position ``s_ref(t)`` through MSL's second-order filter (Modelica
    translational ``Position``)."""

    kind = "translational_position"
    title = "prescribed position (Modelica Position, filtered)"
    domain = "translational"
    params = _params("translational", "f_crit", "w0")
    signal_docs: ClassVar[dict] = {"input": ("Input signal: the reference position [m].", True)}


class _Accelerate(PrescribedMotion):
    signal_keys = ("input",)
    input_kind: ClassVar[dict] = {"input": "acceleration"}

    def start(self, u0):
        return self.values[self.params[0].name], self.values[self.params[1].name]

    def law(self, e):
        return self._sig(e, "input"), list(e.du(self.signal_names["input"]))


class Accelerate(_Accelerate):
    """Prescribed angular acceleration ``a_ref(t)`` (Modelica ``Accelerate``)."""

    kind = "accelerate"
    title = "prescribed angular acceleration (Modelica Accelerate)"
    params = _params("rotational", "p0", "w0")
    signal_docs: ClassVar[dict] = {"input": ("Input signal: the acceleration [rad/s²].", True)}


class TranslationalAccelerate(_Accelerate):
    """Prescribed acceleration ``a_ref(t)`` (Modelica translational ``Accelerate``)."""

    kind = "translational_accelerate"
    title = "prescribed acceleration (Modelica Accelerate)"
    domain = "translational"
    params = _params("translational", "p0", "w0")
    signal_docs: ClassVar[dict] = {"input": ("Input signal: the acceleration [m/s²].", True)}


class _Move(PrescribedMotion):
    signal_keys = ("position", "speed", "acceleration")
    input_kind: ClassVar[dict] = {k: k for k in signal_keys}

    def start(self, u0):
        return (float(u0.get(self.signal_names["position"], 0.0)),
                float(u0.get(self.signal_names["speed"], 0.0)))

    def law(self, e):
        return self._sig(e, "acceleration"), list(e.du(self.signal_names["acceleration"]))


class Move(_Move):
    """Angle, speed and acceleration prescribed together (Modelica ``Move``)."""

    kind = "move"
    title = "prescribed angle, speed and acceleration (Modelica Move)"
    signal_docs: ClassVar[dict] = {"position": ("Input signal: the angle [rad].", True),
                   "speed": ("Input signal: the speed [rad/s].", True),
                   "acceleration": ("Input signal: the angular acceleration [rad/s²].", True)}


class TranslationalMove(_Move):
    """Position, velocity and acceleration prescribed together (Modelica translational
    ``Move``)."""

    kind = "translational_move"
    title = "prescribed position, velocity and acceleration (Modelica Move)"
    domain = "translational"
    signal_docs: ClassVar[dict] = {"position": ("Input signal: the position [m].", True),
                   "speed": ("Input signal: the velocity [m/s].", True),
                   "acceleration": ("Input signal: the acceleration [m/s²].", True)}


class _ConstantSpeed(PrescribedMotion):
    def speed_state(self):
        return None

    def speed_of(self, plan):
        return f"p[{plan.slot[(self.name, self.params[1].name)]}]"

    def start(self, u0):
        return self.values[self.params[0].name], self.values[self.params[1].name]

    def law(self, e):
        return "0.0", []


class ConstantSpeed(_ConstantSpeed):
    """A fixed speed ``w_fixed`` (Modelica ``ConstantSpeed``)."""

    kind = "constant_speed"
    title = "constant speed (Modelica ConstantSpeed)"
    params = _params("rotational", "p0", "fixed")


class TranslationalConstantSpeed(_ConstantSpeed):
    """A fixed velocity ``v_fixed`` (Modelica translational ``ConstantSpeed``)."""

    kind = "translational_constant_speed"
    title = "constant velocity (Modelica ConstantSpeed)"
    domain = "translational"
    params = _params("translational", "p0", "fixed")


PRESCRIBED = (Speed, Position, Accelerate, Move, ConstantSpeed, TranslationalSpeed,
              TranslationalPosition, TranslationalAccelerate, TranslationalMove,
              TranslationalConstantSpeed)
