"""Generate, compile and cache one straight-line plant per network topology.

The generator asks every component for its equations (:meth:`Component.emit`, written
against an :class:`Emitter`) and writes one Python module with the plant's compiled
functions: ``rhs``, ``jac`` (exact), ``events``, ``reset`` and ``outputs`` (the
:mod:`clutchsim.core.system` protocol).  Parameter values stay in the parameter vector:
the module depends only on the *topology* (components, their structural options, the
connections and the sparsity of the speed reduction), so a sweep over values never
recompiles.  The module's file name is a hash of the topology; it lives in clutchsim's
cache directory (keyed by clutchsim's sources) with its C library, so a second process
loads it without compiling (:mod:`clutchsim.cgen.loader`, shared with the friction rig).

Mechanics.  Node speeds are ``w = N·v`` (:class:`~clutchsim.network.network.Assembly`).
Each component adds torques ``T`` on its flanges' nodes; the generalised forces are
``F = Nᵀ·T`` and, with the reduced inertia ``M = Nᵀ·diag(J)·N``, ``a = M⁻¹·F``.  A friction
element ``e`` has the slip ``w_e = b_e·v`` and, in the friction convention, its torque
``τ_e`` acts as ``−τ_e·b_e`` on ``F``.  Locked elements ``A`` (coulomb-robust in its stuck
mode) hold ``b_A·v̇ = 0``: their torques solve ``S_AA·τ_A = b_A·a`` with ``S = B·M⁻¹·Bᵀ`` and
``v̇ = a − M⁻¹·B_Aᵀ·τ_A`` (:func:`~clutchsim.network._kernels.lock_solve`).  Locking
projects ``v`` onto the new constraint set in the metric of ``M`` (momentum conserving; the
kinetic energy it removes is booked as ``W_sync``).  ``N``, ``M⁻¹``, ``B``, ``M⁻¹·Bᵀ`` and
``S`` are *derived parameters*, recomputed in Python whenever a value changes.

The expressions components write are a C-like subset of Python (checked with :mod:`ast`
when the module is generated: arithmetic, comparisons, conditional expressions, ``math``
functions, ``abs``/``min``/``max``), so the same source can be printed as C.
"""

from __future__ import annotations

import ast
import hashlib
from typing import NamedTuple

__all__ = ["Emitter", "generate", "load_module"]

#: energy accounts (quadrature states, in this order) and the key components book into
ENERGY = (("W_in", "in"), ("W_friction", "fric"), ("W_damping", "damp"), ("W_road", "road"),
          ("E_grade", "grade"), ("W_sync", "sync"))
#: version of the generated code's layout; part of every module's hash
GENERATOR_VERSION = 3

_ALLOWED = (ast.Expression, ast.BinOp, ast.UnaryOp, ast.BoolOp, ast.Compare, ast.IfExp,
            ast.Call, ast.Name, ast.Load, ast.Constant, ast.Attribute, ast.Subscript,
            ast.Add, ast.Sub, ast.Mult, ast.Div, ast.Pow, ast.USub, ast.UAdd, ast.Not,
            ast.And, ast.Or, ast.Lt, ast.LtE, ast.Gt, ast.GtE, ast.Eq, ast.NotEq, ast.Mod)
_FUNCS = {"abs", "min", "max", "float"}
_MATH = {"tanh", "exp", "log", "sqrt", "sin", "cos", "atan", "pi", "copysign", "fabs"}


def check_expr(expr: str) -> str:
    """``expr`` if it is in the C-like subset generated code may use, else ValueError."""
    tree = ast.parse(expr, mode="eval")
    for node in ast.walk(tree):
        if not isinstance(node, _ALLOWED):
            raise ValueError(  # noqa: TRY004 (a bad expression is a bad value, as all errors here)
f"generated expression {expr!r}: {type(node).__name__} is not "
                             "allowed in component equations")
        if isinstance(node, ast.Call):
            f = node.func
            ok = (isinstance(f, ast.Name) and f.id in _FUNCS) or (
                isinstance(f, ast.Attribute) and isinstance(f.value, ast.Name)
                and f.value.id == "math" and f.attr in _MATH)
            if not ok:
                raise ValueError(f"generated expression {expr!r}: call of "
                                 f"{ast.unparse(f)} is not allowed")
        if isinstance(node, ast.Subscript) and not (
                isinstance(node.value, ast.Name) and node.value.id in ("p", "y", "u")):
            raise ValueError(f"generated expression {expr!r}: only p[], y[], u[] may be "
                             "indexed")
    return expr


class Emitter:
    """What a component's :meth:`emit` writes against (one per component and render)."""

    def __init__(self, gen, comp):
        self.g = gen
        self.c = comp
        self.prefix = f"c{gen.comp_index[comp.name]}_"

    @property
    def domain(self):
        """The network's :class:`~clutchsim.network.spec.Domain` (names and units of
        outputs)."""
        return self.g.plan.domain

    # --------------------------------------------------------------- reading values
    def w(self, flange: str) -> str:
        """Speed of ``flange`` [rad/s]."""
        return f"w{self.g.asm.node_of[(self.c.name, flange)]}"

    def par(self, name: str) -> str:
        """A scalar value of the component's :meth:`pack`."""
        return f"p[{self.g.slot[(self.c.name, name)]}]"

    def lookup(self, table: str, x: str, local: str) -> tuple[str, str]:
        """The table ``table`` of :meth:`pack` (breakpoints then values) interpolated at
        ``x``: the private locals ``local`` and ``d<local>``, its value and its slope."""
        o, n = self.g.tables[(self.c.name, table)]
        v, dv = self.tmp(local), self.tmp(f"d{local}")
        self.line(f"{v}, {dv} = table(p, {o}, {n}, {x})")
        return v, dv

    def x(self, state: str) -> str:
        """One of the component's own states."""
        return f"y[{self.g.state_index[(self.c.name, state)]}]"

    def theta(self, node: str) -> str:
        """Temperature of thermal node ``node`` [°C]."""
        return f"y[{self.g.state_index[(node, 'theta')]}]"

    def u(self, name: str) -> str:
        """Signal ``name`` (as declared by :meth:`inputs`): the local of the component that
        produces it, else the external input's channel."""
        if name in self.g.plan.produced:
            var = self.g.signal_var.get(name)
            if var is None:     # the plan orders producers first: a bug if it happens
                raise ValueError(f"{self.c.label}: signal {name!r} is read before "
                                 f"{self.g.plan.produced[name][0].label} produced it")
            return var
        return f"u[{self.g.channel[name]}]"

    def du(self, name: str) -> list[tuple]:
        """Partial derivatives ``(key, local)`` of signal ``name`` with respect to states
        and speeds (keys as :meth:`kw`/:meth:`kx`); empty for an external input."""
        self.u(name)
        return list(self.g.signal_partials.get(name, ()))

    def chain(self, name: str, factor: str) -> list[tuple]:
        """``(key, factor·∂signal/∂key)`` of signal ``name``: the partials of an expression
        whose derivative with respect to the signal is ``factor``."""
        return [(k, f"({factor}) * {d}") for k, d in self.du(name)]

    def signal(self, local: str, expr: str) -> str:
        """Produce the component's signal ``local`` (declared by :meth:`signals`) as
        ``expr``; returns its local variable.  It is also an output."""
        if local not in self.c.signals():
            raise ValueError(f"{self.c.label}: signal {local!r} is not declared by "
                             "signals()")
        name = self.c.signal_name(local)
        var = self.let(f"sig_{local}", expr)
        self.g.signal_var[name] = var
        self.g.signal_partials[name] = []
        self.output(name, self.c.signals()[local], var)
        return var

    def dsignal(self, local: str, key, expr: str) -> None:
        """Partial derivative of the produced signal ``local`` with respect to ``key``."""
        name = self.c.signal_name(local)
        parts = self.g.signal_partials[name]
        var = self.let(f"dsig_{local}_{len(parts)}", expr)
        parts.append((key, var))

    def tmp(self, base: str) -> str:
        """A local variable name private to this component."""
        return f"{self.prefix}{base}"

    # keys of partial derivatives
    def kw(self, flange: str):
        return self.g.plan.speed_key(self.g.asm.node_of[(self.c.name, flange)])

    def kx(self, state: str):
        return ("y", self.g.state_index[(self.c.name, state)])

    def ktheta(self, node: str):
        return ("y", self.g.state_index[(node, "theta")])

    # --------------------------------------------------------------- writing equations
    def line(self, code: str) -> None:
        """A statement (assignments, ``if``) used by the equations below it."""
        self.g.body.append(code)

    def let(self, name: str, expr: str) -> str:
        """``name = expr`` as a private local; returns the local's name."""
        v = self.tmp(name)
        self.line(f"{v} = {check_expr(expr)}")
        return v

    def torque(self, flange: str, expr: str) -> None:
        """Torque ``expr`` [N·m] acting on the node of ``flange``."""
        self.g.torques.append((self.g.asm.node_of[(self.c.name, flange)], check_expr(expr)))

    def dtorque(self, flange: str, key, expr: str) -> None:
        """Partial derivative of that torque with respect to ``key`` (``kw``/``kx``/...)."""
        self.g.dtorques.append((self.g.asm.node_of[(self.c.name, flange)], key,
                                check_expr(expr)))

    def torque_pair(self, a: str, b: str, tau: str, partials) -> None:
        """Torque ``tau`` on the node of ``a`` and ``−tau`` on that of ``b`` (an element
        between two flanges) with the partial derivatives of ``tau``: ``partials``
        ``((key, expr, negated), ...)``, ``∂tau/∂key = expr`` (``−expr`` where ``negated``)."""
        self.torque(a, tau)
        self.torque(b, f"-{tau}")
        for fl, minus in ((a, False), (b, True)):
            for key, expr, negated in partials:
                self.dtorque(fl, key, f"-{expr}" if minus != negated else expr)

    def deriv(self, state: str, expr: str) -> None:
        self.g.derivs.append((self.g.state_index[(self.c.name, state)], check_expr(expr)))

    def dderiv(self, state: str, key, expr: str) -> None:
        self.g.dderivs.append((self.g.state_index[(self.c.name, state)], key,
                               check_expr(expr)))

    def heat(self, node: str, expr: str) -> None:
        """Heat flow ``expr`` [W] into thermal node ``node``."""
        self.g.heats.append((node, check_expr(expr)))

    def dheat(self, node: str, key, expr: str) -> None:
        self.g.dheats.append((node, key, check_expr(expr)))

    def power(self, account: str, expr: str) -> None:
        """Book ``expr`` [W] in an energy account (``in``, ``fric``, ``damp``, ``road``,
        ``grade``)."""
        self.g.powers.append((account, check_expr(expr)))

    def dpower(self, account: str, key, expr: str) -> None:
        """Partial derivative of a booked power (the energy accounts are states: the
        implicit integrators read their Jacobian rows)."""
        self.g.dpowers.append((account, key, check_expr(expr)))

    def output(self, name: str, unit: str, expr: str, setup: tuple[str, ...] = ()) -> None:
        """An output signal; ``setup`` statements run before it (outputs only).  Two
        components writing the same output (two engines, two vehicles) are a NetworkError
        naming both."""
        other = self.g.output_owner.setdefault(name, self.c)
        if other is not self.c:
            from .network import NetworkError
            raise NetworkError(f"{self.c.label} and {other.label} both write the output "
                               f"{name!r} [{unit}]: a network holds one component of this "
                               f"kind ({self.c.kind}); remove one, or join them into one (one "
                               "engine with their summed full-load curve)", self.c.name)
        self.g.outputs.append((name, unit, check_expr(expr), setup))

    def event(self, name: str, direction: int, expr: str, action: str) -> None:
        """An event function; at its zero crossing the plant answers ``action``
        (``"fail"``: the run stops as failed, ``"stop"``, ``"continue"``; ``"bank"``: the
        component's next scheduled values take effect, see
        :meth:`~clutchsim.network.component.Component.schedule`)."""
        if action not in ("fail", "stop", "continue", "bank"):
            raise ValueError(f"{self.c.label}: event action {action!r} is not one of fail, "
                             "stop, continue, bank")
        self.g.events.append((name, int(direction), check_expr(expr), action, self.c.name))

    def node_inertia(self, flange: str) -> str:
        """Inertia [kg·m²] at the node of ``flange`` (a derived value)."""
        return f"p[{self.g.plan.off_J + self.g.asm.node_of[(self.c.name, flange)]}]"

    def applied(self, flange: str) -> tuple[list[str], list[tuple]]:
        """The torques the components emitted so far put on the node of ``flange``, and
        their partials ``(key, expr)`` (a prescribed-motion source, emitted last, books the
        power it delivers from them)."""
        node = self.g.asm.node_of[(self.c.name, flange)]
        return ([e for n, e in self.g.torques if n == node],
                [(k, e) for n, k, e in self.g.dtorques if n == node])

    def accel(self, flange: str) -> str:
        """Acceleration of ``flange`` [rad/s²] (outputs only)."""
        return f"al{self.g.asm.node_of[(self.c.name, flange)]}"

    def spring_energy(self, expr: str) -> None:
        """Potential energy [J] stored by the component (the ``E_spring`` output)."""
        self.g.springs.append(check_expr(expr))

    def constraint_torque(self, relation: int, flange: str) -> str:
        """Torque [N·m] the component's rigid relation ``relation`` exerts on the node of
        ``flange`` (outputs only)."""
        row = self.g.relation_row[(self.c.name, relation)]
        node = self.g.asm.node_of[(self.c.name, flange)]
        return f"(p[{self.g.plan.off_G + row * self.g.asm.n_nodes + node}] * lam{row})"


class Topology(NamedTuple):
    """Everything that shapes the generated code (its hash names the module)."""

    key: str
    source: str


class _Gen:
    """One generation pass over a network (see :func:`generate`)."""

    def __init__(self, plan):
        self.plan = plan
        self.asm = plan.asm
        self.slot = plan.slot
        self.tables = plan.tables
        self.state_index = plan.state_index
        self.channel = plan.channel
        self.comp_index = {c.name: i for i, c in enumerate(plan.net.components)}
        self.relation_row = plan.relation_row
        self.body: list[str] = []
        self.torques: list = []
        self.dtorques: list = []
        self.derivs: list = []
        self.dderivs: list = []
        self.heats: list = []
        self.dheats: list = []
        self.powers: list = []
        self.dpowers: list = []
        self.outputs: list = []
        self.output_owner: dict = {}        # output name -> the component writing it
        self.events: list = []
        self.springs: list = []
        self.signal_var: dict = {}
        self.signal_partials: dict = {}
        # signals that follow from states alone first (they break loops of signals), then
        # every component's equations, producers before the consumers of their signals
        for c in plan.emit_order:
            if c.signals() and not c.feedthrough:
                c.emit_signals(Emitter(self, c))
        for c in plan.emit_order:
            if getattr(c, "friction", False):
                plan.friction_prelude(self, c)
            c.emit(Emitter(self, c))
        for c in plan.thermal:
            c.emit(Emitter(self, c))


def generate(plan) -> Topology:
    """The module source of ``plan`` (a :class:`~clutchsim.network.plant.Plan`)."""
    g = _Gen(plan)
    src = plan.render(g)
    h = hashlib.blake2b(digest_size=10)
    h.update(str(GENERATOR_VERSION).encode())
    h.update(src.encode())
    return Topology(h.hexdigest(), src)


def load_module(topo: Topology, *, exact_jacobian: bool = True):
    """Import and register the module of ``topo`` (with its exact Jacobian unless
    ``exact_jacobian`` is False): :func:`clutchsim.cgen.loader.load_plant`, the module
    printed as C and compiled by the system C compiler (about a second for a new topology,
    a library loaded in milliseconds after that), numba where that is impossible."""
    from ..cgen.loader import load_plant
    return load_plant("network", topo.key, topo.source, exact_jacobian=exact_jacobian)
