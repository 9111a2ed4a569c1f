"""Gear lash: backlash in series with a spring and a damper (Modelica ``ElastoBacklash``)."""

from __future__ import annotations

from ..spec import Param
from .spring_damper import TwistCoupling

#: a total backlash at or below this is no backlash: a plain spring-damper (Modelica's bEps)
B_EPS = 1e-10


def lash_law(e, s: str, w: str, b: str, c: str, d: str) -> tuple[str, ...]:
    """The lash's torque at the offset ``s`` from the centre of the gap ``[−b/2, b/2]`` and
    the twist rate ``w`` (:class:`ElastoBacklash`'s law, also the engaged teeth of an
    elastic dog clutch): the locals ``(τ, τ_c, ∂τ_c/∂s, ∂τ/∂s, ∂τ/∂w, side, b/2, plain)``."""
    hb = e.let("hb", f"0.5 * {b}")
    plain = e.let("plain", f"{b} <= {B_EPS!r}")
    # side of the contact: +1 beyond +b/2, -1 beyond -b/2, 0 in the gap (and plain)
    sg = e.let("sg", f"0.0 if {plain} else (1.0 if {s} > {hb} else "
                     f"(-1.0 if {s} < -{hb} else 0.0))")
    kc = e.let("kc", f"{c} if ({plain} or {sg} != 0.0) else 0.0")
    tc = e.let("tc", f"{kc} * ({s} - {sg} * {hb})")
    td = e.let("td", f"{d} * {w}")
    cut = e.let("cut", f"(not {plain}) and {sg} * ({tc} + {td}) <= 0.0")
    lim = e.let("lim", f"(not {plain}) and {sg} * ({td} - {tc}) >= 0.0")
    tau = e.let("tau", f"0.0 if {cut} else (2.0 * {tc} if {lim} else {tc} + {td})")
    kp = e.let("kp", f"0.0 if {cut} else (2.0 * {c} if {lim} else {c})")
    kw = e.let("kw", f"0.0 if ({cut} or {lim}) else {d}")
    return tau, tc, kc, kp, kw, sg, hb, plain


class ElastoBacklash(TwistCoupling):
    """Backlash ``b`` in series with a spring ``c`` and a damper ``d`` between flanges a, b.

    Twist ``φ = φ_b − φ_a`` (state ``phi_<name>`` [rad]), ``dφ/dt = w = ω_b − ω_a``; the
    torque ``τ`` acts as ``+τ`` on a and ``−τ`` on b (the spring-damper's convention).
    With ``s = φ − phi_rel0`` and the gap ``[−b/2, b/2]``:

    * spring ``τ_c = c·(s − b/2)`` for ``s > b/2``, ``c·(s + b/2)`` for ``s < −b/2``, else 0;
      damper ``τ_d = d·w``;
    * in the gap ``τ = 0``; in contact ``τ = τ_c + τ_d`` with the damping limited to
      ``|τ_d| <= |τ_c|`` when it pushes (``τ = 2·τ_c``), and ``τ = 0`` when ``τ_c + τ_d``
      would pull the teeth together (the contact never pulls);
    * ``b <= 1e-10 rad``: a plain spring-damper ``τ = c·s + d·w``.

    The torque is continuous at the gap edges (the limiter makes it start at 0), so the
    edges are located events that only restart the integrator (``continue``); the inner
    limiter switches are kinks without events (Modelica's ``noEvent``).  Stored energy
    ``τ_c²/(2c)``; damping power ``(τ − τ_c)·w >= 0`` booked in ``W_damping`` (it is the
    whole difference between the power taken in and the spring's stored energy, also while
    the contact is cut off, where Modelica's ``lossPower`` reports 0).
    """

    kind = "elasto_backlash"
    title = "gear lash: backlash in series with a spring-damper (Modelica ElastoBacklash)"
    flanges = ("a", "b")
    params = (
        Param("b", "rad", "total backlash (the gap is [-b/2, b/2] around phi_rel0)", low=0.0),
        Param("c", "N·m/rad", "contact stiffness", low=0.0, strict=True),
        Param("d", "N·m·s/rad", "contact damping", default=0.0, low=0.0),
        Param("phi_rel0", "rad", "unstretched relative angle (centre of the gap)",
              default=0.0),
        Param("phi0", "rad", "initial relative angle phi_b - phi_a", default=0.0),
    )

    def emit(self, e):
        self.emit_lash(e, f"T_{self.name}")

    def emit_lash(self, e, torque_output: str) -> None:
        """The lash's equations between its :attr:`twist_flanges`, its torque as the output
        ``torque_output``."""
        fa, fb = self.twist_flanges
        b, c, d, phi_rel0 = (e.par(k) for k in ("b", "c", "d", "phi_rel0"))
        phi, w = self.twist(e)
        s = e.let("s", f"{phi} - {phi_rel0}")
        tau, tc, kc, kp, kw, sg, hb, plain = lash_law(e, s, w, b, c, d)
        self.emit_twist(e, w, tau, kp, kw)
        # damping power (τ − τ_c)·w: everything the spring does not store
        e.power("damp", f"({tau} - {tc}) * {w}")
        e.dpower("damp", e.kx("phi"), f"({kp} - {kc}) * {w}")
        dpw = e.let("dpw", f"{tau} - {tc} + {kw} * {w}")
        e.dpower("damp", e.kw(fb), dpw)
        e.dpower("damp", e.kw(fa), f"-{dpw}")
        e.spring_energy(f"(0.5 * {tc} * {tc} / {c})")
        e.output(torque_output, "N·m", tau)
        e.output(f"contact_{self.name}", "-", sg)
        # the gap edges: the torque's slope jumps there (no event for a plain spring)
        for side, edge in (("+", f"{s} - {hb}"), ("-", f"{s} + {hb}")):
            e.event(f"{self.name}: gap edge {side}b/2", 0,
                    f"1.0 if {plain} else {edge}", "continue")
