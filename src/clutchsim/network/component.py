"""The base class of network components and the protocol they are compiled through.

A component says once what it is:

* ``flanges``: its mechanical connection points (names); ``grounded`` lists the ones that
  are tied to the housing when a scenario leaves them unconnected (supports);
* ``params``: its scalar parameters (:class:`~clutchsim.network.spec.Param`: name, unit,
  range, description), validated on construction;
* ``states``: the continuous states it owns (:class:`~clutchsim.network.spec.StateSpec`);
* its equations, in :meth:`Component.emit`, written against an emitter ``e``
  (:class:`~clutchsim.network.codegen.Emitter`): ``e.w(flange)`` a flange speed,
  ``e.par(name)`` a parameter, ``e.x(state)`` a state, ``e.u(input)`` an input signal
  (an external input, or a signal another component produces: ``e.du(input)`` gives its
  partial derivatives to chain into this component's own);
  ``e.torque(flange, expr)`` applies a torque on a flange, ``e.deriv(state, expr)`` sets a
  state derivative, ``e.power(account, expr)`` books a power in the energy accounts, and
  every equation gives its exact partial derivatives beside it (``e.dtorque``,
  ``e.dderiv``).  Expressions are strings in a small, C-like subset of Python
  (arithmetic, comparisons, ``math`` functions, conditional expressions); the generator
  writes them into one straight-line compiled module per topology;
* the signals it *produces* (:meth:`Component.signals`, named ``<component>.<signal>``):
  ``e.signal(name, unit, expr)`` with its partials ``e.dsignal(name, key, expr)``; other
  components read them by that full name where they would read an input.  A component
  whose signals read no input at the same instant (they follow from its states) sets
  ``feedthrough = False`` and writes them in :meth:`Component.emit_signals`: they are
  emitted before every component's equations, so they break loops of signals;
* rigid parts: :meth:`Component.inertias` (inertia at a flange) and
  :meth:`Component.constraints` (linear relations between flange speeds, e.g. a gear).

Adding a component is one new module under ``clutchsim/network/components`` and its line
in :data:`clutchsim.network.components.COMPONENTS`; ``docs/network.md`` has the recipe.
"""

from __future__ import annotations

import copy
from typing import ClassVar

import numpy as np

from .spec import Param, StateSpec, check_value

__all__ = ["Component"]


class Component:
    """A network component (see the module docstring)."""

    kind: ClassVar[str] = ""
    title: ClassVar[str] = ""
    flanges: ClassVar[tuple[str, ...]] = ()
    grounded: ClassVar[tuple[str, ...]] = ()
    params: ClassVar[tuple[Param, ...]] = ()
    states: ClassVar[tuple[StateSpec, ...]] = ()
    #: do its signals read its inputs at the same instant (False: they follow from its
    #: states and flange speeds alone, written by :meth:`emit_signals`)
    feedthrough: ClassVar[bool] = True
    #: mechanical domain (:data:`~clutchsim.network.spec.DOMAINS`): ``"rotational"``,
    #: ``"translational"``, or None for a component of either (a thermal node)
    domain: ClassVar[str | None] = "rotational"

    def __init__(self, name: str, **values):
        if not isinstance(name, str) or not name or not name.replace("_", "a").isalnum():
            raise ValueError(f"{self.kind}: name {name!r} must be a non-empty identifier "
                             "(letters, digits, underscores)")
        self.name = name
        known = {p.name for p in self.params}
        unknown = sorted(set(values) - known)
        if unknown:
            from ..core.system import closest
            raise ValueError(f"{self.label}: unknown parameter {unknown[0]!r}"
                             f"{closest(unknown[0], known)}; parameters: "
                             f"{', '.join(sorted(known)) or 'none'}")
        v = {}
        label = self.label
        for p in self.params:
            if p.name in values:
                v[p.name] = check_value(label, p, values[p.name])
            elif p.default is None:
                raise ValueError(f"{label}: parameter {p.name!r} [{p.unit}] is required "
                                 f"({p.doc})")
            else:
                v[p.name] = float(p.default)
        self.values = v

    # ------------------------------------------------------------------ declaration
    @property
    def label(self) -> str:
        """``"<kind> '<name>'"``, how messages name this component."""
        return f"{self.kind.replace('_', ' ')} {getattr(self, 'name', '?')!r}"

    def __getattr__(self, key):
        values = self.__dict__.get("values")
        if values is not None and key in values:
            return values[key]
        raise AttributeError(key)

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self.name!r})"

    def structure(self) -> tuple:
        """What of this component shapes the generated code: a hashable tuple (its kind
        and name, plus :meth:`options`).  Networks with equal structures share one
        compiled plant."""
        return (self.kind, self.name, self.options())

    def options(self) -> tuple:
        """Structural options (a friction model, a governor that is present, the length
        of a table, ...); parameter values never are."""
        return ()

    def parameter_values(self) -> dict[str, dict]:
        """Every value its equations read, for a run's records and reports: ``{name:
        {"value", "unit", "description"}}``, its declared parameters (:attr:`params`) and
        then what :meth:`described_values` adds (a friction model's fields, tables)."""
        out = {p.name: {"value": self.values[p.name], "unit": p.unit, "description": p.doc}
               for p in self.params}
        out.update(self.described_values())
        return out

    def described_values(self) -> dict[str, dict]:
        """The values of :meth:`parameter_values` beyond the declared scalars (a component
        constructed with a friction model or a table says them here; tables through
        :func:`~clutchsim.network.spec.table_entry`)."""
        return {}

    def inputs(self) -> tuple[str, ...]:
        """Names of the input signals it reads."""
        return ()

    def input_units(self) -> dict[str, str]:
        """Unit of each input of :meth:`inputs`."""
        return {}

    def input_ranges(self) -> dict[str, tuple[float, float, str, str]]:
        """``input name -> (low, high, unit, what it is)``: the range each input of :meth:`inputs` must
        stay in (a throttle or a normalised actuation in [0, 1]); the scenario loader checks
        the input signals against it over the run.  Inputs without a range are absent."""
        return {}

    def signals(self) -> dict[str, str]:
        """Signals it produces: local name -> unit.  Their full names are
        ``<component>.<local name>``; each is also an output (a results column)."""
        return {}

    def signal_name(self, local: str) -> str:
        """The full name of its produced signal ``local``."""
        return f"{self.name}.{local}"

    def inertias(self) -> dict[str, float]:
        """Inertia [kg·m²] it puts at each of its flanges."""
        return {}

    def constraints(self) -> list[dict[str, float]]:
        """Rigid linear relations between its flange speeds, ``sum(c·w_flange) = 0``."""
        return []

    def pack(self) -> dict[str, float | np.ndarray]:
        """The values its equations read (``e.par``/``e.lookup``): its parameters, plus
        anything derived from them (tables as 1-D arrays)."""
        return dict(self.values)

    def state_layout(self) -> list[tuple[str, str, str]]:
        """(key, state name in results, unit) of each state it owns; by default its
        :attr:`states` as ``<component>.<state>``."""
        return [(s.name, f"{self.name}.{s.name}", s.unit) for s in self.states]

    def discrete_states(self) -> list[str]:
        """Keys (of :meth:`state_layout`) of its discrete states: the ones that change only
        at its events (a switching law's mode, a lock flag, a counter), whose derivative is
        0 between events.  They are the dimensionless ("-") states of the layout that are
        not among its :attr:`states` (continuous by declaration).  An FMU keeps them as its
        last event left them (``clutchsim/fmu/plant_core.c``): an importer's integrator
        moves them only by round-off, and a mode of 1e-51 is not the mode 0."""
        own = {s.name for s in self.states}
        return [k for k, _, unit in self.state_layout() if unit == "-" and k not in own]

    def initial_speeds(self) -> dict[str, float]:
        """Initial speed [rad/s] it prescribes at its flanges (inertias)."""
        return {}

    def initial_state(self, ctx) -> list[float]:
        """Initial values of its states; ``ctx`` gives the initial flange speeds
        (``ctx.speed(component, flange)``) and the inputs at the start (``ctx.input0``)."""
        return [0.0] * len(self.states)

    def schedule(self) -> tuple:
        """``(time [s], {parameter: value})`` entries at which its values change during a
        run (a gearbox's shifts), in time order.  Each is an event of its own
        (``e.event(..., "bank")``, emitted in the same order); the plant switches to a
        precomputed bank of all values and derived parameters there."""
        return ()

    def with_values(self, **changes) -> Component:
        """A copy with some parameter values changed (checked against their
        declarations); its structure is unchanged."""
        specs = {p.name: p for p in self.params}
        new = copy.copy(self)
        new.values = dict(self.values)
        for key, val in changes.items():
            if key not in specs:
                from ..core.system import closest
                raise ValueError(f"{self.label}: unknown parameter {key!r}"
                                 f"{closest(key, specs)}")
            new.values[key] = check_value(self.label, specs[key], val)
        return new

    def emit_signals(self, e) -> None:
        """Write the signals of a component with ``feedthrough = False`` (from its states
        and flange speeds only); runs before any component's :meth:`emit`."""

    def emit(self, e) -> None:
        """Write the equations (see the module docstring)."""

    def check_network(self, net) -> None:
        """Checks that need the whole network (names of thermal nodes, ...)."""
