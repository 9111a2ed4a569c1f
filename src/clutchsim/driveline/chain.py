"""A driveline written as a series chain, and its translation into a network.

Chain files (``[[inertia]]``/``[[coupling]]``) describe inertias in series joined by
couplings; :meth:`Chain.network` translates them into a :class:`~clutchsim.network.Network`
(``docs/network.md``), whose generated plant runs them.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from ..core import System
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
)

__all__ = ["ENERGY_STATES", "Chain"]

#: energy-account states (integrals) [J]
ENERGY_STATES = ("W_in", "W_friction", "W_damping", "W_road", "E_grade", "W_sync")


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
    angles : bool
        Angle states ``phi_<inertia>`` [rad] in the plant (``Network.angles``).
    """

    inertias: tuple
    couplings: tuple
    brakes: tuple = ()
    engine: Engine | None = None
    vehicle: Vehicle | None = None
    thermal: tuple = ()
    name: str = "driveline"
    metadata: dict = field(default_factory=dict)
    angles: bool = False

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

    def network(self):
        """This chain as a :class:`~clutchsim.network.Network` (the documented
        translation, ``docs/network.md``): each inertia an inertia, each coupling the
        component of its kind between inertia k (flange a) and k+1 (flange b), a coupling's
        own ``ratio`` an ideal gear on its input side, a load input a torque source, brakes
        on their inertia, the engine on its inertia, the vehicle on the last inertia."""
        from .. import network as nw
        from ..network import components as nc
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
                if isinstance(c, Gearbox):
                    comps.append(nc.Gearbox(c.name, c.ratios, shifts=c.shifts, gear=c.gear,
                                            final_drive=c.final_drive,
                                            efficiency=c.efficiency,
                                            efficiency_reverse=c.efficiency_reverse,
                                            drag_torque=c.drag_torque))
                elif isinstance(c, LossyGear):
                    comps.append(nc.LossyGear(c.name, ratio=c.ratio, loss_table=c.loss_table))
                else:
                    comps.append(nc.IdealGear(c.name, ratio=c.ratio))
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
            elif isinstance(c, OneWayClutch):
                comps.append(nc.OneWayClutch(c.name, c.command, T_slide=c.T_slide,
                                             peak=c.peak, heat=c.heat,
                                             mu_temperature=c.mu_temperature,
                                             locked0=c.locked0))
            else:
                comps.append(nc.Clutch(c.name, c.model, c.command, clamp_table=c.clamp_table,
                                       mu_temperature=c.mu_temperature, mu_slip=c.mu_slip,
                                       heat=c.heat, locked0=c.locked0, z0=c.z0, drag=c.drag,
                                       runout=c.runout, wear=c.wear))
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
        return nw.Network(comps, conns, name=self.name, metadata=dict(self.metadata),
                          angles=self.angles)

    def build(self, inputs0: dict | None = None) -> System:
        """The compiled :class:`~clutchsim.core.System` of this chain: the generated plant
        of its network (:meth:`network`).

        ``inputs0`` (input name -> value at the start time) lets switching friction
        elements with zero slip start free when their command is 0 (else they start
        locked).
        """
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
