"""A torsional spring-damper, optionally two-stage (a clutch-disc damper, a driveshaft)."""

from __future__ import annotations

from ..component import Component
from ..spec import Param


class TwistCoupling(Component):
    """A compliant coupling between flanges a and b with its twist as a state (Modelica's
    ``PartialCompliantWithRelativeStates``): ``φ = φ_b − φ_a`` (state ``phi_<name>`` [rad],
    from ``phi0``), ``dφ/dt = ω_b − ω_a``, its torque ``τ`` acting as ``+τ`` on a and ``−τ``
    on b.  Subclasses declare ``phi0`` and write ``τ`` with :meth:`emit_twist`."""

    def state_layout(self):
        return [("phi", f"phi_{self.name}", "rad")]

    def initial_state(self, ctx):
        return [self.phi0]

    #: the flanges the twist is measured between (φ = φ_b − φ_a)
    twist_flanges = ("a", "b")

    def twist(self, e) -> tuple[str, str]:
        """The twist ``φ`` (state) and the twist rate ``ω_b − ω_a`` (a local)."""
        a, b = self.twist_flanges
        return e.x("phi"), e.let("wr", f"{e.w(b)} - {e.w(a)}")

    def emit_twist(self, e, wr: str, tau: str, k_phi: str, k_w: str) -> None:
        """The torques ``±tau`` on a and b, the twist equation ``dφ/dt = wr`` and their
        partial derivatives (``k_phi = ∂τ/∂φ``, ``k_w = ∂τ/∂wr``)."""
        a, b = self.twist_flanges
        e.torque(a, tau)
        e.torque(b, f"-{tau}")
        e.deriv("phi", wr)
        for fl, sg in ((a, ""), (b, "-")):
            e.dtorque(fl, e.kx("phi"), f"{sg}{k_phi}")
            e.dtorque(fl, e.kw(b), f"{sg}{k_w}")
            e.dtorque(fl, e.kw(a), f"{'-' if not sg else ''}{k_w}")
        e.dderiv("phi", e.kw(b), "1.0")
        e.dderiv("phi", e.kw(a), "-1.0")

    def book_viscous(self, e, wr: str, d: str) -> None:
        """The power ``d·wr²`` of a viscous damper ``d`` in ``W_damping``, with its partials."""
        a, b = self.twist_flanges
        e.power("damp", f"{d} * {wr} * {wr}")
        e.dpower("damp", e.kw(b), f"2.0 * {d} * {wr}")
        e.dpower("damp", e.kw(a), f"-2.0 * {d} * {wr}")


class SpringDamper(TwistCoupling):
    """Spring and damper in parallel between flanges a and b.

    Twist ``φ = φ_b − φ_a`` (state ``phi_<name>`` [rad]), ``dφ/dt = ω_b − ω_a``; torque
    ``τ = c(φ) + d·(ω_b − ω_a)`` acts as ``+τ`` on a and ``−τ`` on b.  Two-stage spring:
    ``c(φ) = c·φ`` for ``|φ| <= knee``, else ``sign(φ)·(c·knee + c2·(|φ| − knee))``.
    """

    kind = "spring_damper"
    title = "torsional spring-damper (two-stage optional)"
    flanges = ("a", "b")
    params = (
        Param("c", "N·m/rad", "first-stage stiffness", low=0.0, strict=True, high=1e9),
        Param("d", "N·m·s/rad", "viscous damping", default=0.0, low=0.0, high=1e7),
        Param("knee", "rad", "twist where the second stage starts (0: single stage)",
              default=0.0, low=0.0, high=10.0),
        Param("c2", "N·m/rad", "second-stage stiffness", default=0.0, low=0.0, high=1e9),
        Param("phi0", "rad", "initial twist", default=0.0, low=-10.0, high=10.0),
    )

    def __init__(self, name, **values):
        super().__init__(name, **values)
        if self.knee > 0.0 and self.c2 <= 0.0:
            raise ValueError(f"{self.label}: a two-stage spring (knee = {self.knee:g} rad > 0) "
                             "needs c2 > 0 N·m/rad")

    def emit(self, e):
        c, d, knee, c2 = (e.par(k) for k in ("c", "d", "knee", "c2"))
        phi, wr = self.twist(e)
        inner = e.let("in1", f"{knee} <= 0.0 or abs({phi}) <= {knee}")
        sp = e.let("sp", f"{c} * {phi} if {inner} else math.copysign({c} * {knee} + {c2} * "
                         f"(abs({phi}) - {knee}), {phi})")
        ks = e.let("ks", f"{c} if {inner} else {c2}")
        tau = e.let("tau", f"{sp} + {d} * {wr}")
        self.emit_twist(e, wr, tau, ks, d)
        self.book_viscous(e, wr, d)
        ex = f"(abs({phi}) - {knee})"
        e.spring_energy(f"(0.5 * {c} * {phi} * {phi} if {inner} else 0.5 * {c} * {knee} * "
                        f"{knee} + {c} * {knee} * {ex} + 0.5 * {c2} * {ex} * {ex})")
        e.output(f"{e.domain.effort}_{self.name}", e.domain.effort_unit, tau)
