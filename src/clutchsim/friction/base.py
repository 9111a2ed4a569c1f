"""Abstract base of every friction model of clutchsim.

Conventions shared by all models
--------------------------------
Sign
    ``v`` is the relative slip velocity. The friction force ``F`` returned by a
    model is the force transmitted in the direction of ``v``: it resists
    sliding, so the sliding body sees ``-F`` and steady sliding has
    ``sign(F) == sign(v)``.
Units
    Parameters are stored in translational SI units (N, m, m/s). The very same
    object is used for rotation, where the numbers are read as N·m, rad and
    rad/s (:meth:`FrictionModel.unit_of` gives the unit in either domain).
Capacity ``scale``
    Every kernel takes a capacity multiplier ``scale >= 0`` (normalised normal
    force, or the clutch command COM). Every force term of every model is
    proportional to ``scale`` (Coulomb and static levels, viscous terms,
    bristle forces, ``T_stat`` of model (6)). State dynamics are written in
    normalised form (they use the nominal, ``scale = 1`` curves), so they stay
    well posed when ``scale = 0``. ``scale = 0`` is a free, open element: the
    force is exactly zero whatever the state.
Stick force ``F_e``
    The friction force that would keep the relative acceleration exactly zero,
    computed by the plant (``F_e = u`` for a mass pushed by ``u``). Only the
    switching models (coulomb-naive, coulomb-robust, karnopp) read it.
Events
    Models that need the integrator to locate something declare event
    functions ``g_k``; an event fires when ``g_k`` crosses zero in the declared
    direction (-1 falling, +1 rising, 0 both). At a located event the
    integrator calls the model's reset, which returns a :class:`FrictionReset`:
    ``NONE`` (nothing changed, a monitoring event), ``CHANGED`` (states
    changed), ``STUCK`` (states changed and the element is now stuck: the plant
    sets the relative velocity to exactly zero, conserving momentum) or
    ``RELEASED`` (the element has just left the stuck mode).  These are the
    model's words to its plant; the plant answers the integrator with a
    :class:`clutchsim.core.Action`.

Compiled kernels
----------------
``<model>_force(p, z, v, F_e, scale, dz) -> F``
    ``p`` the packed parameters (:meth:`FrictionModel.pack`), ``z`` the ``nz`` states;
    returns the force and writes the state derivatives ``dz``. The state derivatives
    never depend on ``F_e`` or ``scale``.
``<model>_jacobian(p, z, v, F_e, scale, dz, Jz, dF) -> F``
    Returns the same ``F`` and writes the same ``dz`` as ``_force`` (it calls it: the two
    cannot drift apart), and writes the exact partial derivatives (every entry):
    ``Jz`` (shape ``(nz, nz + 1)``, C-contiguous) ``Jz[i, j] = d dz_i/d z_j`` for
    ``j < nz`` and ``Jz[i, nz] = d dz_i/d v``; ``dF`` (length ``nz + 3``)
    ``dF[j] = dF/d z_j``, ``dF[nz] = dF/dv``, ``dF[nz + 1] = dF/dF_e``,
    ``dF[nz + 2] = dF/dscale``. Models without states take ``Jz`` of shape ``(0, 1)``.
    Where the model is piecewise (stuck/sliding modes, the clip of the stick force,
    elasto-plastic and GMS zones) the derivative of the piece ``_force`` evaluates at
    that point; at exactly ``v = 0``, where ``|v|`` has a kink, the one-sided derivative
    for ``v -> 0+``. Discrete states (coulomb-robust's ``mode``) have zero derivatives.
    Two points where the exact slope is infinite get 0 instead (the Stribeck slope at
    ``v = 0`` for an exponent ``delta < 1``; Dahl with ``alpha < 1`` at steady sliding);
    each model's page in ``docs/models`` states its nonsmooth points.
A model hands its kernels to the rest of clutchsim as explicit references
(:class:`FrictionKernels`, the class variable ``kernels``): generated plants call them
directly; :func:`~clutchsim.friction.kernels.friction_force`, ``friction_jacobian``,
``friction_events`` and ``friction_reset`` dispatch on the model's integer ``code`` (its
place in :data:`~clutchsim.friction.registry.MODELS`, given by the registry) and are
generated from the registry (:mod:`clutchsim.friction.kernels`).

Capabilities
------------
Everything the rest of clutchsim needs to know about a model is declared on its class (the
recipe for a new model is ``docs/models/README.md``): ``uses_stick_force``,
``smooth_at_events``, ``passive``, ``lockable``, ``jumps``, the ``kernels``, the
``phenomena`` it shows by the literature (:data:`PHENOMENA` is the one vocabulary),
:meth:`FrictionModel.static_capacity` and :meth:`FrictionModel.typical_scales` (the scales
tests and benchmarks draw and compare with), and ``steady_checks``, steady sliding forces
written out independently of the model's code.
"""

from __future__ import annotations

import abc
import dataclasses
import enum
import functools
import math
import re
from typing import Any, ClassVar, NamedTuple

import numpy as np

__all__ = ["COULOMB_STEADY_CHECKS", "DOMAINS", "PHENOMENA", "SHARED_PARAMETERS",
           "STEADY_CHECK_SPEEDS", "STRIBECK_STEADY_CHECKS", "UNIT_KINDS", "ElementLaw",
           "Expectation", "FrictionKernels", "FrictionModel", "FrictionReset", "Scales",
           "SelfExcitedWarning", "StatelessModel", "expect", "parameters", "steady_checks_at"]


class FrictionReset(enum.IntEnum):
    """What a friction model's reset kernel did at its event (one meaning each)."""

    #: nothing changed (a monitoring event)
    NONE = 0
    #: the model's states changed
    CHANGED = 1
    #: the states changed and the element is now stuck (its slip is set to exactly zero)
    STUCK = 2
    #: the element has just left the stuck mode
    RELEASED = 3


#: the same codes as plain ints for the compiled kernels and plants
RESET_NONE = int(FrictionReset.NONE)
RESET_CHANGED = int(FrictionReset.CHANGED)
RESET_STUCK = int(FrictionReset.STUCK)
RESET_RELEASED = int(FrictionReset.RELEASED)

DOMAINS = ("translational", "rotational")

#: Unit strings of each parameter kind, per domain.
UNIT_KINDS: dict[str, tuple[str, str]] = {
    "force": ("N", "N·m"),
    "velocity": ("m/s", "rad/s"),
    "displacement": ("m", "rad"),
    "force/velocity": ("N·s/m", "N·m·s/rad"),
    "force/displacement": ("N/m", "N·m/rad"),
    "force/time": ("N/s", "N·m/s"),
    "1": ("-", "-"),
}


#: the classic friction phenomena (key -> title), in the order of the phenomena matrix: the
#: one vocabulary of the models' ``phenomena`` and of :mod:`clutchsim.benchmarks.phenomena`
PHENOMENA: dict[str, str] = {
    "stiction": "Stiction",
    "stribeck": "Stribeck effect",
    "presliding": "Pre-sliding displacement",
    "lag": "Frictional lag",
    "varying_breakaway": "Varying break-away force",
    "no_drift": "No drift under biased vibration",
}

#: categories of a literature expectation
EXPECTED = ("yes", "no", "depends")


class Expectation(NamedTuple):
    """What the literature says about one phenomenon of a model: ``expected`` is ``"yes"``,
    ``"no"`` or ``"depends"`` (on a parameter or an option), ``text`` the statement as the
    model's page gives it (with its numbers where the literature has them)."""

    expected: str
    text: str


def expect(**texts: str) -> dict[str, Expectation]:
    """A model's ``phenomena`` declaration: ``phenomenon="yes (with a note)"`` for every key
    of :data:`PHENOMENA`.  A text opens with what is expected: ``yes``/``no`` (the text is
    the statement, ``"no"`` alone means no) or ``depends:`` followed by what it depends on.
    """
    if set(texts) != set(PHENOMENA):
        raise TypeError(f"expect() got {sorted(texts)}; it takes exactly {list(PHENOMENA)}")
    out = {}
    for key in PHENOMENA:
        text = texts[key]
        if text.startswith("depends:"):
            out[key] = Expectation("depends", text.removeprefix("depends:").strip())
        elif text.split(" ", 1)[0] in ("yes", "no"):
            out[key] = Expectation(text.split(" ", 1)[0], text)
        else:
            raise TypeError(f"expect({key}={text!r}): the text must open with yes, no or "
                            "depends:")
    return out


#: what the parameter names several models share mean: ``name -> (unit kind, description)``
#: (a model's own parameters are described where it declares them, :func:`parameters`)
SHARED_PARAMETERS: dict[str, tuple[str, str]] = {
    "F_c": ("force", "Coulomb friction level"),
    "F_s": ("force", "static friction level"),
    "v_s": ("velocity", "Stribeck velocity"),
    "delta": ("1", "Stribeck exponent"),
    "sigma0": ("force/displacement", "bristle stiffness"),
    "sigma1": ("force/velocity", "bristle damping"),
    "sigma2": ("force/velocity", "viscous friction coefficient"),
}

#: the slip velocities [m/s or rad/s] at which the models write out their steady sliding
#: forces (``steady_checks``, :func:`steady_checks_at`): both directions, inside and beyond
#: the Stribeck and regularisation ranges of the default parameter sets
STEADY_CHECK_SPEEDS = (-0.02, 0.0005, 0.002, 0.3)


def steady_checks_at(*forces: float) -> tuple[tuple[float, float], ...]:
    """A model's ``steady_checks``: the steady sliding forces ``forces`` [N or N·m], written
    out from its formula with its default parameter set, at :data:`STEADY_CHECK_SPEEDS` in
    that order."""
    if len(forces) != len(STEADY_CHECK_SPEEDS):
        raise TypeError(f"steady_checks_at() takes {len(STEADY_CHECK_SPEEDS)} forces, one per "
                        f"speed of STEADY_CHECK_SPEEDS; got {len(forces)}")
    return tuple(zip(STEADY_CHECK_SPEEDS, forces))


#: the steady sliding forces of the Stribeck curve ``sign(v)·(F_c + (F_s -
#: F_c)·exp(-(v/v_s)^2)) + sigma2·v`` with ``F_c = 1``, ``F_s = 1.5``, ``v_s = 1e-3``,
#: ``sigma2 = 0.4``: the ``steady_checks`` of the models whose default parameter set has
#: that curve (lugre, elastoplastic, gms; stribeck, whose ``tanh(v/v_t)`` is ±1 at these
#: speeds)
STRIBECK_STEADY_CHECKS = steady_checks_at(-1.008, 1.3896003915357025, 1.009957819444367, 1.12)

#: the steady sliding forces of a Coulomb level ``F_c = 1`` alone (``F_ss = F_c·sign(v)``):
#: the ``steady_checks`` of coulomb-naive and dahl
COULOMB_STEADY_CHECKS = steady_checks_at(-1.0, 1.0, 1.0, 1.0)

_BOUND = re.compile(r"^(>=|>|<=|<) (\S+)$")
_INTERVAL = re.compile(r"^in ([\[(])(\S+), (\S+)([\])])$")
_CHOICE = re.compile(r"^(\S+) or (\S+)$")


@functools.cache
def _parsed_rule(rule: str) -> tuple:
    """A rule's form and parts, parsed once per rule text: ``("bound", op, rhs)`` (``rhs``
    a number's text or another parameter's name), ``("choice", a, b)``, ``("interval",
    opening, low, high, closing)``, or None for a text of no form."""
    for kind, form in (("bound", _BOUND), ("choice", _CHOICE), ("interval", _INTERVAL)):
        m = form.match(rule)
        if m:
            return (kind, *m.groups())
    return None


def parameters(**declared: str | tuple[str, str, str]
               ) -> tuple[dict[str, tuple[str, str]], dict[str, str]]:
    """A model's parameter declaration, in field order: ``name=rule`` for a name of
    :data:`SHARED_PARAMETERS`, ``name=(unit kind, description, rule)`` for the model's own.
    Returns ``(parameter_info, parameter_rules)``.

    A rule is checked on construction, before the model's ``_check``: ``""`` (none),
    ``"> 0"``, ``">= 0"``, ``"< 1"``, ``">= F_c"`` (another parameter), ``"in (0, 1)"``,
    ``"in [0, 1]"``, ``"1 or 2"``.  Rules of another form (a sequence's elements, a
    relation between several parameters) stay in the model's ``_check``.
    """
    info: dict[str, tuple[str, str]] = {}
    rules: dict[str, str] = {}
    for name, spec in declared.items():
        if isinstance(spec, str):
            if name not in SHARED_PARAMETERS:
                raise TypeError(f"parameters(): {name!r} is not a shared parameter; give "
                                "(unit kind, description, rule)")
            info[name], rules[name] = SHARED_PARAMETERS[name], spec
        else:
            kind, doc, rules[name] = spec
            info[name] = (kind, doc)
        if info[name][0] not in UNIT_KINDS:
            raise TypeError(f"parameters(): {name} has unit kind {info[name][0]!r}, not one "
                            f"of {', '.join(UNIT_KINDS)}")
        if rules[name] and _parsed_rule(rules[name]) is None:
            raise TypeError(f"parameters(): {name}'s rule {rules[name]!r} is not of the "
                            "forms '> 0', '>= F_c', 'in (0, 1]', '1 or 2'")
    return info, rules


class Scales(NamedTuple):
    """Typical magnitudes of a model with its parameters: ``force`` [N or N·m], ``velocity``
    [m/s or rad/s] (where the force changes), ``states`` (one per state, in its unit).
    Tests draw their points and size their tolerances with them."""

    force: float
    velocity: float
    states: tuple[float, ...]


@dataclasses.dataclass(frozen=True)
class FrictionKernels:
    """The compiled kernels a model provides (see the module docstring for their
    signatures): ``force`` and ``jacobian`` always, ``events`` and ``reset`` for a model
    with events (None otherwise).  Plants and the generated dispatchers call these very
    functions; nothing is looked up by name."""

    force: Any
    jacobian: Any
    events: Any = None
    reset: Any = None

    def __post_init__(self) -> None:
        if (self.events is None) != (self.reset is None):
            raise TypeError("FrictionKernels: events and reset come together (both or none)")

    def get(self, kind: str) -> Any:
        """The kernel of ``kind`` ("force", "jacobian", "events" or "reset")."""
        fn = getattr(self, kind)
        if fn is None:
            raise ValueError(f"the model has no {kind} kernel")
        return fn


class SelfExcitedWarning(UserWarning):
    """The locked (stuck) state of a model is self-excited (negative damping)."""


def check_domain(domain) -> str:
    """``domain`` if it is one of :data:`DOMAINS`, else a ValueError saying so."""
    if domain not in DOMAINS:
        raise ValueError(f"domain = {domain!r} must be one of {', '.join(DOMAINS)}")
    return domain


def _domain_index(domain: str) -> int:
    return DOMAINS.index(check_domain(domain))


class FrictionModel(abc.ABC):
    """Abstract friction model: parameters plus compiled kernels.

    Concrete models are final frozen dataclasses whose fields are the physical
    parameters (translational SI units). They declare, as class variables,
    ``name`` (registry name), ``citation``, ``parameter_info`` (``{parameter: (unit kind,
    description)}``) and ``parameter_rules`` (``{parameter: rule}``), both from one call of
    :func:`parameters`, ``phenomena`` (``{phenomenon: Expectation}`` over every key of
    :data:`PHENOMENA`, from :func:`expect`), ``default_parameter_set``, ``kernels``
    (:class:`FrictionKernels`), ``steady_checks`` and ``event_spec`` (``((name,
    direction), ...)``; a property where the events follow an option, as model (6)'s
    reset policy ``stop`` has none), plus the capability flags below. They implement
    small hooks: ``_check`` (optional: what the rules cannot say), ``_pack`` (private parameter
    layout read by the kernels), ``_state_spec`` (state names and unit kinds),
    ``_steady`` (steady sliding force at ``scale = 1``), ``_sliding_state`` (states in
    steady sliding), :meth:`static_capacity` and :meth:`typical_scales`.
    The integer ``code`` of the compiled dispatchers is not declared: the registry gives
    it (the model's place in :data:`~clutchsim.friction.registry.MODELS`, from 1).
    """

    name: ClassVar[str]
    #: given by the registry (:func:`clutchsim.friction.registry.register`), never by hand
    code: ClassVar[int]
    citation: ClassVar[str]
    parameter_info: ClassVar[dict[str, tuple[str, str]]]
    phenomena: ClassVar[dict[str, Expectation]]
    default_parameter_set: ClassVar[str]
    kernels: ClassVar[FrictionKernels]
    #: ``((v, F), ...)``: steady sliding forces ``F`` [N or N·m] at slip velocities ``v``
    #: with the default parameter set at ``scale = 1``, written out independently of the
    #: model's code (by hand from the formula, or the literature's table); the tests compare
    #: :meth:`steady_state_force` with them
    steady_checks: ClassVar[tuple[tuple[float, float], ...]]
    #: ``{parameter: rule}`` checked on construction (:func:`parameters` gives it with
    #: ``parameter_info``); rules of other forms are the model's ``_check``
    parameter_rules: ClassVar[dict[str, str]] = {}
    event_spec: ClassVar[tuple[tuple[str, int], ...]] = ()
    #: does the force read the stick force ``F_e``?  (plants skip computing it otherwise;
    #: :func:`clutchsim.friction.kernels.uses_stick_force` is the compiled twin)
    uses_stick_force: ClassVar[bool] = False
    #: is the force continuous in time across the model's event crossings when its reset
    #: changes nothing (``FrictionReset.NONE``)?  Plants then answer ``Action.PASS`` and
    #: the integrator steps through such a crossing instead of restarting at it.  False
    #: for a model whose force switches at its event (coulomb-naive's sign).
    smooth_at_events: ClassVar[bool] = False
    #: is the model passive at every instant: memoryless, its force never opposes its slip
    #: (``F·v >= 0``)?  Plants check it on every run (:mod:`clutchsim.network.invariants`).
    #: False for models that store energy in a state (bristles, pre-sliding) and for
    #: Karnopp's stick band (its stick force acts at small non-zero slips)
    passive: ClassVar[bool] = False
    #: is the model a stick/slip state machine (one state, the mode: −1 backward, 0 stuck,
    #: +1 forward; a discrete state, changed only by its reset) whose stuck mode the plant
    #: locks and frees?  Its events are ``stop`` (0) and ``breakaway`` (1).  (coulomb-robust)
    lockable: ClassVar[bool] = False
    #: does the element slide only forward (positive slip; it locks where the slip would
    #: turn negative)?  A freewheel.  Plants check that it never slides backwards
    #: (:mod:`clutchsim.network.invariants`).
    forward_only: ClassVar[bool] = False
    #: does the force jump at zero slip outside any event logic (a discontinuous force with
    #: no useful derivative there)?  Plants then difference their Jacobian instead of using
    #: the exact one, and chatter detection stops a run at lock-up.  (coulomb-naive)
    jumps: ClassVar[bool] = False
    #: does the force jump away from zero slip where no event marks it (Karnopp's window
    #: edges ``|v| = DV``)?  The integrator steps across such a jump as small as the
    #: tolerance demands; where the slip hovers at the edge (a stiff part beside it, at a
    #: tight tolerance) the step collapses there: the model's documented outcome
    #: (docs/models/karnopp.md), which the fuzzed networks accept from it.
    edge_jumps: ClassVar[bool] = False

    # ------------------------------------------------------------------ hooks
    def _check(self) -> None:
        """Validation beyond ``parameter_rules``; raise ValueError via :meth:`_require`."""

    @abc.abstractmethod
    def _pack(self) -> list[float]:
        """Parameters in the private layout read by the kernels."""

    @abc.abstractmethod
    def _state_spec(self) -> tuple[tuple[str, str], ...]:
        """``((state name, unit kind), ...)``; unit kind in UNIT_KINDS."""

    @abc.abstractmethod
    def _steady(self, v: np.ndarray) -> np.ndarray:
        """Steady sliding force at ``scale = 1`` for the velocities ``v``."""

    @abc.abstractmethod
    def _sliding_state(self, v: float) -> list[float]:
        """States in steady sliding at velocity ``v`` (``v != 0``)."""

    @abc.abstractmethod
    def static_capacity(self) -> float:
        """The largest force the model holds a body at rest with, at ``scale = 1`` [N or
        N·m] (a clutch's static torque capacity: its ``capacity_<name>`` output, and the
        limit of its ``stick_over_capacity`` check)."""

    @abc.abstractmethod
    def typical_scales(self) -> Scales:
        """Typical force, velocity and state magnitudes (:class:`Scales`) with these
        parameters."""

    # ------------------------------------------------------------ validation
    def __post_init__(self) -> None:
        for f in dataclasses.fields(self):  # type: ignore[arg-type]
            value = getattr(self, f.name)
            if f.type in ("str", str):  # option fields (e.g. a reset policy)
                if not isinstance(value, str):
                    raise ValueError(
                        f"{type(self).__name__}: {f.name} = {value!r} must be a string"
                    )
                continue
            if isinstance(value, (list, tuple, np.ndarray)):
                items = tuple(self._as_float(f.name, x) for x in value)
                object.__setattr__(self, f.name, items)
            else:
                object.__setattr__(self, f.name, self._as_float(f.name, value))
        # the bounds by numbers first: a relation (``F_s >= F_c``) then reads checked values
        rules = [(p, r) for p, r in self.parameter_rules.items() if r]
        rules.sort(key=lambda pr: _parsed_rule(pr[1])[-1] in self.parameter_info)
        for param, rule in rules:
            self._check_rule(param, rule)
        self._check()

    def _check_rule(self, param: str, rule: str) -> None:
        value = getattr(self, param)
        kind, *parts = _parsed_rule(rule)
        if kind == "bound":
            op, rhs = parts
            if rhs in self.parameter_info:
                limit = getattr(self, rhs)
                unit = UNIT_KINDS[self.parameter_info[rhs][0]][0]
                rule = f"{op} {rhs} = {limit:g}" + ("" if unit == "-" else f" {unit}")
            else:
                limit = float(rhs)
            ok = {">": value > limit, ">=": value >= limit, "<": value < limit,
                  "<=": value <= limit}[op]
        elif kind == "choice":
            ok = value in (float(parts[0]), float(parts[1]))
        else:
            opening, low, high, closing = parts
            ok = ((value > float(low) if opening == "(" else value >= float(low))
                  and (value < float(high) if closing == ")" else value <= float(high)))
        self._require(ok, param, rule)

    def _as_float(self, param: str, value: Any) -> float:
        cls = type(self).__name__
        if isinstance(value, bool):
            # contract: every bad parameter raises ValueError
            raise ValueError(f"{cls}: {param} = {value!r} must be a number, not a bool")  # noqa: TRY004
        try:
            x = float(value)
        except (TypeError, ValueError):
            raise ValueError(f"{cls}: {param} = {value!r} must be a real number") from None
        if not math.isfinite(x):
            raise ValueError(f"{cls}: {param} = {x} must be finite (no NaN or inf)")
        return x

    def _fmt(self, param: str) -> str:
        value = getattr(self, param)
        kind = self.parameter_info[param][0]
        unit = UNIT_KINDS[kind][0]
        if isinstance(value, str):
            shown = repr(value)
        elif isinstance(value, tuple):
            shown = "(" + ", ".join(f"{x:g}" for x in value) + ")"
        else:
            shown = f"{value:g}"
        return f"{param} = {shown}" + ("" if unit == "-" else f" {unit}")

    def _require(self, ok: bool, param: str, rule: str) -> None:
        """Raise ``ValueError('<Model>: <param> = <value> <unit> must be <rule>')``."""
        if not ok:
            raise ValueError(f"{type(self).__name__}: {self._fmt(param)} must be {rule}")

    # ------------------------------------------------------------ states
    @property
    def n_states(self) -> int:
        """Number of internal states of the model."""
        return len(self._state_spec())

    def state_names(self) -> tuple[str, ...]:
        """Names of the internal states, in storage order."""
        return tuple(name for name, _ in self._state_spec())

    def state_units(self, domain: str = "translational") -> tuple[str, ...]:
        """Units of the internal states in ``domain`` ("translational"/"rotational")."""
        i = _domain_index(domain)
        return tuple(UNIT_KINDS[kind][i] for _, kind in self._state_spec())

    def initial_state(self) -> np.ndarray:
        """State at rest and unloaded (all zeros; coulomb-robust: stuck)."""
        return np.zeros(self.n_states, dtype=np.float64)

    def sliding_state(self, v: float) -> np.ndarray:
        """States in steady sliding at slip velocity ``v != 0``.

        With these states the compiled kernel returns ``steady_state_force(v)``
        and (except for switching artefacts) zero state derivatives.
        """
        v = float(v)
        if v == 0.0 or not math.isfinite(v):
            raise ValueError(f"v = {v} must be finite and non-zero for steady sliding")
        return np.asarray(self._sliding_state(v), dtype=np.float64).reshape(self.n_states)

    # ------------------------------------------------------------ events
    @property
    def n_events(self) -> int:
        """Number of event functions the integrator must watch."""
        return len(self.event_spec)

    def event_names(self) -> tuple[str, ...]:
        """Names of the event functions."""
        return tuple(name for name, _ in self.event_spec)

    def event_directions(self) -> np.ndarray:
        """Crossing direction of each event: -1 falling, +1 rising, 0 both."""
        return np.array([d for _, d in self.event_spec], dtype=np.int64)

    # ------------------------------------------------------------ numbers
    def pack(self) -> np.ndarray:
        """Parameters as a 1-D float64 array in the model's private layout."""
        return np.ascontiguousarray(self._pack(), dtype=np.float64)

    def steady_state_force(self, v: Any, scale: float = 1.0) -> np.ndarray:
        """Steady sliding friction force for slip velocity ``v``.

        Parameters
        ----------
        v : array_like
            Slip velocity [m/s or rad/s].
        scale : float, optional
            Capacity multiplier (>= 0), default 1.

        Returns
        -------
        numpy.ndarray
            Friction force [N or N·m] in the direction of ``v``.
        """
        if not (math.isfinite(scale) and scale >= 0.0):
            raise ValueError(f"scale = {scale} must be finite and >= 0")
        v = np.asarray(v, dtype=np.float64)
        return scale * self._steady(v)

    # ------------------------------------------------------------ helpers
    def with_(self, **changes: Any) -> FrictionModel:
        """Copy with some parameters changed (validated like the constructor; an unknown
        parameter name raises TypeError listing the model's parameters)."""
        names = [f.name for f in dataclasses.fields(self)]
        unknown = [k for k in changes if k not in names]
        if unknown:
            import difflib
            close = difflib.get_close_matches(unknown[0], names, n=1, cutoff=0.5)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            raise TypeError(f"{self.name} has no parameter {unknown[0]!r}{hint}; its "
                            f"parameters: {', '.join(names)}")
        return dataclasses.replace(self, **changes)  # type: ignore[type-var]

    @classmethod
    def from_parameters(cls, set_name: str) -> FrictionModel:
        """Build the model from a literature parameter set (TOML data file)."""
        from .params import load_parameter_set

        pset = load_parameter_set(set_name)
        if cls.name not in pset.models:
            raise ValueError(
                f"parameter set {set_name!r} is for model(s) {', '.join(pset.models)}, "
                f"not {cls.name!r}"
            )
        return cls(**pset.parameters)

    @classmethod
    def unit_of(cls, param: str, domain: str = "translational") -> str:
        """Unit of parameter ``param`` in ``domain``."""
        i = _domain_index(domain)
        if param not in cls.parameter_info:
            raise ValueError(
                f"{cls.__name__} has no parameter {param!r}; valid: {', '.join(cls.parameter_info)}"
            )
        return UNIT_KINDS[cls.parameter_info[param][0]][i]


class StatelessModel(FrictionModel):
    """A model without states: its force is a function of the slip (and ``F_e``,
    ``scale``) alone."""

    def _state_spec(self) -> tuple[tuple[str, str], ...]:
        return ()

    def _sliding_state(self, v: float) -> list[float]:
        return []


class ElementLaw(FrictionModel):
    """The switching law of one network element (a freewheel, a dog clutch, a synchroniser,
    a mass between stops): a :class:`FrictionModel` the element's plant code calls like any
    other, but not a registry model, so it cannot be put on another element with
    ``--model``.  It has no literature phenomena, parameter set or steady sliding checks;
    it reads the stick force; its ``code`` is negative and given by its element."""

    phenomena: ClassVar[dict[str, Expectation]] = {}
    default_parameter_set: ClassVar[str] = ""
    steady_checks: ClassVar[tuple[tuple[float, float], ...]] = ()
    uses_stick_force: ClassVar[bool] = True
