"""Assemble components into the compiled chain plant (:mod:`clutchsim.driveline.plant`)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from ..core import System, register_system
from . import plant as P
from .components import (
    Brake,
    Engine,
    FrictionElement,
    Gear,
    Gearbox,
    Inertia,
    LossyGear,
    OneWayClutch,
    SpringDamper,
    Vehicle,
    has_losses,
    static_capacity,
)

__all__ = ["ENERGY_STATES", "Chain", "ChainPlant"]

#: energy-account states (integrals) [J]
ENERGY_STATES = ("W_in", "W_friction", "W_damping", "W_road", "E_grade", "W_sync")

_SWITCHING = ("coulomb-robust",)


class ChainPlant(NamedTuple):
    """Tag type of the driveline chain plant."""

    k: int = 0


register_system(ChainPlant, rhs=P.chain_rhs, events=P.chain_events, reset=P.chain_reset,
                outputs=P.chain_outputs)


#: couplings that can carry gear losses (a switching lossy element in the plant)
_LOSSY = (LossyGear, Gearbox)


@dataclass(frozen=True)
class Chain:
    """Inertias in series joined by couplings, with brakes, an engine, a vehicle and heat.

    Parameters
    ----------
    inertias : tuple of Inertia
        The nodes, in order (engine side first).
    couplings : tuple
        ``len(inertias) - 1`` couplings: :class:`Gear`, :class:`Gearbox`, :class:`LossyGear`
        (at most one with losses per chain), :class:`SpringDamper`, :class:`FrictionElement`
        or :class:`OneWayClutch`; coupling k joins inertia k to k+1.
    brakes : tuple of Brake
        Friction elements to ground.
    engine : Engine, optional
    vehicle : Vehicle, optional
        Attached to the last inertia.
    thermal : tuple of ThermalNode
    name : str
    """

    inertias: tuple
    couplings: tuple
    brakes: tuple = ()
    engine: Engine | None = None
    vehicle: Vehicle | None = None
    thermal: tuple = ()
    name: str = "driveline"
    metadata: dict = field(default_factory=dict)

    def __post_init__(self):
        object.__setattr__(self, "inertias", tuple(self.inertias))
        object.__setattr__(self, "couplings", tuple(self.couplings))
        object.__setattr__(self, "brakes", tuple(self.brakes))
        object.__setattr__(self, "thermal", tuple(self.thermal))
        if not self.inertias or not all(isinstance(i, Inertia) for i in self.inertias):
            raise ValueError("chain: needs at least one Inertia (and only Inertia objects)")
        if len(self.couplings) != len(self.inertias) - 1:
            raise ValueError(f"chain: {len(self.inertias)} inertias need "
                             f"{len(self.inertias) - 1} couplings, got {len(self.couplings)}")
        for c in self.couplings:
            if not isinstance(c, (Gear, Gearbox, LossyGear, SpringDamper, FrictionElement,
                                  OneWayClutch)) or isinstance(c, Brake):
                # contract: every invalid chain raises ValueError, whatever the fault
                raise ValueError(f"chain: {c!r} is not a coupling")  # noqa: TRY004
        lossy = [c.name for c in self.lossy_gears]
        if len(lossy) > 1:
            raise ValueError(f"chain: at most one gear with losses (lossy gear, or gearbox "
                             f"with an efficiency below 1 or a drag torque) per chain (the "
                             f"loss of a rolling gear is solved in closed form), got {lossy}")
        names = [x.name for x in (*self.inertias, *self.couplings, *self.brakes)]
        dup = {n for n in names if names.count(n) > 1}
        if dup:
            raise ValueError(f"chain: duplicate component names {sorted(dup)}")
        nodes = self.node_names
        for b in self.brakes:
            if b.node not in nodes:
                raise ValueError(f"brake {b.name!r}: node {b.node!r} is not an inertia "
                                 f"(inertias: {', '.join(nodes)})")
        if self.engine is not None and self.engine.node not in nodes:
            raise ValueError(f"engine: node {self.engine.node!r} is not an inertia "
                             f"(inertias: {', '.join(nodes)})")
        th = [t.name for t in self.thermal]
        dup_th = {n for n in th if th.count(n) > 1}
        if dup_th:
            raise ValueError(f"chain: duplicate thermal node names {sorted(dup_th)}")
        linked = set()
        for t in self.thermal:
            if t.link is None:
                continue
            if t.link not in th:
                raise ValueError(f"thermal node {t.name!r}: link {t.link!r} is not a thermal "
                                 f"node (nodes: {', '.join(th)})")
            pair = frozenset((t.name, t.link))
            if pair in linked:
                raise ValueError(f"thermal nodes {t.name!r} and {t.link!r} are linked twice; "
                                 "declare the link on one of them only")
            linked.add(pair)
        for fe in self.friction_elements:
            for n, _ in fe.heat:
                if n not in th:
                    raise ValueError(f"friction element {fe.name!r}: heat goes to thermal node "
                                     f"{n!r}, which does not exist (nodes: {', '.join(th)})")
            if fe.mu_temperature is not None and not fe.heat:
                raise ValueError(f"friction element {fe.name!r}: mu_temperature needs a "
                                 "thermal node (heat)")

    @property
    def node_names(self) -> tuple[str, ...]:
        return tuple(i.name for i in self.inertias)

    @property
    def friction_elements(self) -> tuple:
        """Clutches, one-way clutches (couplings, in chain order) and brakes."""
        return tuple(c for c in self.couplings
                     if isinstance(c, (FrictionElement, OneWayClutch))) + self.brakes

    @property
    def lossy_gears(self) -> tuple:
        """Lossy gears and gearboxes with losses (without losses they are plain gears)."""
        return tuple(c for c in self.couplings if has_losses(c))

    @property
    def elements(self) -> tuple:
        """Switching elements of the plant: friction couplings and lossy gears in chain
        order, then the brakes."""
        return tuple(c for c in self.couplings
                     if isinstance(c, (FrictionElement, OneWayClutch)) or has_losses(c)) \
            + self.brakes

    def input_names(self) -> tuple[str, ...]:
        """Input signals the plant reads, in channel order."""
        names: list[str] = []
        for i in self.inertias:
            if i.load and i.load not in names:
                names.append(i.load)
        if self.engine is not None and self.engine.throttle not in names:
            names.append(self.engine.throttle)
        for fe in self.friction_elements:
            if fe.command not in names:
                names.append(fe.command)
        return tuple(names)

    def input_units(self) -> tuple[str, ...]:
        """Unit of each input of :meth:`input_names`: a load on an inertia is a torque
        [N·m]; the throttle and the friction commands (COM, or a pedal position read
        through a clamp table) are fractions [-]."""
        loads = {i.load for i in self.inertias if i.load}
        return tuple("N·m" if n in loads else "-" for n in self.input_names())

    def _omega0(self) -> np.ndarray:
        return np.array([i.omega0 for i in self.inertias])

    def network_unsupported(self) -> str | None:
        """Why this chain cannot run as a :class:`~clutchsim.network.Network` yet (a lossy
        gear, a gearbox with losses or shifts, a one-way clutch), or None."""
        for c in self.couplings:
            if has_losses(c):
                return f"{c.name}: a gear with losses"
            if isinstance(c, Gearbox) and c.shifts:
                return f"{c.name}: a gearbox that shifts"
            if isinstance(c, OneWayClutch):
                return f"{c.name}: a one-way clutch"
        return None

    def network(self):
        """This chain as a :class:`~clutchsim.network.Network` (the documented
        translation, ``docs/network.md``): each inertia an inertia, each coupling the
        component of its kind between inertia k (flange a) and k+1 (flange b), a coupling's
        own ``ratio`` an ideal gear on its input side, a gearbox the ideal gear of its
        selected gear, a load input a torque source, brakes on their inertia, the engine on
        its inertia, the vehicle on the last inertia."""
        from .. import network as nw
        from ..network import components as nc
        why = self.network_unsupported()
        if why is not None:
            raise nw.NetworkError(f"chain {self.name!r}: {why} is not a network component yet")
        comps, conns = [], []
        for i in self.inertias:
            comps.append(nc.Inertia(i.name, J=i.J, omega0=i.omega0,
                                    bearing_damping=i.bearing_damping))
            if i.load:
                comps.append(nc.TorqueSource(f"{i.name}_load", input=i.load))
                conns.append((f"{i.name}_load.flange", f"{i.name}.a"))
        for k, c in enumerate(self.couplings):
            a, b = f"{self.inertias[k].name}.b", f"{self.inertias[k + 1].name}.a"
            if isinstance(c, (Gear, LossyGear, Gearbox)):
                ratio = c.ratio(c.gear) if isinstance(c, Gearbox) else c.ratio
                comps.append(nc.IdealGear(c.name, ratio=ratio))
                conns += [(a, f"{c.name}.a"), (f"{c.name}.b", b)]
                continue
            if c.ratio != 1.0:
                g = f"{c.name}_ratio"
                comps.append(nc.IdealGear(g, ratio=c.ratio))
                conns.append((a, f"{g}.a"))
                a = f"{g}.b"
            if isinstance(c, SpringDamper):
                comps.append(nc.SpringDamper(c.name, c=c.c, d=c.d, knee=c.knee, c2=c.c2,
                                             phi0=c.phi0))
            else:
                comps.append(nc.Clutch(c.name, c.model, c.command, clamp_table=c.clamp_table,
                                       mu_temperature=c.mu_temperature, mu_slip=c.mu_slip,
                                       heat=c.heat, locked0=c.locked0, z0=c.z0, drag=c.drag))
            conns += [(a, f"{c.name}.a"), (f"{c.name}.b", b)]
        for br in self.brakes:
            comps.append(nc.Brake(br.name, br.model, br.command, clamp_table=br.clamp_table,
                                  mu_temperature=br.mu_temperature, mu_slip=br.mu_slip,
                                  heat=br.heat, locked0=br.locked0, z0=br.z0, drag=br.drag))
            conns.append((f"{br.name}.flange", f"{br.node}.a"))
        if self.engine is not None:
            eng = self.engine
            comps.append(nc.Engine("engine_torque", eng.speeds, eng.torques, eng.throttle,
                                   drag0=eng.drag0, drag1=eng.drag1, idle_speed=eng.idle_speed,
                                   kp=eng.kp, ki=eng.ki, stall_speed=eng.stall_speed))
            conns.append(("engine_torque.flange", f"{eng.node}.a"))
        if self.vehicle is not None:
            v = self.vehicle
            comps.append(nc.Vehicle("vehicle", mass=v.mass, tyre_radius=v.tyre_radius,
                                    grade=v.grade, rolling=v.rolling, cd_area=v.cd_area,
                                    air_density=v.air_density, v_eps=v.v_eps,
                                    gravity=v.gravity))
            conns.append(("vehicle.flange", f"{self.inertias[-1].name}.a"))
        for t in self.thermal:
            comps.append(nc.ThermalNode(t.name, capacity=t.capacity, conductance=t.conductance,
                                        ambient=t.ambient, theta0=t.theta0, link=t.link,
                                        link_conductance=t.link_conductance))
        return nw.Network(comps, conns, name=self.name, metadata=dict(self.metadata))

    def build(self, inputs0: dict | None = None) -> System:
        """The compiled :class:`~clutchsim.core.System` of this chain.

        ``inputs0`` (input name -> value at the start time) lets switching friction
        elements with zero slip start free when their command is 0 (else they start
        locked).  Chains the network supports run on their generated network plant
        (:meth:`network`); the others on the chain plant.
        """
        if self.network_unsupported() is None:
            # the chain is immutable: its network, plan and parameter vector are built once
            cached = self.__dict__.get("_compiled")
            if cached is None:
                from ..network import compile_network
                net = self.network()
                plan = compile_network(net)
                cached = (net, plan, plan.values_vector(net.components))
                object.__setattr__(self, "_compiled", cached)
            net, plan, params = cached
            return plan.system(net.components, inputs0=inputs0, name=self.name,
                               metadata=dict(self.metadata), params=params.copy())
        self_inputs0 = dict(inputs0 or {})
        inertias, couplings = self.inertias, self.couplings
        n = len(inertias)
        fes = self.elements
        fe_index = {fe.name: e for e, fe in enumerate(fes)}
        inputs = self.input_names()
        chan = {name: i for i, name in enumerate(inputs)}
        th_index = {t.name: i for i, t in enumerate(self.thermal)}
        omega0 = self._omega0()
        # ---- state layout
        snames = [f"omega_{i.name}" for i in inertias]
        sunits = ["rad/s"] * n
        y0 = list(omega0)
        y_twist = len(y0)
        twist_idx = {}
        for k, c in enumerate(couplings):
            if isinstance(c, SpringDamper):
                twist_idx[k] = len(y0)
                snames.append(f"phi_{c.name}")
                sunits.append("rad")
                y0.append(c.phi0)
            elif isinstance(c, Gearbox):
                twist_idx[k] = len(y0)
                snames.append(f"ratio_{c.name}")
                sunits.append("-")
                y0.append(c.ratio(c.gear))
        # initial speeds must satisfy the rigid gears
        ratios = []
        for k, c in enumerate(couplings):
            r = c.ratio(c.gear) if isinstance(c, Gearbox) else c.ratio
            ratios.append(r)
            if isinstance(c, (Gear, Gearbox, LossyGear)) and \
                    not np.isclose(omega0[k + 1], omega0[k] / r, rtol=1e-12, atol=1e-12):
                kind = {Gear: "gear", Gearbox: "gearbox", LossyGear: "lossy gear"}[type(c)]
                raise ValueError(f"{kind} {c.name!r}: initial speeds "
                                 f"violate the ratio: omega0 of {inertias[k + 1].name!r} = "
                                 f"{omega0[k + 1]:g} rad/s, but omega0 of "
                                 f"{inertias[k].name!r} / {r:g} = {omega0[k] / r:g} rad/s")
        y_z = len(y0)
        z_idx = []
        for fe in fes:
            z_idx.append(len(y0))
            z0 = self._z0(fe, omega0, ratios, self_inputs0)
            for s_name, s_unit, v in zip(*self._state_spec(fe), z0):
                snames.append(f"{fe.name}.{s_name}")
                sunits.append(s_unit)
                y0.append(v)
        y_lock = len(y0)
        for fe in fes:
            snames.append(f"{fe.name}.locked")
            sunits.append("-")
            y0.append(1.0 if self._locked0(fe, omega0, ratios, self_inputs0) else 0.0)
        y_th = len(y0)
        for t in self.thermal:
            snames.append(f"theta_{t.name}")
            sunits.append("°C")
            y0.append(t.theta0)
        y_gov = len(y0)
        if self.engine is not None and self.engine.idle_speed > 0:
            snames.append("engine.governor_integral")
            sunits.append("rad")
            y0.append(0.0)
        y_en = len(y0)
        for e_name in ENERGY_STATES:
            snames.append(e_name)
            sunits.append("J")
            y0.append(0.0)
        # ---- events
        ev_names, ev_dirs = [], []
        ev_off = []
        for fe in fes:
            ev_off.append(len(ev_names))
            if isinstance(fe, (*_LOSSY, OneWayClutch)):
                ev_names += [f"{fe.name}: stop", f"{fe.name}: breakaway"]
                ev_dirs += [-1, -1]
            else:
                ev_names += [f"{fe.name}: {e}" for e in fe.model.event_names()]
                ev_dirs += [int(d) for d in fe.model.event_directions()]
        ev_stall = len(ev_names)
        if self.engine is not None:
            ev_names.append(f"engine stalled (speed fell below {self.engine.stall_speed:g} "
                            f"rad/s = {self.engine.stall_speed * 30 / np.pi:.0f} rpm)")
            ev_dirs.append(-1)
        # ---- parameter vector
        head = np.zeros(P.HEADER)
        data: list[float] = []

        def block(width):
            off = P.HEADER + len(data)
            data.extend([0.0] * width)
            return off

        def put(off, idx, value):
            data[off - P.HEADER + idx] = float(value)

        def table(xs, ys):
            off = P.HEADER + len(data)
            data.extend(float(x) for x in xs)
            data.extend(float(v) for v in ys)
            return off

        head[P.H_N], head[P.H_NF], head[P.H_NTH] = n, len(fes), len(self.thermal)
        head[P.H_ENG] = 1.0 if self.engine is not None else 0.0
        head[P.H_VEH] = 1.0 if self.vehicle is not None else 0.0
        head[P.H_YTW], head[P.H_YZ], head[P.H_YLK] = y_twist, y_z, y_lock
        head[P.H_YTH], head[P.H_YGOV], head[P.H_YEN] = y_th, y_gov, y_en
        head[P.H_EVSTALL] = ev_stall
        node_off = [block(P.NODE_W) for _ in range(n)]
        head[P.H_NODE] = node_off[0]
        for j, i in enumerate(inertias):
            J = i.J + (self.vehicle.equivalent_inertia if self.vehicle and j == n - 1 else 0.0)
            put(node_off[j], P.N_J, J)
            put(node_off[j], P.N_D, i.bearing_damping)
            put(node_off[j], P.N_LOAD, chan[i.load] if i.load else -1)
        cpl_off = [block(P.CPL_W) for _ in range(max(n - 1, 1))]
        head[P.H_CPL] = cpl_off[0]
        shift_pending = []
        for k, c in enumerate(couplings):
            o = cpl_off[k]
            put(o, P.C_RATIO, ratios[k])
            put(o, P.C_FE, -1)
            if isinstance(c, Gear) or (isinstance(c, LossyGear) and c.ideal):
                put(o, P.C_KIND, P.GEAR)
            elif isinstance(c, LossyGear):
                put(o, P.C_KIND, P.LOSSY_GEAR)
                put(o, P.C_FE, fe_index[c.name])
            elif isinstance(c, Gearbox):
                put(o, P.C_KIND, P.SHIFT_GEAR)
                put(o, P.C_Y, twist_idx[k])
                if has_losses(c):
                    put(o, P.C_FE, fe_index[c.name])
                shift_pending.append((k, c))
            elif isinstance(c, SpringDamper):
                put(o, P.C_KIND, P.SPRING)
                put(o, P.C_Y, twist_idx[k])
                for idx, v in ((P.C_C1, c.c), (P.C_D, c.d), (P.C_KNEE, c.knee), (P.C_C2, c.c2)):
                    put(o, idx, v)
            else:
                put(o, P.C_KIND, P.FRICTION)
                put(o, P.C_FE, fe_index[c.name])
        # shifts: times, new ratios, first event index
        for k, gb in shift_pending:
            put(cpl_off[k], P.C_NSH, len(gb.shifts))
            off = P.HEADER + len(data)
            data.extend(float(t) for t, _ in gb.shifts)
            data.extend(gb.ratio(g) for _, g in gb.shifts)
            data.append(float(len(ev_names)))
            put(cpl_off[k], P.C_SHOFF, off)
            for t, g in gb.shifts:
                ev_names.append(f"{gb.name}: shift to gear {g} at {t:g} s")
                ev_dirs.append(1)
        fe_off = [block(P.FE_W) for _ in range(max(len(fes), 1))]
        head[P.H_FE] = fe_off[0]
        nodes = self.node_names
        for e, fe in enumerate(fes):
            o = fe_off[e]
            put(o, P.F_YZ, z_idx[e])
            put(o, P.F_YLK, y_lock + e)
            put(o, P.F_EV, ev_off[e])
            put(o, P.F_THA, -1)
            put(o, P.F_THB, -1)
            if isinstance(fe, _LOSSY):
                # the loss acts like a brake on the flange-a inertia of the (rigid) gear
                put(o, P.F_KIND, P.FK_LOSSY)
                put(o, P.F_LOC, P.LOC_BRAKE)
                put(o, P.F_IDX, couplings.index(fe))
                put(o, P.F_NZ, 1)
                put(o, P.F_NEV, 2)
                put(o, P.F_IN, -1)
                put(o, P.F_CAP, 0.0)
                cols = fe.columns()
                aux = P.HEADER + len(data)
                data.append(float(len(cols[0])))
                for col in cols:
                    data.extend(float(v) for v in col)
                put(o, P.F_AUX, aux)
                continue
            if isinstance(fe, Brake):
                put(o, P.F_LOC, P.LOC_BRAKE)
                put(o, P.F_IDX, nodes.index(fe.node))
            else:
                put(o, P.F_LOC, P.LOC_COUPLING)
                put(o, P.F_IDX, couplings.index(fe))
            if isinstance(fe, OneWayClutch):
                put(o, P.F_KIND, P.FK_ONE_WAY)
                put(o, P.F_AUX, fe.free_threshold)
                put(o, P.F_NEV, 2)
            else:
                put(o, P.F_KIND, P.FK_MODEL)
                put(o, P.F_NEV, fe.model.n_events)
            put(o, P.F_CODE, fe.model.code)
            put(o, P.F_NZ, fe.model.n_states)
            put(o, P.F_IN, chan[fe.command])
            put(o, P.F_DRAG, fe.drag)
            put(o, P.F_CAP, static_capacity(fe.model))
            for slot, (tn, share) in zip(((P.F_THA, P.F_SHA), (P.F_THB, P.F_SHB)), fe.heat):
                put(o, slot[0], th_index[tn])
                put(o, slot[1], share)
            for key, (i_off, i_n) in (("clamp_table", (P.F_ACT, P.F_NACT)),
                                      ("mu_temperature", (P.F_MUT, P.F_NMUT)),
                                      ("mu_slip", (P.F_MUS, P.F_NMUS))):
                tab = getattr(fe, key)
                if tab is not None:
                    put(o, i_off, table(*tab))
                    put(o, i_n, len(tab[0]))
        for e, fe in enumerate(fes):   # model parameters last: kernels read p[off:]
            off = P.HEADER + len(data)
            if not isinstance(fe, _LOSSY):
                data.extend(fe.model.pack().tolist())
            put(fe_off[e], P.F_PAR, off)
        th_off = [block(P.TH_W) for _ in range(max(len(self.thermal), 1))]
        head[P.H_TH] = th_off[0]
        for i, t in enumerate(self.thermal):
            put(th_off[i], P.T_C, t.capacity)
            put(th_off[i], P.T_HA, t.conductance)
            put(th_off[i], P.T_AMB, t.ambient)
            put(th_off[i], P.T_LINK, th_index[t.link] if t.link is not None else -1)
            put(th_off[i], P.T_G, t.link_conductance)
        if self.engine is not None:
            eng = self.engine
            o = block(P.ENG_W)
            head[P.H_ENGB] = o
            put(o, P.E_NODE, nodes.index(eng.node))
            put(o, P.E_TAB, table(eng.speeds, eng.torques))
            put(o, P.E_NTAB, len(eng.speeds))
            put(o, P.E_IN, chan[eng.throttle])
            for idx, v in ((P.E_D0, eng.drag0), (P.E_D1, eng.drag1), (P.E_IDLE, eng.idle_speed),
                           (P.E_KP, eng.kp), (P.E_KI, eng.ki), (P.E_STALL, eng.stall_speed)):
                put(o, idx, v)
            put(o, P.E_GOV, 1.0 if eng.idle_speed > 0 else 0.0)
        if self.vehicle is not None:
            v = self.vehicle
            o = block(P.VEH_W)
            head[P.H_VEHB] = o
            put(o, P.V_NODE, n - 1)
            put(o, P.V_MASS, v.mass)
            put(o, P.V_R, v.tyre_radius)
            angle = np.arctan(v.grade / 100.0)
            put(o, P.V_COS, np.cos(angle))
            put(o, P.V_SIN, np.sin(angle))
            put(o, P.V_FR, v.rolling)
            put(o, P.V_CA, 0.5 * v.air_density * v.cd_area)
            put(o, P.V_G, v.gravity)
            put(o, P.V_EPS, v.v_eps)
        head[P.H_NEV] = len(ev_names)
        params = np.concatenate([head, np.array(data, dtype=float)])
        # ---- outputs
        onames, ounits = [], []
        for c in couplings:
            onames.append(f"T_{c.name}")
            ounits.append("N·m")
        for fe in fes:
            # a coupling's torque is already T_<name>; a brake's is listed here
            if isinstance(fe, _LOSSY):
                onames += [f"T_loss_{fe.name}", f"w_slip_{fe.name}", f"capacity_{fe.name}",
                           f"T_stick_{fe.name}", f"P_{fe.name}"]
            else:
                t_name = f"T_{fe.name}" if isinstance(fe, Brake) else f"T_friction_{fe.name}"
                onames += [t_name, f"w_slip_{fe.name}", f"capacity_{fe.name}",
                           f"T_stick_{fe.name}", f"P_{fe.name}"]
            ounits += ["N·m", "rad/s", "N·m", "N·m", "W"]
        if self.engine is not None:
            onames.append("T_engine")
            ounits.append("N·m")
        if self.vehicle is not None:
            onames += ["v_vehicle", "a_vehicle"]
            ounits += ["m/s", "m/s²"]
        onames += ["E_kinetic", "E_spring"]
        ounits += ["J", "J"]
        meta = dict(self.metadata)
        meta.update({"models": {fe.name: self._model_name(fe) for fe in fes},
                     "nodes": list(nodes)})
        return System(ChainPlant(), params, np.array(y0, dtype=float), tuple(snames),
                      tuple(sunits), input_names=inputs,
                      input_units=self.input_units(), output_names=tuple(onames),
                      output_units=tuple(ounits), event_names=tuple(ev_names),
                      event_directions=tuple(ev_dirs), name=self.name, metadata=meta,
                      quadratures=len(ENERGY_STATES))

    # -------------------------------------------------------------- helpers
    @staticmethod
    def _model_name(fe) -> str:
        if isinstance(fe, _LOSSY):
            return "lossy-gear"
        if isinstance(fe, OneWayClutch):
            return "one-way-clutch"
        return fe.model.name

    @staticmethod
    def _state_spec(fe):
        """(state names, state units) of a switching element's own states."""
        if isinstance(fe, _LOSSY):
            return ("mode",), ("-",)
        return tuple(fe.model.state_names()), tuple(fe.model.state_units("rotational"))

    def _slip0(self, fe, omega0, ratios) -> float:
        if isinstance(fe, Brake):
            return float(omega0[self.node_names.index(fe.node)])
        k = self.couplings.index(fe)
        if isinstance(fe, _LOSSY):       # the gear's own speed at flange a
            return float(omega0[k])
        return float(omega0[k + 1] - omega0[k] / ratios[k])

    def _locked0(self, fe, omega0, ratios, inputs0) -> bool:
        if isinstance(fe, _LOSSY):
            return self._slip0(fe, omega0, ratios) == 0.0
        if isinstance(fe, OneWayClutch):
            w = self._slip0(fe, omega0, ratios)
            if w < 0.0:
                raise ValueError(f"one-way clutch {fe.name!r}: initial relative speed "
                                 f"omega_b - omega_a/ratio = {w:g} rad/s is negative; the "
                                 "freewheel only allows >= 0")
            return bool(fe.locked0) if fe.locked0 is not None else w == 0.0
        if fe.model.name not in _SWITCHING:
            return False
        if fe.locked0 is not None:
            return bool(fe.locked0)
        return self._slip0(fe, omega0, ratios) == 0.0 and inputs0.get(fe.command, 1.0) > 0.0

    def _z0(self, fe, omega0, ratios, inputs0) -> np.ndarray:
        if isinstance(fe, (*_LOSSY, OneWayClutch)):
            w = self._slip0(fe, omega0, ratios)
            locked = self._locked0(fe, omega0, ratios, inputs0)
            return np.array([0.0 if locked else (1.0 if w >= 0.0 else -1.0)])
        if fe.z0 is not None:
            return np.asarray(fe.z0, dtype=float)
        z = fe.model.initial_state()
        if fe.model.name in _SWITCHING and not self._locked0(fe, omega0, ratios, inputs0):
            w = self._slip0(fe, omega0, ratios)
            if w != 0.0:
                z = np.array([np.sign(w)])
            # w == 0 with zero command: the model's stuck mode, but not locked by the plant
            # (its force clip(F_e, 0) is 0); the break-away event frees it as soon as a
            # torque appears.
        return z
