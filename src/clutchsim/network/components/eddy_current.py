"""Eddy-current brakes (Modelica ``EddyCurrentTorque`` and ``EddyCurrentForce``): Kloss'
characteristic, its loss heating a thermal node, the conductivity falling with the
temperature."""

from __future__ import annotations

from typing import ClassVar

from ..component import Component
from ..spec import Param


class EddyCurrentBrake(Component):
    """Braking torque ``τ_b = 2·tau_nominal·e²·x/(1 + x²)`` with
    ``x = ω/(w_nominal·(1 + alpha·(θ − T_ref)))`` and ``ω = ω_flange − ω_support``: it acts
    as ``−τ_b`` on ``flange`` and ``+τ_b`` on ``support`` (grounded when unconnected); its
    maximum ``tau_nominal`` is reached at ``ω = w_nominal`` at the reference temperature.

    * ``e``: the excitation, the parameter ``excitation`` or the input ``excitation_input``;
    * ``θ``: the temperature [°C] of the thermal node ``heat`` (the brake's loss
      ``τ_b·ω >= 0`` heats it), else ``T_ref`` (the loss then leaves the model);
    * the loss is booked in ``W_damping``.

    Outputs ``T_<name>`` (``F_<name>``: the braking torque ``τ_b``) and ``P_<name>`` [W].
    """

    kind = "eddy_current_brake"
    title = "eddy-current brake (Modelica EddyCurrentTorque), heating a thermal node"
    flanges = ("flange", "support")
    grounded = ("support",)
    params = (
        Param("tau_nominal", "N·m", "maximum braking torque", low=0.0),
        Param("w_nominal", "rad/s", "speed of the maximum torque at T_ref", low=0.0,
              strict=True),
        Param("alpha", "1/K", "temperature coefficient of the conductor's resistance",
              default=0.0, low=0.0),
        Param("T_ref", "°C", "reference temperature", default=20.0, low=-273.15),
        Param("excitation", "-", "excitation (1: the nominal torque), without an input",
              default=1.0, low=0.0),
    )
    signal_docs: ClassVar[dict] = {
        "excitation_input": ("Input signal: the excitation [-] (instead of the parameter).",
                             False),
        "heat": ("Thermal node the loss heats (its temperature sets the characteristic).",
                 False)}
    signal_keys = ("excitation_input",)

    def __init__(self, name, excitation_input=None, heat=None, **values):
        super().__init__(name, **values)
        for key, v in (("excitation_input", excitation_input), ("heat", heat)):
            if v is not None and (not isinstance(v, str) or not v):
                raise ValueError(f"{self.label}: {key} = {v!r} must be a name")
        self.excitation_input, self.heat = excitation_input, heat

    def options(self):
        return (self.excitation_input, self.heat)

    def inputs(self):
        return () if self.excitation_input is None else (self.excitation_input,)

    def input_units(self):
        return {} if self.excitation_input is None else {self.excitation_input: "-"}

    def check_network(self, net):
        if self.heat is not None:
            nodes = [c.name for c in net.components if getattr(c, "thermal", False)]
            if self.heat not in nodes:
                raise ValueError(f"{self.label}: heat = {self.heat!r} is not a thermal node "
                                   f"(thermal nodes: {', '.join(nodes) or 'none'})")

    def emit(self, e):
        P = e.par
        w = e.let("w", f"{e.w('flange')} - {e.w('support')}")
        th = P("T_ref") if self.heat is None else e.theta(self.heat)
        k = e.let("k", f"1.0 + {P('alpha')} * ({th} - {P('T_ref')})")
        x = e.let("x", f"{w} / ({P(self.params[1].name)} * {k})")
        if self.excitation_input is None:
            ex, dex = P("excitation"), []
        else:
            ex, dex = e.u(self.excitation_input), e.du(self.excitation_input)
        g = e.let("g", f"2.0 * {P(self.params[0].name)} * {ex} * {ex}")
        den = e.let("den", f"1.0 + {x} * {x}")
        tb = e.let("tb", f"{g} * {x} / {den}")
        dtx = e.let("dtx", f"{g} * (1.0 - {x} * {x}) / ({den} * {den})")     # dτ_b/dx
        dtw = e.let("dtw", f"{dtx} / ({P(self.params[1].name)} * {k})")       # dτ_b/dω
        e.torque("flange", f"-{tb}")
        e.torque("support", tb)
        keys = [(e.kw("flange"), dtw, "1.0"), (e.kw("support"), dtw, "-1.0")]
        for key, d, s in keys:
            e.dtorque("flange", key, f"-{s} * {d}")
            e.dtorque("support", key, f"{s} * {d}")
        loss = e.let("loss", f"{tb} * {w}")
        dlw = e.let("dlw", f"{dtw} * {w} + {tb}")                             # dP/dω
        e.power("damp", loss)
        e.dpower("damp", e.kw("flange"), dlw)
        e.dpower("damp", e.kw("support"), f"-{dlw}")
        other = []          # partials by the temperature and the excitation: (key, dτ_b)
        if self.heat is not None:
            other.append((e.ktheta(self.heat),
                          e.let("dtt", f"-{dtx} * {x} * {P('alpha')} / {k}")))
        for key, d in dex:
            other.append((key, f"(4.0 * {P(self.params[0].name)} * {ex} * {x} / {den}) * {d}"))
        for key, d in other:
            e.dtorque("flange", key, f"-({d})")
            e.dtorque("support", key, d)
            e.dpower("damp", key, f"({d}) * {w}")
        if self.heat is not None:
            e.heat(self.heat, loss)
            e.dheat(self.heat, e.kw("flange"), dlw)
            e.dheat(self.heat, e.kw("support"), f"-{dlw}")
            for key, d in other:
                e.dheat(self.heat, key, f"({d}) * {w}")
        e.output(f"{e.domain.effort}_{self.name}", e.domain.effort_unit, tb)
        e.output(f"P_{self.name}", "W", loss)


class TranslationalEddyCurrentBrake(EddyCurrentBrake):
    """Braking force ``f_b = 2·f_nominal·e²·x/(1 + x²)``, ``x = v/(v_nominal·(1 +
    alpha·(θ − T_ref)))`` (Modelica ``EddyCurrentForce``); otherwise as
    :class:`EddyCurrentBrake`."""

    kind = "translational_eddy_current_brake"
    title = "eddy-current brake (Modelica EddyCurrentForce), heating a thermal node"
    domain = "translational"
    params = (
        Param("f_nominal", "N", "maximum braking force", low=0.0),
        Param("v_nominal", "m/s", "velocity of the maximum force at T_ref", low=0.0,
              strict=True),
        *EddyCurrentBrake.params[2:],
    )
