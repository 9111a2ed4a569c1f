"""The driveline as a network of components, compiled per topology.

* :class:`Network` — components (:mod:`clutchsim.network.components`) joined at flanges;
* :func:`compile_network` — the :class:`~clutchsim.network.plant.Plan` of a network: its
  generated, compiled and cached plant; ``plan.system()`` gives a
  :class:`~clutchsim.core.System` to simulate.

See ``docs/network.md``.
"""

from .component import Component
from .components import COMPONENTS
from .network import GROUND, Network, NetworkError
from .plant import Plan, compile_network
from .spec import Param, StateSpec

__all__ = ["COMPONENTS", "GROUND", "Component", "Network", "NetworkError", "Param", "Plan",
           "StateSpec", "compile_network"]
