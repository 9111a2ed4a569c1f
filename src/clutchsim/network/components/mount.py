"""An engine or transmission block on a torsional mount to the body (or the ground)."""

from __future__ import annotations

from ..spec import Param
from .spring_damper import TwistCoupling


class TorsionalMount(TwistCoupling):
    """The powertrain block, inertia ``J`` about the crankshaft axis at ``block``, on a mount
    of stiffness ``c`` and damping ``d`` to ``support`` (the body; grounded when left
    unconnected).  Connect the supports of the engine, the clutch housing or the gearbox to
    ``block``: their reaction torques turn it.

    Twist ``φ = φ_block − φ_support`` (state ``phi_<name>`` [rad], from ``phi0``),
    ``dφ/dt = ω_block − ω_support``; the mount torque ``τ = c·φ + d·(ω_block − ω_support)``
    acts as ``−τ`` on the block and ``+τ`` on the support.  ``E_spring`` holds ``c·φ²/2``,
    ``W_damping`` the power ``d·(ω_block − ω_support)²``.  Output ``T_<name>``: ``τ``, the
    torque the mount passes into the body.
    """

    kind = "torsional_mount"
    title = "powertrain block on a torsional mount"
    flanges = ("block", "support")
    grounded = ("support",)
    twist_flanges = ("support", "block")
    params = (
        Param("J", "kg·m²", "inertia of the block about the crankshaft axis", low=0.0,
              strict=True, high=1e4),
        Param("c", "N·m/rad", "torsional stiffness of the mounts", low=0.0, strict=True,
              high=1e9),
        Param("d", "N·m·s/rad", "torsional damping of the mounts", default=0.0, low=0.0,
              high=1e7),
        Param("phi0", "rad", "initial twist (the block's roll angle)", default=0.0,
              low=-1.0, high=1.0),
    )

    def inertias(self):
        return {"block": self.J}

    def emit(self, e):
        c, d = e.par("c"), e.par("d")
        phi, wr = self.twist(e)
        tau = e.let("tau", f"{c} * {phi} + {d} * {wr}")
        self.emit_twist(e, wr, tau, c, d)
        self.book_viscous(e, wr, d)
        e.spring_energy(f"0.5 * {c} * {phi} * {phi}")
        e.output(f"T_{self.name}", "N·m", tau)
