"""A linear damper between two flanges (Modelica ``Damper``), rotational and translational."""

from __future__ import annotations

from ..component import Component
from ..spec import Param


class Damper(Component):
    """Viscous damper between flanges a and b: ``τ = d·(ω_b − ω_a)`` acts as ``+τ`` on a and
    ``−τ`` on b (the spring-damper's convention, without its spring and twist state); its
    power ``d·(ω_b − ω_a)² >= 0`` is booked in ``W_damping``.  Outputs the torque
    ``T_<name>`` and the relative speed ``w_rel_<name>``."""

    kind = "damper"
    title = "viscous damper (Modelica Damper)"
    flanges = ("a", "b")
    params = (Param("d", "N·m·s/rad", "damping constant", low=0.0),)
    rel_prefix = "w_rel"

    def emit(self, e):
        d = e.par("d")
        wr = e.let("wr", f"{e.w('b')} - {e.w('a')}")
        tau = e.let("tau", f"{d} * {wr}")
        e.torque_pair("a", "b", tau, ((e.kw("b"), d, False), (e.kw("a"), d, True)))
        e.power("damp", f"{d} * {wr} * {wr}")
        e.dpower("damp", e.kw("b"), f"2.0 * {d} * {wr}")
        e.dpower("damp", e.kw("a"), f"-2.0 * {d} * {wr}")
        e.output(f"{e.domain.effort}_{self.name}", e.domain.effort_unit, tau)
        e.output(f"{self.rel_prefix}_{self.name}", e.domain.speed_unit, wr)


class TranslationalDamper(Damper):
    """Viscous damper between flanges a and b (Modelica translational ``Damper``):
    ``f = d·(v_b − v_a)``, ``+f`` on a, ``−f`` on b; outputs ``F_<name>`` and
    ``v_rel_<name>``."""

    kind = "translational_damper"
    title = "translational viscous damper (Modelica Damper)"
    domain = "translational"
    params = (Param("d", "N·s/m", "damping constant", low=0.0),)
    rel_prefix = "v_rel"
