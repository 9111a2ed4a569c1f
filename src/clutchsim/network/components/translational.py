"""Translational twins of rotational components (Modelica ``Mechanics.Translational``):
a spring-damper, a force source, support friction and a brake.

The network's mathematics is the same in both domains (a mass is an inertia, a force a
torque, a stretch a twist): each class here is its rotational twin with translational
parameters, units and result names (N, m, m/s, kg).  Masses are
:class:`~clutchsim.network.components.inertia.Mass`; the mass with stops and friction is
:mod:`~clutchsim.network.components.mass_stop`.
"""

from __future__ import annotations

from ..spec import Param
from .friction import Brake
from .spring_damper import SpringDamper
from .torque_source import TorqueSource


class TranslationalSpringDamper(SpringDamper):
    """Spring and damper in parallel between flanges a and b (Modelica translational
    ``SpringDamper``): stretch ``x = s_rel − s_rel0`` (state ``stretch_<name>`` [m], from
    ``stretch0``), ``dx/dt = v_b − v_a``; force ``f = c(x) + d·(v_b − v_a)`` acts as ``+f``
    on a and ``−f`` on b (two-stage optional, as the torsional one)."""

    kind = "translational_spring_damper"
    title = "translational spring-damper (two-stage optional)"
    domain = "translational"
    params = (
        Param("c", "N/m", "first-stage stiffness", low=0.0, strict=True),
        Param("d", "N·s/m", "viscous damping", default=0.0, low=0.0),
        Param("knee", "m", "stretch where the second stage starts (0: single stage)",
              default=0.0, low=0.0),
        Param("c2", "N/m", "second-stage stiffness", default=0.0, low=0.0),
        Param("stretch0", "m", "initial stretch s_rel − s_rel0 (the flanges' initial distance "
              "minus the unstretched length)", default=0.0),
    )
    fault_keys = ()

    def state_layout(self):
        return [("phi", f"stretch_{self.name}", "m")]

    def initial_state(self, ctx):
        return [self.stretch0]


class Force(TorqueSource):
    """Force ``f = u(t)`` [N] on ``flange``, reaction ``−f`` on ``support`` (grounded when
    unconnected; Modelica translational ``Force``)."""

    kind = "force"
    title = "force from an input signal"
    domain = "translational"

    def input_units(self):
        return {self.input: "N"}


class _TranslationalFriction(Brake):
    """A friction element from ``flange`` to ``support`` with any friction model in its
    translational parameters (N, m/s); slip ``v = v_flange − v_support``."""

    domain = "translational"
    params = (Param("drag", "N", "drag force of the open element, drag·tanh(v/1 m/s)",
                    default=0.0, low=0.0),)
    fault_keys = ()

    def __init__(self, name, model, command=None, mu_slip=None, heat=(), locked0=None,
                 z0=None, **values):
        super().__init__(name, model, command, mu_slip=mu_slip, heat=heat,
                         locked0=locked0, z0=z0, **values)


class SupportFriction(_TranslationalFriction):
    """Friction between a flange and the housing, always fully applied (Modelica
    translational ``SupportFriction``; its Stribeck table is the model's curve, or
    ``mu_slip``)."""

    kind = "support_friction"
    title = "friction to the housing (any friction model, always applied)"
    commanded = False

    def __init__(self, name, model, mu_slip=None, heat=(), locked0=None, z0=None, **values):
        super().__init__(name, model, None, mu_slip=mu_slip, heat=heat, locked0=locked0,
                         z0=z0, **values)


class TranslationalBrake(_TranslationalFriction):
    """A brake from ``flange`` to ``support`` whose capacity follows the normalised normal
    force ``command`` (Modelica translational ``Brake``, ``f_normalized``)."""

    kind = "translational_brake"
    title = "translational brake (any friction model, commanded normal force)"
