"""One-sided elastic contact: a spring-damper that can lift off (Modelica translational
``ElastoGap``)."""

from __future__ import annotations

from ..spec import Param
from .spring_damper import TwistCoupling


class ElastoGap(TwistCoupling):
    """A spring-damper between flanges a and b that acts only while the gap is closed.

    Relative position ``s = s_b − s_a`` (state ``s_rel_<name>`` [m], from ``s_rel_start``),
    ``ds/dt = v = v_b − v_a``; with ``r = (s − s_rel0)/s_ref``:

    * contact while ``s < s_rel0``; the spring force ``f_c = −c·s_ref·|r|^n`` (``n = 1``:
      ``c·(s − s_rel0)``), the damping force ``d·v`` limited to ``[f_c, −f_c]`` (so the
      contact pushes and never pulls, and the force starts at 0: no sticking);
    * the force ``f = f_c + f_d`` acts as ``+f`` on a and ``−f`` on b (``f < 0`` pushes
      the flanges apart); no contact: ``f = 0``.

    The force is continuous at the contact edge ``s = s_rel0`` (a located event that only
    restarts the integrator).  Stored energy ``c·s_ref²·|r|^(n+1)/(n+1)``; damping power
    ``f_d·v >= 0`` in ``W_damping``.  Outputs ``F_<name>``, ``v_rel_<name>`` and
    ``contact_<name>`` (1 in contact, else 0).
    """

    kind = "elasto_gap"
    title = "elastic gap: one-sided contact spring-damper (Modelica ElastoGap)"
    domain = "translational"
    flanges = ("a", "b")
    params = (
        Param("c", "N/m", "contact stiffness", low=0.0, strict=True),
        Param("d", "N·s/m", "contact damping", default=0.0, low=0.0),
        Param("s_rel0", "m", "relative position s_b - s_a at which contact begins",
              default=0.0),
        Param("n", "-", "exponent of the spring force", default=1.0, low=1.0),
        Param("s_ref", "m", "reference compression of the nonlinear spring "
              "(f_c = -c·s_ref·|(s - s_rel0)/s_ref|^n)", default=1.0, low=0.0, strict=True),
        Param("s_rel_start", "m", "initial relative position s_b - s_a", default=0.0),
    )

    def state_layout(self):
        return [("phi", f"s_rel_{self.name}", "m")]

    def initial_state(self, ctx):
        return [self.s_rel_start]

    def emit(self, e):
        c, d, s0, n, sr = (e.par(k) for k in ("c", "d", "s_rel0", "n", "s_ref"))
        s, v = self.twist(e)
        x = e.let("x", f"({s0} - {s}) / {sr}")           # compression/s_ref (> 0: contact)
        on = e.let("on", f"{x} > 0.0")
        fc = e.let("fc", f"-{c} * {sr} * {x} ** {n} if {on} else 0.0")
        kc = e.let("kc", f"{c} * {n} * {x} ** ({n} - 1.0) if {on} else 0.0")   # dfc/ds
        fd2 = e.let("fd2", f"{d} * {v}")
        # the damping force limited to [fc, -fc]: which bound (or none) is active
        lo = e.let("lo", f"{on} and {fd2} < {fc}")
        hi = e.let("hi", f"{on} and {fd2} > -{fc}")
        fd = e.let("fd", f"{fc} if {lo} else (-{fc} if {hi} else ({fd2} if {on} else 0.0))")
        f = e.let("f", f"{fc} + {fd}")
        kp = e.let("kp", f"2.0 * {kc} if {lo} else (0.0 if {hi} else {kc})")
        kv = e.let("kv", f"{d} if ({on} and not {lo} and not {hi}) else 0.0")
        self.emit_twist(e, v, f, kp, kv)
        # damping power fd·v (>= 0: fd has the sign of v)
        e.power("damp", f"{fd} * {v}")
        e.dpower("damp", e.kx("phi"), f"({kp} - {kc}) * {v}")
        dpv = e.let("dpv", f"{fd} + {kv} * {v}")
        e.dpower("damp", e.kw("b"), dpv)
        e.dpower("damp", e.kw("a"), f"-{dpv}")
        e.spring_energy(f"({c} * {sr} * {sr} * {x} ** ({n} + 1.0) / ({n} + 1.0) if {on} "
                        "else 0.0)")
        e.output(f"F_{self.name}", "N", f)
        e.output(f"v_rel_{self.name}", "m/s", v)
        e.output(f"contact_{self.name}", "-", f"1.0 if {on} else 0.0")
        e.event(f"{self.name}: contact edge", 0, f"{s} - {s0}", "continue")
