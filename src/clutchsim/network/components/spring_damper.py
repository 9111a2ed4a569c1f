"""A torsional spring-damper, optionally two-stage (a clutch-disc damper, a driveshaft)."""

from __future__ import annotations

from ..component import Component
from ..spec import Param
from ._faults import FaultPhase


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
        e.torque_pair(a, b, tau, ((e.kx("phi"), k_phi, False), (e.kw(b), k_w, False),
                                  (e.kw(a), k_w, True)))
        e.deriv("phi", wr)
        e.dderiv("phi", e.kw(b), "1.0")
        e.dderiv("phi", e.kw(a), "-1.0")

    def book_viscous(self, e, wr: str, d: str) -> None:
        """The power ``d·wr²`` of a viscous damper ``d`` in ``W_damping``, with its partials."""
        a, b = self.twist_flanges
        e.power("damp", f"{d} * {wr} * {wr}")
        e.dpower("damp", e.kw(b), f"2.0 * {d} * {wr}")
        e.dpower("damp", e.kw(a), f"-2.0 * {d} * {wr}")


class SpringDamper(FaultPhase, TwistCoupling):
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
        Param("fault_time", "s", "time at which the fault (fault_stiffness_loss, "
              "fault_damping_loss) starts", default=0.0, low=0.0),
        Param("fault_stiffness_loss", "-", "fault: share of the stiffness (both stages) lost "
              "(0: none, 1: a broken spring)", default=0.0, low=0.0, high=1.0),
        Param("fault_damping_loss", "-", "fault: share of the damping lost", default=0.0,
              low=0.0, high=1.0),
        Param("fault_duration", "s", "time over which the fault's loss grows linearly to its "
              "share", default=1e-3, low=0.0, strict=True, high=10.0),
    )
    #: the keys of the faults it can have (``docs/components.md``, faults)
    fault_keys = ("fault_time", "fault_stiffness_loss", "fault_damping_loss", "fault_duration")

    def __init__(self, name, **values):
        super().__init__(name, **values)
        if self.knee > 0.0 and self.c2 <= 0.0:
            raise ValueError(f"{self.label}: a two-stage spring (knee = {self.knee:g} rad > 0) "
                             "needs c2 > 0 N·m/rad")

    @property
    def has_fault(self) -> bool:
        # read from the values each time: it follows a with_values
        v = self.values
        return v.get("fault_stiffness_loss", 0.0) > 0.0 or v.get("fault_damping_loss", 0.0) > 0.0

    def options(self):
        return (self.has_fault,)

    def fault_description(self) -> str | None:
        """What fails and when (None: no fault), for the events and the report."""
        if not self.has_fault:
            return None
        parts = [f"{k} -{100 * v:g} %" for k, v in (
            ("stiffness", self.fault_stiffness_loss), ("damping", self.fault_damping_loss))
            if v > 0.0]
        return (f"{', '.join(parts)} over {self.fault_time:g} to "
                f"{self.fault_time + self.fault_duration:g} s")

    def schedule(self) -> tuple:
        """Its fault: the loss grows from ``fault_time`` (phase 1) and is complete after
        ``fault_duration`` (phase 2; ``_faults.py``)."""
        if not self.has_fault:
            return ()
        t0 = self.values["fault_time"]
        return ((t0, {"fault_phase": 1}),
                (t0 + self.values["fault_duration"], {"fault_phase": 2}))

    def pack(self):
        d = super().pack()
        if self.has_fault:
            d["fault_ph"] = float(self.fault_phase)
            d["fault_end"] = self.values["fault_time"] + self.values["fault_duration"]
        return d

    def emit(self, e):
        c, d, knee, c2 = (e.par(k) for k in ("c", "d", "knee", "c2"))
        phi, wr = self.twist(e)
        inner = e.let("in1", f"{knee} <= 0.0 or abs({phi}) <= {knee}")
        sp0 = e.let("sp", f"{c} * {phi} if {inner} else math.copysign({c} * {knee} + {c2} * "
                          f"(abs({phi}) - {knee}), {phi})")
        ks0 = e.let("ks", f"{c} if {inner} else {c2}")
        ex = f"(abs({phi}) - {knee})"
        e0 = e.let("e0", f"(0.5 * {c} * {phi} * {phi} if {inner} else 0.5 * {c} * {knee} * "
                         f"{knee} + {c} * {knee} * {ex} + 0.5 * {c2} * {ex} * {ex})")
        sp, ks, dd, energy = sp0, ks0, d, e0
        if self.has_fault:
            # the fault's share r(t) grows linearly from fault_time over fault_duration; the
            # spring keeps (1 − loss·r) of its stiffness: the energy it lets go,
            # loss·(dr/dt)·E0 >= 0, is booked in W_damping
            # phase 0 (before), 1 (growing: linear in t, also a little past its end until
            # that event is located), 2 (complete), switched at located time events
            t0, dur, ph = e.par("fault_time"), e.par("fault_duration"), e.par("fault_ph")
            r = e.let("flt_r", f"0.0 if {ph} == 0.0 else ((t - {t0}) / {dur} if {ph} == 1.0 "
                               "else 1.0)")
            rdot = e.let("flt_rd", f"1.0 / {dur} if {ph} == 1.0 else 0.0")
            kc = e.let("flt_kc", f"1.0 - {e.par('fault_stiffness_loss')} * {r}")
            sp, ks = e.let("spf", f"{kc} * {sp0}"), e.let("ksf", f"{kc} * {ks0}")
            dd = e.let("ddf", f"{d} * (1.0 - {e.par('fault_damping_loss')} * {r})")
            energy = f"{kc} * {e0}"
            lossp = f"{e.par('fault_stiffness_loss')} * {rdot}"
            e.power("damp", f"{lossp} * {e0}")
            e.dpower("damp", e.kx("phi"), f"{lossp} * {sp0}")
            for edge, at in (("starts", t0), ("is complete", e.par("fault_end"))):
                e.event(f"{self.name}: fault {edge}, {{fault_description}}", 1, f"t - {at}",
                        "bank")
            e.output(f"fault_{self.name}", "-", r)
        tau = e.let("tau", f"{sp} + {dd} * {wr}")
        self.emit_twist(e, wr, tau, ks, dd)
        self.book_viscous(e, wr, dd)
        e.spring_energy(energy)
        e.output(f"{e.domain.effort}_{self.name}", e.domain.effort_unit, tau)
