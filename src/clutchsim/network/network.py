"""A driveline as a network: components joined at flanges, reduced to independent speeds.

Flanges joined by :attr:`Network.connections` form *nodes* (one speed each; the reserved
name ``ground`` is the housing, at rest).  Rigid components (gears, planetary sets) give
linear relations between node speeds, ``G·w = 0``; :class:`Assembly` solves them once,
exactly, for a set of *independent speeds* ``v`` with ``w = N·v`` (reduced row echelon
form; the speeds of inertias named first are kept as states, in the order the components
are listed).  The reduced inertia matrix ``M = Nᵀ·diag(J)·N`` must be regular: a
coordinate without inertia (a support left floating with nothing on it) is an error that
names its flanges.  A prescribed-motion source's node is a *moving ground*: eliminated like
the ground, its speed read from the source (:meth:`Assembly._prescribed` states the rules).
Friction elements that lock (coulomb-robust) add relations at run time;
the generated plant solves them in closed form (:mod:`clutchsim.network.codegen`).

Nothing here depends on scenarios: :mod:`clutchsim.scenario` builds a :class:`Network`
from a file, and the driveline's chain files are translated into one
(:func:`clutchsim.network.from_chain`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..core.system import closest
from .component import Component
from .spec import DOMAINS, Domain

__all__ = ["GROUND", "Assembly", "Network", "NetworkError"]

#: reserved node name of the housing (speed 0)
GROUND = "ground"

#: relative size below which a pivot of the constraint elimination counts as zero
_PIVOT_TOL = 1e-10


class NetworkError(ValueError):
    """A network that cannot be built; ``where`` names the component (and flange)."""

    def __init__(self, message: str, where: str = ""):
        super().__init__(message)
        self.where = where


@dataclass(frozen=True, eq=False)
class Network:
    """Components and the flanges they share.

    Parameters
    ----------
    components : sequence of Component
        Unique names.  Thermal nodes are components without flanges.
    connections : sequence of sequence of str
        Each entry joins two or more flanges, ``"component.flange"`` or ``"ground"``.
    name : str
    metadata : dict
        Kept with results.
    angles : bool
        Add an exact angle (position) state per inertia node, ``phi_<node>`` [rad]
        (``s_<node>`` [m] in the translational domain): ``dphi/dt`` = the node's speed.
        They are quadratures (nothing reads them): the implicit solve does not grow.  Off
        by default, so that default results keep their states.

    The network's domain (:attr:`domain`) follows from its components: all rotational
    (inertias, gears, clutches) or all translational (masses, forces, sliding friction).
    """

    components: tuple
    connections: tuple
    name: str = "driveline"
    metadata: dict = field(default_factory=dict)
    angles: bool = False

    def __post_init__(self):
        comps = tuple(self.components)
        object.__setattr__(self, "components", comps)
        object.__setattr__(self, "connections", tuple(tuple(c) for c in self.connections))
        for c in comps:
            if not isinstance(c, Component):
                raise NetworkError(f"network: {c!r} is not a network component")
        names = [c.name for c in comps]
        dup = sorted({n for n in names if names.count(n) > 1})
        if dup:
            raise NetworkError(f"network: two components are named {dup[0]!r}; component "
                               "names must be unique", dup[0])
        if GROUND in names:
            raise NetworkError(f"network: {GROUND!r} is reserved for the housing; rename "
                               "that component", GROUND)
        first: dict = {}
        for c in comps:
            if c.domain is not None:
                first.setdefault(c.domain, c)
        if len(first) > 1:
            (d1, c1), (d2, c2) = list(first.items())[:2]
            raise NetworkError(f"network: {c2.label} is {d2} but {c1.label} is {d1}: the "
                               "components of one network share one domain (rotational: "
                               "N·m, rad/s; translational: N, m/s)", c2.name)
        object.__setattr__(self, "_domain", next(iter(first), "rotational"))

    @property
    def domain(self) -> Domain:
        """The network's mechanical :class:`~clutchsim.network.spec.Domain` (names and
        units of its speeds, positions and torques or forces)."""
        return DOMAINS[self._domain]

    def component(self, name: str) -> Component:
        for c in self.components:
            if c.name == name:
                return c
        raise NetworkError(f"network: no component {name!r}"
                           f"{closest(name, [c.name for c in self.components])}", name)

    def parameter_values(self) -> dict[str, dict[str, dict]]:
        """Every value the equations read, per component: ``{component: {parameter:
        {"value", "unit", "description"}}}``
        (:meth:`~clutchsim.network.component.Component.parameter_values`), the
        ``parameters`` of a run's ``summary.json`` and its report."""
        return {c.name: c.parameter_values() for c in self.components}

    def compile(self):
        """The compiled :class:`~clutchsim.network.plant.Plan` (cached per topology)."""
        from .plant import compile_network
        return compile_network(self)

    def build(self, inputs0: dict | None = None):
        """The :class:`~clutchsim.core.System` of this network; ``inputs0`` (input name ->
        value at the start) lets switching elements with zero slip start free when their
        command is 0."""
        return self.compile().system(self.components, inputs0=inputs0, name=self.name,
                                     metadata=dict(self.metadata))

    def assemble(self) -> Assembly:
        """Nodes, the reduction to independent speeds and the checks (:class:`Assembly`)."""
        return Assembly(self)


def _parse_flange(net: Network, text, k: int):
    if not isinstance(text, str):
        raise NetworkError(f"connection {k + 1}: {text!r} must be a string "
                           "'component.flange' or 'ground'")
    if text == GROUND:
        return GROUND
    comp, sep, flange = text.partition(".")
    if not sep:
        c = net.component(comp)
        if len(c.flanges) == 1:
            return (comp, c.flanges[0])
        raise NetworkError(f"connection {k + 1}: {text!r} names a component, not one of its "
                           f"flanges ({', '.join(f'{comp}.{f}' for f in c.flanges)})", comp)
    c = net.component(comp)
    if flange in getattr(c, "internal_flanges", ()):
        raise NetworkError(f"connection {k + 1}: {text!r} is internal to {c.label} (it joins "
                           "two of its own parts); connect its other flanges "
                           f"({', '.join(f for f in c.flanges if f != flange)})", text)
    if flange not in c.flanges:
        raise NetworkError(f"connection {k + 1}: {c.label} has no flange {flange!r}"
                           f"{closest(flange, c.flanges)}; its flanges: "
                           f"{', '.join(c.flanges) or 'none'}", f"{comp}.{flange}")
    return (comp, flange)


class Assembly:
    """The network reduced to independent speeds (see the module docstring).

    Attributes
    ----------
    node_of : dict
        ``(component, flange) -> node index``.
    n_nodes, ground : int
        Node count; index of the ground node (always present).
    node_names : tuple of str
        A readable name per node (its first inertia, else its first flange).
    free : tuple of int
        The node whose speed is independent coordinate ``k``.
    """

    def __init__(self, net: Network):
        self.net = net
        parent: dict = {}

        def find(a):
            while parent.setdefault(a, a) != a:
                parent[a] = parent[parent[a]]
                a = parent[a]
            return a

        def union(a, b):
            ra, rb = find(a), find(b)
            if ra != rb:
                parent[rb] = ra

        find(GROUND)
        for c in net.components:
            for fa, fb in getattr(c, "joined", ()):
                union((c.name, fa), (c.name, fb))
        used = set()
        for k, conn in enumerate(net.connections):
            if len(conn) < 2:
                raise NetworkError(f"connection {k + 1}: {list(conn)!r} joins fewer than two "
                                   "flanges")
            ends = [_parse_flange(net, x, k) for x in conn]
            for a in ends:
                if a != GROUND and a in used and a in ends[:ends.index(a)]:
                    raise NetworkError(f"connection {k + 1} names {a[0]}.{a[1]} twice",
                                       f"{a[0]}.{a[1]}")
            for a in ends[1:]:
                union(ends[0], a)
            used.update(e for e in ends if e != GROUND)
        for c in net.components:
            optional = getattr(c, "optional_flanges", ())
            for f in c.flanges:
                key = (c.name, f)
                if key in used:
                    find(key)
                elif f in c.grounded:
                    union(GROUND, key)
                elif f in optional:
                    find(key)
                else:
                    raise NetworkError(f"{c.label}: flange {f!r} is connected to nothing; "
                                       f"connect it ('{c.name}.{f}') to another flange or "
                                       "to 'ground'", f"{c.name}.{f}")
        roots = []
        for key in [GROUND, *[(c.name, f) for c in net.components for f in c.flanges]]:
            r = find(key)
            if r not in roots:
                roots.append(r)
        index = {r: i for i, r in enumerate(roots)}
        self.ground = index[find(GROUND)]
        self.node_of = {(c.name, f): index[find((c.name, f))]
                        for c in net.components for f in c.flanges}
        self.n_nodes = len(roots)
        # node names: first inertia-carrying component at the node, else first flange
        names: list[str | None] = [None] * self.n_nodes
        names[self.ground] = GROUND
        self.J_owner: list[list[str]] = [[] for _ in range(self.n_nodes)]
        for c in net.components:
            bodies = c.inertias()
            for f in bodies:
                n = self.node_of[(c.name, f)]
                self.J_owner[n].append(c.name)
                if names[n] is None:    # a component with two bodies names them by flange
                    names[n] = c.name if len(bodies) == 1 else f"{c.name}_{f}"
        for c in net.components:
            for f in c.flanges:
                n = self.node_of[(c.name, f)]
                if names[n] is None:
                    names[n] = f"{c.name}_{f}"
        self.node_names = tuple(names)
        self.flanges_at = [[f"{c.name}.{f}" for c in net.components for f in c.flanges
                            if self.node_of[(c.name, f)] == n] for n in range(self.n_nodes)]
        self.prescribed = self._prescribed()
        self._reduce()

    # ------------------------------------------------------------------ prescribed motion
    def _prescribed(self) -> dict:
        """``node -> source`` of the prescribed-motion sources (a component with a
        ``prescribed_flange``): the node moves as the source says, like a moving ground.
        The rules (each a NetworkError naming the components): one source per node; not the
        ground; no rigid part (gear, planetary set, gear with losses) at the node, since the
        plant eliminates rigid parts as homogeneous relations and a prescribed node is not
        one of their coordinates; no friction element at the node, since a lock there would
        hold the relative acceleration at 0 against the prescribed one."""
        out: dict = {}
        for c in self.net.components:
            f = getattr(c, "prescribed_flange", None)
            if f is None:
                continue
            n = self.node_of[(c.name, f)]
            where = f"{c.name}.{f}"
            if n == self.ground:
                raise NetworkError(f"{c.label}: {where} is connected to the ground, which "
                                   "stands still: a prescribed motion of the housing (connect "
                                   "the source to the part it drives)", c.name)
            if n in out:
                raise NetworkError(f"{c.label}: {where} is at the node {out[n].label} already "
                                   "drives (two prescribed motions on one node fight each "
                                   "other: keep one)", c.name)
            out[n] = c
        for n, src in out.items():
            for c in self.net.components:
                if c is src:
                    continue
                here = [f for f in c.flanges if self.node_of[(c.name, f)] == n]
                if not here:
                    continue
                if c.constraints():
                    raise NetworkError(
                        f"{c.label}: its flange {c.name}.{here[0]} is at the node whose motion "
                        f"{src.label} prescribes; a rigid part may not touch a prescribed node "
                        "(two prescribed speeds on one rigid group fight each other, and the "
                        "plant eliminates rigid parts as relations between free speeds): "
                        "prescribe the motion on the other side of the gear, scaled by its "
                        "ratio, or put a compliant part between", c.name)
                if getattr(c, "friction", False):
                    raise NetworkError(
                        f"{c.label}: its flange {c.name}.{here[0]} is at the node whose motion "
                        f"{src.label} prescribes; a friction element may not touch a "
                        "prescribed node (locked, it would hold the relative acceleration at 0 "
                        "against the prescribed motion): put an inertia between the source and "
                        "the friction element (a drive's rotor), driven through a stiff spring "
                        "if needed", c.name)
        return out

    # ------------------------------------------------------------------ rigid relations
    def constraint_rows(self) -> tuple[np.ndarray, list[tuple[Component, int]]]:
        """``G`` (one row per rigid relation; the ground row first) and, per row after the
        first, (component, index of its relation)."""
        rows = []
        owners: list[tuple[Component, int]] = []
        g = np.zeros(self.n_nodes)
        g[self.ground] = 1.0
        rows.append(g)
        for c in self.net.components:
            for i, rel in enumerate(c.constraints()):
                r = np.zeros(self.n_nodes)
                for f, coef in rel.items():
                    r[self.node_of[(c.name, f)]] += coef
                rows.append(r)
                owners.append((c, i))
        return np.array(rows), owners

    def static_ratio(self, frm: tuple[str, str], to: tuple[str, str]) -> float | None:
        """``ω_frm/ω_to`` with every compliant coupling (a declared ``twist_flanges``: springs,
        lash, mounts, dual-mass flywheels) held rigid: the ratio of the gears between the two
        flanges, by which a torque at ``frm`` reaches ``to`` in a quasi-static driveline.
        ``frm``/``to``: (component, flange).  None when no gear path joins them (a friction
        element or a differential between, a flange at rest)."""
        rows = [self.G]
        for c in self.net.components:
            pair = getattr(c, "twist_flanges", None)
            if pair:
                r = np.zeros(self.n_nodes)
                r[self.node_of[(c.name, pair[0])]] += 1.0
                r[self.node_of[(c.name, pair[1])]] -= 1.0
                rows.append(r[None, :])
        N, _free, _rank = self.reduce(np.vstack(rows))
        a, b = N[self.node_of[frm]], N[self.node_of[to]]
        k = int(np.argmax(np.abs(b)))
        if b[k] == 0.0 or not np.allclose(a, a[k] / b[k] * b, rtol=1e-12, atol=1e-14):
            return None
        return float(a[k] / b[k])

    def node_inertia(self) -> np.ndarray:
        """Inertia at each node [kg·m²]."""
        J = np.zeros(self.n_nodes)
        for c in self.net.components:
            for f, v in c.inertias().items():
                J[self.node_of[(c.name, f)]] += v
        return J

    def _order(self) -> list[int]:
        """Nodes by preference as independent coordinates: inertia nodes in the order their
        components are listed, then massless nodes; ground last."""
        first = {}
        for k, c in enumerate(self.net.components):
            for f in c.flanges:
                first.setdefault(self.node_of[(c.name, f)], k)
        J = self.node_inertia()
        nodes = [n for n in range(self.n_nodes) if n != self.ground]
        nodes.sort(key=lambda n: (J[n] <= 0.0, first.get(n, 0), n))
        return [*nodes, self.ground]

    def reduce(self, G: np.ndarray, order=None):
        """``N`` (nodes × independent speeds) and the independent nodes for the relations
        ``G`` (rows), eliminating the least preferred nodes first."""
        order = self._order() if order is None else order
        R = G.astype(float).copy()
        cols = list(reversed(order))           # least preferred first: they get pivots
        pivots = []
        row = 0
        for c in cols:
            if row >= R.shape[0]:
                break
            scale = max(1.0, np.abs(R).max())
            i = row + int(np.argmax(np.abs(R[row:, c])))
            if abs(R[i, c]) <= _PIVOT_TOL * scale:
                continue
            R[[row, i]] = R[[i, row]]
            R[row] /= R[row, c]
            for k in range(R.shape[0]):
                if k != row and R[k, c] != 0.0:
                    R[k] -= R[k, c] * R[row]
            pivots.append((row, c))
            row += 1
        dep = {c: r for r, c in pivots}
        free = [n for n in order if n not in dep]
        N = np.zeros((self.n_nodes, len(free)))
        for k, n in enumerate(free):
            N[n, k] = 1.0
            for d, r in dep.items():
                N[d, k] = -R[r, n]
        N[np.abs(N) < 1e-14] = 0.0
        return N, free, len(pivots)

    def _reduce(self):
        G, owners = self.constraint_rows()
        self.G = G
        self.G_owners = owners
        N, free, rank = self.reduce(G)
        # a node the rigid parts hold at rest although it is not the ground: their ratios
        # disagree around a loop, or they tie it to the housing on both sides
        for n in range(self.n_nodes):
            if n != self.ground and n not in self.prescribed and not np.any(N[n]):
                parts = sorted({c.name for c, _ in owners
                                if any(self.node_of[(c.name, f)] == n for f in c.flanges)})
                raise NetworkError(
                    f"network: the rigid parts {', '.join(parts)} hold "
                    f"{', '.join(self.flanges_at[n])} at rest: their ratios disagree around a "
                    "loop (the product of the ratios around a loop must be 1), or they tie it "
                    "to the ground", parts[0] if parts else "")
        self.N = N
        self.free = tuple(free[:-1]) if free and free[-1] == self.ground else tuple(free)
        if self.ground in self.free:
            raise AssertionError("ground cannot be an independent coordinate")
        self.rank = rank
        self.n_v = N.shape[1]
        self.pattern = tuple(map(tuple, (N != 0.0).astype(int)))
        self.check_inertia(self.node_inertia())

    def check_inertia(self, J: np.ndarray, N: np.ndarray | None = None) -> np.ndarray:
        """The reduced inertia matrix ``Nᵀ·diag(J)·N`` (default ``N``: the assembly's), or a
        NetworkError naming the flanges of a coordinate without inertia."""
        N = self.N if N is None else N
        M = N.T @ (J[:, None] * N)
        if self.n_v == 0:
            return M
        w, vecs = np.linalg.eigh(M)
        scale = max(float(np.max(np.abs(J))), 1e-300)
        body, article = (("mass", "a") if self.net.domain.name == "translational"
                         else ("inertia", "an"))
        for k in range(self.n_v):
            if w[k] <= 1e-12 * scale:
                motion = N @ vecs[:, k]
                big = np.abs(motion) > 1e-9 * np.max(np.abs(motion))
                fl = [f for n in np.flatnonzero(big) for f in self.flanges_at[n]]
                moved = float(np.sum(J[big]))
                if moved > 0.0:
                    unit = "kg" if body == "mass" else "kg·m²"
                    raise NetworkError(
                        f"network: {', '.join(fl)} move only {moved:g} {unit} of {body}, "
                        f"below 1e-12 of the largest {body} ({scale:g} {unit}): too little "
                        "to integrate beside it (the speeds there would change 1e12 times "
                        f"faster); give it a realistic {body} (a clutch disc is ~0.01 kg·m²) "
                        "or join it rigidly to its neighbour", fl[0].split(".")[0] if fl else "")
                raise NetworkError(
                    f"network: {', '.join(fl)} can move without moving any {body} (a "
                    f"support or flange left floating): put {article} {body} there, or connect "
                    f"it to ground or to a part with {body}", fl[0].split(".")[0] if fl else "")
        return M
