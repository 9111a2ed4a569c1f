"""A lumped thermal node (pressure plate, flywheel, a friction-surface layer)."""

from __future__ import annotations

from ..component import Component
from ..spec import Param


class ThermalNode(Component):
    """``C·dθ/dt = Σ heat in − hA·(θ − ambient) − G·(θ − θ_link)`` (state ``theta_<name>``
    [°C]).  Friction elements send their power ``|τ·ω|`` here by share; ``link`` conducts
    to another node (declare each link once)."""

    kind = "thermal_node"
    title = "lumped thermal node"
    thermal = True
    domain = None
    params = (
        Param("capacity", "J/K", "heat capacity m·c_p", low=0.0, strict=True),
        Param("conductance", "W/K", "convection hA to ambient (0: adiabatic)", default=0.0,
              low=0.0, high=1e7),
        Param("ambient", "°C", "ambient temperature", default=20.0, low=-273.15,
              high=2000.0),
        Param("theta0", "°C", "initial temperature", default=20.0, low=-273.15, high=2000.0),
        Param("link_conductance", "W/K", "conductance of the link", default=0.0, low=0.0,
              high=1e7),
    )

    def __init__(self, name, link=None, **values):
        super().__init__(name, **values)
        if link is not None and not isinstance(link, str):
            raise ValueError(f"{self.label}: link = {link!r} must be the name of a thermal node")
        if link is not None and self.link_conductance <= 0.0:
            raise ValueError(f"{self.label}: link to {link!r} needs link_conductance > 0 W/K")
        if link is None and self.link_conductance > 0.0:
            raise ValueError(f"{self.label}: link_conductance = {self.link_conductance:g} W/K "
                             "needs a link (the name of the node it conducts to)")
        if link == name:
            raise ValueError(f"{self.label}: link must name another node, not the node itself")
        self.link = link

    def options(self):
        return (self.link,)

    def described_values(self):
        if self.link is None:
            return {}
        return {"link": {"value": self.link, "unit": "",
                         "description": "the thermal node it conducts to (link_conductance)"}}

    def check_network(self, net):
        if self.link is None:
            return
        from ...core.system import closest
        from ..network import NetworkError
        nodes = [c.name for c in net.components if getattr(c, "thermal", False)]
        if self.link not in nodes:
            raise NetworkError(f"{self.label}: link = {self.link!r} is not a thermal node"
                               f"{closest(self.link, nodes)} (nodes: {', '.join(nodes)})",
                               f"{self.name}.link")
        other = net.component(self.link)
        if getattr(other, "link", None) == self.name:
            raise ValueError(f"thermal nodes {self.name!r} and {self.link!r} are linked twice; "
                             "declare the link on one of them only")

    def emit(self, e):
        P = e.par
        th = e.theta(self.name)
        e.heat(self.name, f"-{P('conductance')} * ({th} - {P('ambient')})")
        e.dheat(self.name, e.ktheta(self.name), f"-{P('conductance')}")
        if self.link is not None:
            tl = e.theta(self.link)
            q = f"{P('link_conductance')} * ({th} - {tl})"
            e.heat(self.name, f"-{q}")
            e.heat(self.link, q)
            G = P("link_conductance")
            e.dheat(self.name, e.ktheta(self.name), f"-{G}")
            e.dheat(self.name, e.ktheta(self.link), G)
            e.dheat(self.link, e.ktheta(self.name), G)
            e.dheat(self.link, e.ktheta(self.link), f"-{G}")
