"""A gearbox with losses and elastic backlash (Modelica ``Gearbox``): a gear with losses
(:class:`~clutchsim.network.components.lossy_gear.LossyGear`) and a lash
(:class:`~clutchsim.network.components.backlash.ElastoBacklash`) in series, with no inertia
between them."""

from __future__ import annotations

from ..spec import Param
from .backlash import ElastoBacklash
from .lossy_gear import LossyGear


class LossyGearWithLash(LossyGear, ElastoBacklash):
    """Gear with losses from ``a`` to an inner massless flange ``mesh``, then the lash
    (backlash ``b`` in series with ``c`` and ``d``) from ``mesh`` to ``b``.

    The gear's relation ``ω_a − ω_s = ratio·(ω_mesh − ω_s)`` holds the mesh's speed (it has
    no inertia and needs none); the lash's twist ``φ = φ_b − φ_mesh`` is the state
    ``phi_<name>`` [rad] from ``phi0``.  The losses, the stuck/rolling logic and their
    outputs are the lossy gear's (``T_loss_<name>``, ``P_<name>``, the states
    ``<name>.mode``, ``<name>.locked``); ``T_<name>`` is the torque the gear passes on at the
    mesh, ``T_lash_<name>`` the lash's torque (``+τ`` on the mesh, ``−τ`` on ``b``),
    ``contact_<name>`` its contact side.  ``mesh`` is internal (``internal_flanges``): connecting it is an error.
    """

    kind = "lossy_gear_with_lash"
    title = "gearbox: gear with losses and elastic backlash in series (Modelica Gearbox)"
    flanges = ("a", "b", "support", "mesh")
    optional_flanges = ("mesh",)
    internal_flanges = ("mesh",)
    out_flange = "mesh"
    twist_flanges = ("mesh", "b")
    params = (
        Param("ratio", "-", "speed ratio ω_a/ω_mesh relative to the support", nonzero=True),
        *(p for p in ElastoBacklash.params),
    )

    def state_layout(self):
        return [*LossyGear.state_layout(self), ("phi", f"phi_{self.name}", "rad")]

    def initial_state(self, ctx):
        return [*LossyGear.initial_state(self, ctx), self.phi0]

    def emit(self, e):
        LossyGear.emit(self, e)
        self.emit_lash(e, f"T_lash_{self.name}")
