"""From a :class:`~clutchsim.network.Network` to a compiled :class:`~clutchsim.core.System`.

:class:`Plan` lays out the states, the inputs and the parameter vector (the components'
values, then the *derived* block: ``N``, ``M⁻¹``, the slip rows ``B`` of the switching
friction elements, ``M⁻¹·Bᵀ``, ``S = B·M⁻¹·Bᵀ`` and the pseudo-inverse that gives the
torques in rigid parts), renders the plant module (:mod:`clutchsim.network.codegen`) and
builds :class:`~clutchsim.core.System` objects.  :meth:`Plan.system` with new values reuses
the compiled module: only the parameter vector is rebuilt.
"""

from __future__ import annotations

import functools

import numpy as np

from ..core import System
from .codegen import ENERGY, generate, load_module
from .invariants import build_invariants
from .network import Network, NetworkError

__all__ = ["Plan", "compile_network"]


class _InitCtx:
    def __init__(self, plan, speeds, inputs0):
        self.plan = plan
        self._w = speeds
        self.input0 = dict(inputs0 or {})

    def speed(self, comp: str, flange: str) -> float:
        return float(self._w[self.plan.asm.node_of[(comp, flange)]])


class Plan:
    """Layout and generated module of one network (see the module docstring)."""

    def __init__(self, net: Network):
        self.net = net
        self.asm = asm = net.assemble()
        comps = net.components
        self.thermal = [c for c in comps if getattr(c, "thermal", False)]
        self.mech_order = [c for c in comps if not getattr(c, "thermal", False)]
        self.fes = [c for c in comps if getattr(c, "friction", False)]
        for c in comps:
            c.check_network(net)
        self._check_parallel_clutches()
        # switching block: elements whose force reads the stick torque (lockable or not)
        # (lossy gears last: where a brake and a stuck gear hold the same part, the brake
        # carries the torque up to its capacity and the gear the rest; the split is not
        # unique, Modelica's LossyGearDemo2 documentation)
        sw = [c for c in self.fes if c.model.uses_stick_force]
        self.sw = ([c for c in sw if not getattr(c, "lossy", False)]
                   + [c for c in sw if getattr(c, "lossy", False)])
        lossy = [c for c in self.sw if getattr(c, "lossy", False)]
        if len(lossy) > 1:
            raise NetworkError(f"{lossy[1].label}: a second gear with losses ({lossy[0].label} "
                               "is the first); a network holds at most one (the plant solves "
                               "its loss in closed form)", lossy[1].name)
        self.sw_index = {c.name: i for i, c in enumerate(self.sw)}
        self.fe_index = {c.name: i for i, c in enumerate(self.fes)}
        # ---- signals between components, then the external inputs
        self.produced = produced_signals(comps)
        # prescribed-motion sources last: each books the power it delivers from the torques
        # every other component puts on its node (Emitter.applied)
        order = _signal_order(self.mech_order, self.produced)
        self.emit_order = ([c for c in order if c not in asm.prescribed.values()]
                           + [c for c in order if c in asm.prescribed.values()])
        names: list[str] = []
        units: list[str] = []
        for c in comps:
            for n in c.inputs():
                if n not in names and n not in self.produced:
                    names.append(n)
                    units.append(c.input_units().get(n, "-"))
        self.input_names, self.input_units = tuple(names), tuple(units)
        self.channel = {n: i for i, n in enumerate(names)}
        # ---- states
        sn, su = [], []
        self.state_index: dict = {}
        dom = self.domain = net.domain
        for k, node in enumerate(asm.free):
            sn.append(f"{dom.speed}_{asm.node_names[node]}")
            su.append(dom.speed_unit)
        for c in self.mech_order:
            for s_name, s_label, unit in c.state_layout():
                self.state_index[(c.name, s_name)] = len(sn)
                sn.append(s_label)
                su.append(unit)
        for c in self.thermal:
            self.state_index[(c.name, "theta")] = len(sn)
            sn.append(f"theta_{c.name}")
            su.append("°C")
        self.y_energy = len(sn)
        for e_name, _ in ENERGY:
            sn.append(e_name)
            su.append("J")
        # lining wear of friction elements with a wear law: quadratures after the accounts
        self.wearing = [c for c in self.fes if getattr(c, "wear", None) is not None]
        for c in self.wearing:
            self.state_index[(c.name, "wear")] = len(sn)
            sn.append(f"wear_{c.name}")
            su.append("m")
        # angle (position) states of the inertia nodes (Network.angles): dphi/dt = w_node.
        # Nothing reads them, so they are quadratures: the implicit solve (the inverted block) does
        # not grow, and their rows of the Jacobian are exact
        self.angle_states: list[tuple[int, int]] = []
        if net.angles:
            own = {c.name for c in comps if getattr(c, "own_position", False)}
            for n in range(asm.n_nodes):
                if n == asm.ground or not asm.J_owner[n] or own & set(asm.J_owner[n]):
                    continue
                self.angle_states.append((n, len(sn)))
                sn.append(f"{dom.position}_{asm.node_names[n]}")
                su.append(dom.position_unit)
        # each friction element's own friction work, where there are several (one alone is
        # W_friction, given as the output W_friction_<name>: no state of its own to carry)
        works = self.fes if len(self.fes) > 1 else []
        for c in works:
            self.state_index[(c.name, "work")] = len(sn)
            sn.append(f"W_friction_{c.name}")
            su.append("J")
        self.n_quadratures = (len(ENERGY) + len(self.wearing) + len(self.angle_states)
                              + len(works))
        self.state_names, self.state_units = tuple(sn), tuple(su)
        self.n = len(sn)
        # ---- parameter layout
        self.slot: dict = {}
        self.tables: dict = {}
        size = 0
        self._pack_shape = []
        self.value_range: dict = {}     # component -> (first, end) of its values in p
        for c in comps:
            first = size
            for key, val in c.pack().items():
                if np.ndim(val) == 0:
                    self.slot[(c.name, key)] = size
                    size += 1
                    self._pack_shape.append((c.name, key, 0))
                else:
                    n_val = int(np.size(val))
                    self.tables[(c.name, key)] = (size, n_val // 2 if key != "model" else
                                                  n_val)
                    size += n_val
                    self._pack_shape.append((c.name, key, n_val))
            self.value_range[c.name] = (first, size)
        self.n_values = size
        self._table_size = {(c, k): n for c, k, n in self._pack_shape if n}
        self._reductions: dict = {}
        nn, nv, m = asm.n_nodes, asm.n_v, len(self.sw)
        self.off_N = size
        self.off_Minv = self.off_N + nn * nv
        self.off_B = self.off_Minv + nv * nv
        self.off_MB = self.off_B + m * nv
        self.off_S = self.off_MB + nv * m
        self.off_J = self.off_S + m * m
        G, owners = asm.G, asm.G_owners
        self.relation_row = {(c.name, i): r + 1 for r, (c, i) in enumerate(owners)}
        self.n_rel = G.shape[0]
        self.off_Gp = self.off_J + nn
        self.off_G = self.off_Gp + self.n_rel * nn
        self.n_params = self.off_G + self.n_rel * nn
        self.slips = {c.name: self._slip_vector(c) for c in self.fes}
        self.topology = generate(self)
        # A force that jumps at zero slip (coulomb-naive) has no useful derivative there:
        # its exact Jacobian is 0 on both sides, and the integrator would shrink its steps
        # towards the jump for ever (a Zeno approach) instead of crossing it.  Differencing
        # sees the jump, the crossings are located, and chatter detection stops the run at
        # lock-up, as a naive model should.
        # (declared by the model: FrictionModel.jumps)
        self.exact_jacobian = not any(c.model.jumps for c in self.fes)
        self.module = load_module(self.topology, exact_jacobian=self.exact_jacobian)
        # the component each event belongs to, in the generated event order: the friction
        # elements' events first, then the components' own (render.event_layout)
        sources = [c.name for c in self.fes for _ in range(c.model.n_events)]
        sources += [self.event_templates[k][1] for k in sorted(self.event_templates)]
        self.event_sources = tuple(sources)
        self.kinds = {c.name: c.kind for c in comps}

    def _check_parallel_clutches(self) -> None:
        """Two clutches joining the same two nodes are one clutch pack, or a mistake: a
        dual-clutch transmission's clutches drive separate input shafts."""
        seen: dict = {}
        for c in self.fes:
            if getattr(c, "kind", "") != "clutch":
                continue
            pair = frozenset((self.asm.node_of[(c.name, "a")], self.asm.node_of[(c.name, "b")]))
            other = seen.get(pair)
            if other is not None:
                shafts = " and ".join(sorted(self.asm.node_names[n] for n in pair))
                raise NetworkError(f"{c.label}: joins the same shafts as {other.label} "
                                   f"({shafts}): two clutches commanded onto the same shaft "
                                   "(the clutches of a dual-clutch transmission drive "
                                   "separate input shafts; one clutch pack is one clutch)",
                                   c.name)
            seen[pair] = c

    # ------------------------------------------------------------------ layout helpers
    def _slip_vector(self, c) -> np.ndarray:
        g = np.zeros(self.asm.n_nodes)
        for f, coef in c.slip().items():
            g[self.asm.node_of[(c.name, f)]] += coef
        return g

    def N(self, i, k) -> str:
        """Entry (i, k) of ``N`` (1 exactly for the node of coordinate k itself)."""
        if i in self.asm.free:
            return "1.0"
        return f"p[{self.off_N + i * self.asm.n_v + k}]"

    def minv_pattern(self) -> np.ndarray:
        """Where ``M⁻¹`` can be non-zero: coordinates coupled through shared inertia."""
        asm = self.asm
        pat = np.array(asm.pattern, dtype=bool)
        J = asm.node_inertia() > 0.0
        M = (pat[J].T.astype(int) @ pat[J].astype(int)) > 0
        reach = M | np.eye(asm.n_v, dtype=bool)
        for _ in range(asm.n_v):
            reach = (reach.astype(int) @ reach.astype(int)) > 0
        return reach

    def node_speed(self, n: int) -> str:
        asm = self.asm
        if n == asm.ground:
            return "0.0"
        src = asm.prescribed.get(n)
        if src is not None:         # a prescribed node: the source's speed (its state)
            return src.speed_of(self)
        return self._free_speed(n)

    def speed_key(self, n: int) -> tuple:
        """The key of a partial derivative by the speed of node ``n``: ``("w", n)``, or
        for a prescribed node the source's speed state (``("y", index)``; the ground's key,
        which has no partials, for a constant speed)."""
        src = self.asm.prescribed.get(n)
        if src is None:
            return ("w", n)
        state = src.speed_state()
        return ("w", self.asm.ground) if state is None else \
            ("y", self.state_index[(src.name, state)])

    def _free_speed(self, n: int) -> str:
        asm = self.asm
        if n in asm.free:
            return f"y[{asm.free.index(n)}]"
        return _sum_products([(self.N(n, k), f"y[{k}]") for k in range(asm.n_v)
                              if asm.pattern[n][k]])

    def slip_expr(self, c) -> str:
        g = self.slips[c.name]
        return _sum_products([(repr(float(g[n])), f"w{n}") for n in np.flatnonzero(g)])

    def friction_prelude(self, gen, c) -> None:
        e = self.fe_index[c.name]
        gen.body.append(f"s{e} = {self.slip_expr(c)}")

    # ------------------------------------------------------------------ values
    def values_vector(self, comps=None) -> np.ndarray:
        """The parameter vector for the components' current values (plus derived).

        With scheduled value changes (:meth:`Component.schedule`, e.g. gear shifts) a bank
        of ``n_params`` values follows per change, holding all values in force after it;
        the plant copies it over the first ``n_params`` at that change's event."""
        comps = self.net.components if comps is None else comps
        p0 = self._values(comps)
        if not self.banks:
            return p0
        base = self.n_params
        out = np.empty(base * (1 + len(self.banks)))
        out[:base] = p0
        order = {c.name: i for i, c in enumerate(comps)}
        cur = {c.name: c for c in comps}
        entries = []
        for b, (name, j) in enumerate(self.banks):
            t, changes = cur[name].schedule()[j]
            if t is None:
                # a triggered change (a temperature-triggered fault): its time is the run's,
                # so its bank is the start's values with this component's changed, and the
                # plant copies only that component's values (render.py, _bank)
                one = [c.with_values(**changes) if c.name == name else c for c in comps]
                out[base * (b + 1):base * (b + 2)] = p_b = self._values(one)
                if not np.array_equal(p_b[self.n_values:], p0[self.n_values:]):
                    raise NetworkError(f"{cur[name].label}: a triggered change may not change "
                                       "inertias or rigid relations", name)
                continue
            entries.append(((float(t), order[name], j), name, changes, b))
        for _key, name, changes, b in sorted(entries, key=lambda x: x[0]):
            cur[name] = cur[name].with_values(**changes)
            out[base * (b + 1):base * (b + 2)] = self._values([cur[c.name] for c in comps])
        return out

    def _values(self, comps) -> np.ndarray:
        p = np.zeros(self.n_params)
        for c in comps:
            self._pack_into(p, c)
        self._derive(p, comps)
        return p

    def updated_vector(self, params, base, comps, changed) -> np.ndarray:
        """``params`` (the vector of the components ``base``) with the components at the
        indices ``changed`` of ``comps`` packed again.  The derived block is recomputed
        only when their inertias or rigid relations differ from those in ``base``."""
        if self.banks:      # the banks hold every value after each scheduled change
            return self.values_vector(comps)
        p = params.copy()
        inertias = relations = False
        for i in set(changed):
            self._pack_into(p, comps[i])
            inertias = inertias or comps[i].inertias() != base[i].inertias()
            relations = relations or comps[i].constraints() != base[i].constraints()
        if relations:
            self._derive(p, comps)
        elif inertias:      # N, G, its pseudo-inverse and B stay those already in p
            self._derive_inertia(p, comps, changed=set(changed))
        return p

    def _pack_into(self, p, c) -> None:
        for key, val in c.pack().items():
            slot = self.slot.get((c.name, key))
            if slot is not None:
                p[slot] = float(val)
                continue
            o, _n = self.tables[(c.name, key)]
            arr = np.asarray(val, dtype=float).ravel()
            n_val = self._table_size[(c.name, key)]
            if arr.size != n_val:
                raise NetworkError(f"{c.label}: {key} has {arr.size} entries, the compiled "
                                   f"network {n_val}; a table's length is part of the "
                                   "topology", c.name)
            p[o:o + n_val] = arr

    def _derive(self, p, comps) -> None:
        asm = self.asm
        # rigid relations may carry values (gear ratios): rebuild them from the components
        by_name = {c.name: c for c in comps}
        G = np.array(asm.G)
        for (c_name, i), row in self.relation_row.items():
            r = np.zeros(asm.n_nodes)
            for f, coef in by_name[c_name].constraints()[i].items():
                r[asm.node_of[(c_name, f)]] += coef
            G[row] = r
        nn, nv = asm.n_nodes, asm.n_v
        N, Gp, B = self._reduced(G)
        p[self.off_N:self.off_N + nn * nv] = N.ravel()
        p[self.off_B:self.off_B + len(self.sw) * nv] = B.ravel()
        p[self.off_Gp:self.off_Gp + self.n_rel * nn] = Gp.ravel()
        p[self.off_G:self.off_G + self.n_rel * nn] = G.ravel()
        self._derive_inertia(p, comps, G)

    def _derive_inertia(self, p, comps, G=None, changed=None) -> None:
        """The inertia part of the derived block (``J``, ``M⁻¹``, ``M⁻¹·Bᵀ``, ``S``) for the
        rigid relations ``G`` (default: those already in ``p``).  ``changed``: the indices
        of the only components whose inertias may differ from those behind the ``J``
        already in ``p``: only their nodes are summed again (in the same order, so to the
        same bits)."""
        asm = self.asm
        nn, nv, m = asm.n_nodes, asm.n_v, len(self.sw)
        if G is None:
            G = p[self.off_G:self.off_G + self.n_rel * nn].reshape(self.n_rel, nn)
        N, _Gp, B = self._reduced(G)
        terms = self._inertia_terms
        if changed is not None and any(set(comps[i].inertias()) != terms[2].get(i, set())
                                       for i in changed):
            changed = None      # a component that gained or lost an inertia: sum all
        if changed is None:
            J = np.zeros(nn)
            for c in comps:
                for f, v in c.inertias().items():
                    J[asm.node_of[(c.name, f)]] += v
        else:
            J = p[self.off_J:self.off_J + nn].copy()
            nodes = {n for i in changed for n in terms[1].get(i, ())}
            for n in nodes:
                total = 0.0
                for i, f in terms[0][n]:
                    total += comps[i].inertias()[f]
                J[n] = total
        M = N.T @ (J[:, None] * N)
        if asm.n_v:
            # λ_min(M) ≥ 1/‖M⁻¹‖_F: the inverse, needed anyway, clears M of the check's
            # eigen-decomposition; only a (near-)singular M is looked at (and named) there
            try:
                Minv = np.linalg.inv(M)
                # max |J| as the larger of max J and -min J: the same number, one
                # temporary fewer
                clear = 1.0 / np.linalg.norm(Minv) > 1e-12 * max(float(J.max()),
                                                                  -float(J.min()), 1e-300)
            except np.linalg.LinAlgError:
                Minv, clear = None, False
            if not clear:
                asm.check_inertia(J, N)
                if Minv is None:
                    Minv = np.linalg.inv(M)
        else:
            Minv = np.zeros((0, 0))
        MB = Minv @ B.T
        S = B @ MB
        p[self.off_Minv:self.off_Minv + nv * nv] = Minv.ravel()
        p[self.off_MB:self.off_MB + nv * m] = MB.ravel()
        p[self.off_S:self.off_S + m * m] = S.ravel()
        p[self.off_J:self.off_J + nn] = J

    @functools.cached_property
    def _inertia_terms(self) -> tuple:
        """``(node -> [(component index, flange), ...] in the order the components add
        their inertias, component index -> its nodes, component index -> its flanges
        with an inertia)``."""
        by_node: dict = {}
        nodes_of: dict = {}
        flanges_of: dict = {}
        for i, c in enumerate(self.net.components):
            for f in c.inertias():
                n = self.asm.node_of[(c.name, f)]
                by_node.setdefault(n, []).append((i, f))
                nodes_of.setdefault(i, set()).add(n)
                flanges_of.setdefault(i, set()).add(f)
        return by_node, nodes_of, flanges_of

    def _reduced(self, G) -> tuple:
        """``(N, pinv(Gᵀ), B)`` of the rigid relations ``G`` (``B``: the switching elements'
        slips in the independent speeds; the last few are kept: a sweep over anything but
        ratios meets the same ``G`` in every variant)."""
        key = G.tobytes()
        hit = self._reductions.get(key)
        if hit is not None:
            return hit
        asm = self.asm
        N, free, _rank = asm.reduce(G)
        free = tuple(f for f in free if f != asm.ground)
        if free != asm.free or tuple(map(tuple, (N != 0.0).astype(int))) != asm.pattern:
            raise NetworkError(f"network {self.net.name!r}: these values change which speeds "
                               "are independent (a ratio at 0 or a special value); build the "
                               "network again with them")
        B = np.array([self.slips[c.name] @ N for c in self.sw]).reshape(len(self.sw),
                                                                         asm.n_v)
        hit = (N, np.linalg.pinv(G.T), B)
        if len(self._reductions) >= 8:
            self._reductions.pop(next(iter(self._reductions)))
        self._reductions[key] = hit
        return hit

    # ------------------------------------------------------------------ initial state
    def initial_state(self, comps, inputs0=None) -> np.ndarray:
        asm = self.asm
        by_name = {c.name: c for c in comps}
        y0 = np.zeros(self.n)
        w = np.zeros(asm.n_nodes)
        given: dict[int, tuple[str, float]] = {}
        su = self.domain.speed_unit
        for c in comps:
            for f, val in c.initial_speeds().items():
                n = asm.node_of[(c.name, f)]
                if n in given and abs(given[n][1] - val) > 1e-12 * (1 + abs(val)):
                    raise NetworkError(f"{c.label}: initial speed {val:g} {su} at "
                                       f"{c.name}.{f} disagrees with {given[n][0]}'s "
                                       f"{given[n][1]:g} {su} at the same node", c.name)
                given.setdefault(n, (c.label, float(val)))
        for k, n in enumerate(asm.free):
            y0[k] = given.get(n, ("", 0.0))[1]
        w = asm.N @ y0[:asm.n_v]
        for n, (label, val) in given.items():
            if n in asm.prescribed:     # its source sets that speed (its initial state)
                continue
            if abs(w[n] - val) > 1e-9 * (1.0 + abs(val)):
                raise NetworkError(f"{label}: initial speed {val:g} {su} violates the rigid "
                                   f"parts: they give {w[n]:g} {su} at "
                                   f"{', '.join(asm.flanges_at[n])}", label.split("'")[1]
                                   if "'" in label else label)
        self._component_states(y0, by_name, _InitCtx(self, w, inputs0), None)
        return y0

    def _component_states(self, y0, by_name, ctx, only) -> None:
        """Write the components' own initial states into ``y0`` (all of them, or those
        named in ``only``)."""
        asm = self.asm
        for c in self.mech_order:
            if only is None or c.name in only:
                vals = by_name[c.name].initial_state(ctx)
                for (s_name, _lbl, _u), v in zip(c.state_layout(), vals):
                    y0[self.state_index[(c.name, s_name)]] = v
        for n, idx in self.angle_states:
            first = by_name[asm.J_owner[n][0]]
            if only is None or first.name in only:
                y0[idx] = (first.initial_position() if hasattr(first, "initial_position")
                           else 0.0)
        for c in self.thermal:
            if only is None or c.name in only:
                y0[self.state_index[(c.name, "theta")]] = by_name[c.name].theta0
        for c in self.wearing:
            if only is None or c.name in only:
                y0[self.state_index[(c.name, "wear")]] = by_name[c.name].wear0

    def initial_state_from(self, base: tuple, comps, changed, inputs0=None
                           ) -> np.ndarray | None:
        """:meth:`initial_state` of ``comps`` with ``inputs0``, from ``base`` = ``(its
        components, their initial state with these very inputs)`` where only the
        components named in ``changed`` differ: their own states computed again, the
        rest taken over.  The same numbers as :meth:`initial_state` (each component's
        states depend on its values and on the node speeds and inputs, which are the
        same), but only when no changed component gives other initial speeds (those move
        the node speeds); None then."""
        base_comps, base_y0 = base
        by_name = {c.name: c for c in comps}
        for c0 in base_comps:
            if c0.name in changed and by_name[c0.name].initial_speeds() != \
                    c0.initial_speeds():
                return None
        y0 = base_y0.copy()
        w = self.asm.N @ y0[:self.asm.n_v]
        self._component_states(y0, by_name, _InitCtx(self, w, inputs0), changed)
        return y0

    def state0(self, comps, inputs0, p, produced0: dict | None = None, base=None,
               changed=()) -> np.ndarray:
        """The initial state of ``comps`` with parameter vector ``p``: with the produced
        signals' values at that state among the initial inputs (a clutch commanded by a
        signal, a release system's play), passed again until they stop changing (a chain
        of signals takes one pass per link).  ``produced0``: a guess of those values (a
        variant's base run): when the state built with it gives them back, that state is
        the answer without a second pass; the passes are a finite chain, so the answer is
        the one a start without a guess reaches.  ``base``, ``changed``: the first pass
        from a base state (:meth:`initial_state_from`)."""
        inputs0 = dict(inputs0 or {})
        first = {**inputs0, **(produced0 or {})}
        y0 = None if base is None else self.initial_state_from(base, comps, changed, first)
        if y0 is None:
            y0 = self.initial_state(comps, first)
        if not self.produced:
            return y0
        u = np.array([inputs0.get(n, 0.0) for n in self.input_names], dtype=float)
        out = np.zeros(len(self.output_names))
        pp = p[:self.n_params].copy()
        used = produced0
        for _ in range(len(self.produced) + 1):
            self.module.FUNCTIONS["outputs"](0.0, y0, u, pp, out)
            vals = {n: float(out[i]) for n, i in self._produced_at.items()}
            if vals == used:
                break
            y1 = self.initial_state(comps, {**inputs0, **vals})
            used = vals
            if np.array_equal(y1, y0):
                break
            y0 = y1
        return y0

    @functools.cached_property
    def invariants(self):
        """The physics checks of every run of this plant (:mod:`.invariants`)."""
        return build_invariants(self)

    @functools.cached_property
    def _produced_at(self) -> dict:
        """Produced signal -> its index among the outputs."""
        return {n: self.output_names.index(n) for n in self.produced}

    def produced0(self, system: System, inputs0=None) -> dict:
        """The produced signals' values at the initial state of ``system`` with the initial
        inputs ``inputs0``: the guess :meth:`state0` takes for a variant."""
        if not self.produced:
            return {}
        inputs0 = dict(inputs0 or {})
        u = np.array([inputs0.get(n, 0.0) for n in self.input_names], dtype=float)
        out = np.zeros(len(self.output_names))
        self.module.FUNCTIONS["outputs"](0.0, system.y0, u, system.params[:self.n_params].copy(),
                                         out)
        return {n: float(out[i]) for n, i in self._produced_at.items()}

    def _event_names(self, comps) -> tuple[str, ...]:
        by_name = {c.name: c for c in comps}
        ev_names = list(self.event_names)
        for k, tmpl in self.event_templates.items():
            comp = by_name[tmpl[1]]
            vals = comp.format_values() if hasattr(comp, "format_values") else comp.values
            ev_names[k] = tmpl[0].format(**vals)
        return tuple(ev_names)

    # ------------------------------------------------------------------ system
    def system(self, comps=None, inputs0=None, *, name=None, metadata=None,
               params=None) -> System:
        """The :class:`~clutchsim.core.System` for ``comps`` (same topology as the plan's
        network; default: its own components).  ``params``: their parameter vector when
        the caller already has it (:meth:`values_vector`)."""
        comps = self.net.components if comps is None else tuple(comps)
        p = self.values_vector(comps) if params is None else params
        y0 = self.state0(comps, inputs0, p)
        meta = dict(self.net.metadata if metadata is None else metadata)
        meta.update({"models": {c.name: c.model.name for c in self.fes},
                     "nodes": [self.asm.node_names[n] for n in self.asm.free],
                     "network": self.topology.key, "kinds": self.kinds,
                     "domain": self.domain.name})
        return System(self.module.TAG(0), p, y0, self.state_names, self.state_units,
                      input_names=self.input_names, input_units=self.input_units,
                      output_names=self.output_names, output_units=self.output_units,
                      event_names=self._event_names(comps),
                      event_directions=self.event_directions,
                      event_sources=self.event_sources,
                      name=name or self.net.name, metadata=meta,
                      quadratures=self.n_quadratures, invariants=self.invariants)

    def variant_state(self, comps, params, inputs0=None, changed=(),
                      produced0: dict | None = None, base=None) -> tuple:
        """``(y0, event_names)`` of a variant: the initial state for the components
        ``comps`` with parameter vector ``params`` (``produced0``: the produced signals'
        guess, :meth:`produced0` of the base system), and its event names, formatted
        again only where a component named in ``changed`` formats one from its values
        (else None: the base system's).  ``base``: see :meth:`initial_state_from` (the
        base components' state with the inputs ``inputs0`` and ``produced0``)."""
        comps = tuple(comps)
        changed = set(changed)
        y0 = self.state0(comps, inputs0, params, produced0, base, changed)
        names = (self._event_names(comps) if any(t[1] in changed for t in
                                                 self.event_templates.values()) else None)
        return y0, names

    # ------------------------------------------------------------------ rendering
    def render(self, g) -> str:
        from .render import render
        return render(self, g)


def produced_signals(comps) -> dict:
    """Full signal name -> (producing component, unit) of every produced signal."""
    out: dict = {}
    for c in comps:
        for local, unit in c.signals().items():
            out[c.signal_name(local)] = (c, unit)
    return out


def _signal_order(comps, produced) -> list:
    """``comps`` with every producer of a feedthrough signal before its consumers (stable:
    otherwise in the listed order); a loop of feedthrough signals is a NetworkError naming
    it (a component whose signals follow from its states breaks a loop)."""
    deps = {}
    for c in comps:
        deps[c.name] = [produced[n][0] for n in c.inputs()
                        if n in produced and produced[n][0].feedthrough
                        and produced[n][0] is not c]
    for c in comps:
        own = [n for n in c.inputs() if n in produced and produced[n][0] is c]
        if own and c.feedthrough:
            raise NetworkError(f"{c.label}: reads its own signal {own[0]!r} at the same "
                               "instant (an algebraic loop)", c.name)
    order: list = []
    state: dict = {}

    def visit(c, path):
        st = state.get(c.name)
        if st == 2:
            return
        if st == 1:
            loop = path[path.index(c.name):] + [c.name]
            raise NetworkError(f"{c.label}: a loop of signals that no state breaks: "
                               f"{' -> '.join(loop)} (each reads the next one's signal at "
                               "the same instant; put a lag, an actuator or another "
                               "component with states in the loop)", c.name)
        state[c.name] = 1
        for d in deps[c.name]:
            visit(d, [*path, c.name])
        state[c.name] = 2
        order.append(c)

    for c in comps:
        visit(c, [])
    return order


def _sum_products(pairs) -> str:
    terms = [f"{a} * {b}" for a, b in pairs]
    return " + ".join(terms) if terms else "0.0"


_PLANS: dict = {}


def structure_key(net: Network) -> tuple:
    """What shapes the generated plant of ``net`` (components' structures, connections,
    the angle states)."""
    return (tuple(c.structure() for c in net.components), net.connections, net.angles)


def compile_network(net: Network) -> Plan:
    """The :class:`Plan` of ``net``: generated, compiled and cached on disk once per
    topology, and kept in memory per process (a network of the same structure with other
    values reuses it: pass its components to :meth:`Plan.system`)."""
    key = structure_key(net)
    plan = _PLANS.get(key)
    if plan is None:
        plan = _PLANS[key] = Plan(net)
    else:       # checks of values against the network (a tyre's radius and its vehicle's)
        for c in net.components:
            c.check_network(net)
    return plan
