"""A dual-mass flywheel: two inertias, an arc spring with end stops, friction hysteresis."""

from __future__ import annotations

from ..spec import Param
from .friction import _FrictionElement
from .spring_damper import TwistCoupling


class DualMassFlywheel(_FrictionElement, TwistCoupling):
    """Primary inertia (engine side, flange ``primary``) and secondary inertia (clutch side,
    flange ``secondary``) joined by an arc spring and a friction ring in parallel.

    * Twist ``φ = φ_secondary − φ_primary`` (state ``phi_<name>`` [rad]), ``w = dφ/dt``.
    * Arc spring, symmetric in ``φ`` with ``x = |φ|``: ``c·x`` up to ``knee`` (first
      stage), then slope ``c2`` up to the end stop ``stop``, then the stop's stiffness
      ``c_stop``; ``knee = 0``: one stage up to the stop; ``stop = 0``: no end stop.  Plus
      ``d·w`` (viscous loss of the springs in their grease).  The torque ``τ`` acts as
      ``+τ`` on the primary and ``−τ`` on the secondary.
    * Friction hysteresis: a friction element of any model on the slip ``w`` (the
      ``friction`` table; its capacity is the hysteresis torque, always fully applied),
      with its heat to thermal nodes as a clutch.  With coulomb-robust it sticks and the
      arc spring only moves once its torque exceeds the break-away torque.
    * The stage and stop edges are located events (``continue``).
    """

    kind = "dual_mass_flywheel"
    title = "dual-mass flywheel: arc spring with end stops and friction hysteresis"
    flanges = ("primary", "secondary")
    twist_flanges = ("primary", "secondary")
    commanded = False
    side_a = "primary"
    side_b = "secondary"
    params = (
        Param("J_primary", "kg·m²", "primary inertia (crankshaft side)", low=0.0, strict=True),
        Param("J_secondary", "kg·m²", "secondary inertia (clutch side)", low=0.0, strict=True),
        Param("omega0", "rad/s", "initial speed of both masses", default=0.0),
        Param("c", "N·m/rad", "arc spring stiffness, first stage", low=0.0, strict=True),
        Param("knee", "rad", "twist where the second stage starts (0: single stage)",
              default=0.0, low=0.0),
        Param("c2", "N·m/rad", "arc spring stiffness, second stage", default=0.0, low=0.0),
        Param("stop", "rad", "twist of the end stop (0: none)", default=0.0, low=0.0),
        Param("c_stop", "N·m/rad", "stiffness of the end stop", default=0.0, low=0.0),
        Param("d", "N·m·s/rad", "viscous damping of the arc springs", default=0.0, low=0.0),
        Param("phi0", "rad", "initial twist", default=0.0),
        Param("drag", "N·m", "extra smooth friction drag·tanh(w/1 rad/s)", default=0.0,
              low=0.0),
    )

    def __init__(self, name, model, mu_temperature=None, mu_slip=None, heat=(),
                 locked0=None, z0=None, **values):
        super().__init__(name, model, None, mu_temperature=mu_temperature, mu_slip=mu_slip,
                         heat=heat, locked0=locked0, z0=z0, **values)
        o = self.label
        if self.knee > 0.0 and self.c2 <= 0.0:
            raise ValueError(f"{o}: a two-stage arc spring (knee = {self.knee:g} rad > 0) "
                             "needs c2 > 0 N·m/rad")
        if self.stop > 0.0 and self.stop <= self.knee:
            raise ValueError(f"{o}: stop = {self.stop:g} rad must lie beyond knee = "
                             f"{self.knee:g} rad: the end stop cannot be inside the first "
                             "stage")
        if self.stop > 0.0 and self.c_stop <= 0.0:
            raise ValueError(f"{o}: an end stop (stop = {self.stop:g} rad > 0) needs "
                             "c_stop > 0 N·m/rad")

    def inertias(self):
        return {"primary": self.J_primary, "secondary": self.J_secondary}

    def initial_speeds(self):
        return {"primary": self.omega0, "secondary": self.omega0}

    def pack(self):
        d = super().pack()
        big = 1e30                                  # "never" for a stage or stop not there
        st = self.stop if self.stop > 0.0 else big
        k1 = self.knee if self.knee > 0.0 else st
        t1 = self.c * min(k1, big)
        e1 = 0.5 * self.c * min(k1, big) ** 2
        span = (st - k1) if st < big else 0.0
        d.update(k1=k1, st=st, t_st=t1 + self.c2 * span,
                 e_st=e1 + t1 * span + 0.5 * self.c2 * span * span,
                 e_k1=e1, two=1.0 if self.knee > 0.0 else 0.0,
                 has_stop=1.0 if self.stop > 0.0 else 0.0)
        return d

    def state_layout(self):
        return [*super().state_layout(), ("phi", f"phi_{self.name}", "rad")]

    def initial_state(self, ctx):
        return [*super().initial_state(ctx), self.phi0]

    def emit(self, e):
        super().emit(e)                             # the friction ring
        P = e.par
        c, c2, cs, d = P("c"), P("c2"), P("c_stop"), P("d")
        k1, st = P("k1"), P("st")
        phi, w = self.twist(e)
        x = e.let("x", f"abs({phi})")
        sg = e.let("sg", f"1.0 if {phi} >= 0.0 else -1.0")
        seg = e.let("seg", f"0.0 if {x} <= {k1} else (1.0 if {x} <= {st} else 2.0)")
        t1 = e.let("t1", f"{c} * {k1}")
        mag = e.let("mag", f"{c} * {x} if {seg} == 0.0 else ({t1} + {c2} * ({x} - {k1}) "
                           f"if {seg} == 1.0 else {P('t_st')} + {cs} * ({x} - {st}))")
        ks = e.let("ks", f"{c} if {seg} == 0.0 else ({c2} if {seg} == 1.0 else {cs})")
        tau = e.let("tau", f"{sg} * {mag} + {d} * {w}")
        self.emit_twist(e, w, tau, ks, d)
        self.book_viscous(e, w, d)
        e1, ek = f"({x} - {k1})", f"({x} - {st})"
        e.spring_energy(f"(0.5 * {c} * {x} * {x} if {seg} == 0.0 else ({P('e_k1')} + {t1} * "
                        f"{e1} + 0.5 * {c2} * {e1} * {e1} if {seg} == 1.0 else {P('e_st')} + "
                        f"{P('t_st')} * {ek} + 0.5 * {cs} * {ek} * {ek}))")
        e.output(f"T_spring_{self.name}", "N·m", tau)
        e.event(f"{self.name}: arc spring second stage", 0,
                f"{x} - {k1} if {P('two')} > 0.5 else 1.0", "continue")
        e.event(f"{self.name}: end stop", 0,
                f"{x} - {st} if {P('has_stop')} > 0.5 else 1.0", "continue")
