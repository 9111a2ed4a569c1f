"""Torques (forces) that depend on the speed of a flange relative to its support:
quadratic, linear, inverse and sign laws (Modelica ``QuadraticSpeedDependentTorque``,
``LinearSpeedDependentTorque``, ``InverseSpeedDependentTorque``, ``SignTorque`` and their
translational ``...Force`` twins).

Each acts with ``τ(ω)`` on ``flange`` and ``−τ`` on ``support`` (grounded when unconnected),
``ω = ω_flange − ω_support``; a positive ``τ`` accelerates the flange in the positive
direction, a negative one is a load.  Its power ``τ·ω`` is booked as input (negative for a
load).  ``signed`` = 1 makes the torque change sign with the speed (Modelica's
``TorqueDirection = false``); 0 keeps its direction in both directions of rotation.
Output ``T_<name>`` (``F_<name>``).
"""

from __future__ import annotations

from ..component import Component
from ..spec import Param

#: sign-law regularisations (the parameter ``reg``)
REG_EXP, REG_SINE, REG_LINEAR, REG_COSINE = 0, 1, 2, 3


class _SpeedLaw(Component):
    """A torque ``τ(ω)`` between ``flange`` and ``support``; subclasses give the law."""

    flanges = ("flange", "support")
    grounded = ("support",)

    def law(self, e, w: str) -> tuple[str, str]:
        """``(τ, dτ/dω)`` as expressions of the relative speed ``w``."""
        raise NotImplementedError

    def emit(self, e):
        wr = e.let("wr", f"{e.w('flange')} - {e.w('support')}")
        tau, dt = self.law(e, wr)
        tau, dt = e.let("tau", tau), e.let("dt", dt)
        e.torque_pair("flange", "support", tau,
                      ((e.kw("flange"), dt, False), (e.kw("support"), dt, True)))
        e.power("in", f"{tau} * {wr}")
        e.dpower("in", e.kw("flange"), f"{dt} * {wr} + {tau}")
        e.dpower("in", e.kw("support"), f"-({dt} * {wr} + {tau})")
        e.output(f"{e.domain.effort}_{self.name}", e.domain.effort_unit, tau)


def _law_params(domain, *extra):
    if domain == "rotational":
        nom = (Param("tau_nominal", "N·m", "torque at w_nominal (negative: a load)"),
               Param("w_nominal", "rad/s", "nominal speed", low=0.0, strict=True))
    else:
        nom = (Param("f_nominal", "N", "force at v_nominal (negative: a load)"),
               Param("v_nominal", "m/s", "nominal velocity", low=0.0, strict=True))
    signed = Param("signed", "-", "1: the torque changes sign with the speed; 0: it does not",
                   default=0.0, low=0.0, high=1.0)
    return (*nom, signed, *extra)


class _Nominal(_SpeedLaw):
    def nominal(self, e):
        return e.par(self.params[0].name), e.par(self.params[1].name), e.par("signed")


class QuadraticSpeedTorque(_Nominal):
    """``τ = tau_nominal·(ω/w_nominal)²``, times ``sign(ω)`` when ``signed`` = 1."""

    kind = "quadratic_speed_torque"
    title = "torque quadratic in speed"
    params = _law_params("rotational")

    def law(self, e, w):
        tn, wn, sg = self.nominal(e)
        f = e.let("f", f"(math.copysign(1.0, {w}) if {sg} > 0.5 else 1.0)")
        return f"{tn} * ({w} / {wn}) ** 2 * {f}", f"2.0 * {tn} * {w} / ({wn} * {wn}) * {f}"


class QuadraticSpeedForce(QuadraticSpeedTorque):
    """``f = f_nominal·(v/v_nominal)²``, times ``sign(v)`` when ``signed`` = 1."""

    kind = "quadratic_speed_force"
    title = "force quadratic in velocity"
    domain = "translational"
    params = _law_params("translational")


class LinearSpeedTorque(_Nominal):
    """``τ = tau_nominal·|ω|/w_nominal`` (``signed`` = 1: ``tau_nominal·ω/w_nominal``)."""

    kind = "linear_speed_torque"
    title = "torque linear in speed"
    params = _law_params("rotational")

    def law(self, e, w):
        tn, wn, sg = self.nominal(e)
        f = e.let("f", f"(1.0 if {sg} > 0.5 else math.copysign(1.0, {w}))")
        return f"{tn} * {w} / {wn} * {f}", f"{tn} / {wn} * {f}"


class LinearSpeedForce(LinearSpeedTorque):
    """``f = f_nominal·|v|/v_nominal`` (``signed`` = 1: ``f_nominal·v/v_nominal``)."""

    kind = "linear_speed_force"
    title = "force linear in velocity"
    domain = "translational"
    params = _law_params("translational")


class InverseSpeedTorque(_Nominal):
    """``τ = tau_nominal·w_nominal/|ω|`` beyond ``|ω| >= w0`` (``signed`` = 1:
    ``tau_nominal·w_nominal/ω``); below ``w0`` the constant ``tau_nominal·w_nominal/w0``
    (``signed``: the line ``tau_nominal·w_nominal·ω/w0²``, continuous at ``±w0``, where
    Modelica's ``tau_nominal·ω/w0`` jumps unless ``w_nominal = w0``).  The kinks at
    ``|ω| = w0`` are located events."""

    kind = "inverse_speed_torque"
    title = "torque inversely proportional to speed (a constant power)"
    params = _law_params("rotational", Param("w0", "rad/s", "speed below which the torque "
                                             "is regularised", default=0.1, low=0.0,
                                             strict=True))

    def law(self, e, w):
        tn, wn, sg = self.nominal(e)
        w0 = e.par(self.params[3].name)
        inner = e.let("inner", f"abs({w}) < {w0}")
        tau = (f"({tn} * {wn} * {w} / ({w0} * {w0}) if {sg} > 0.5 else {tn} * {wn} / {w0}) "
               f"if {inner} else ({tn} * {wn} / {w} if {sg} > 0.5 else "
               f"{tn} * {wn} / abs({w}))")
        dt = (f"({tn} * {wn} / ({w0} * {w0}) if {sg} > 0.5 else 0.0) if {inner} else "
              f"(-{tn} * {wn} / ({w} * {w}) if {sg} > 0.5 else "
              f"-{tn} * {wn} * math.copysign(1.0, {w}) / ({w} * {w}))")
        for side in ("+", "-"):
            e.event(f"{self.name}: regularisation {side}{self.params[3].name}", 0,
                    f"{w} {'-' if side == '+' else '+'} {w0}", "continue")
        return tau, dt


class InverseSpeedForce(InverseSpeedTorque):
    """The translational twin of :class:`InverseSpeedTorque` (``v0`` [m/s])."""

    kind = "inverse_speed_force"
    title = "force inversely proportional to velocity (a constant power)"
    domain = "translational"
    params = _law_params("translational", Param("v0", "m/s", "velocity below which the force "
                                                "is regularised", default=0.1, low=0.0,
                                                strict=True))


class SignTorque(_SpeedLaw):
    """``τ = tau_nominal·sgn(ω)`` regularised below ``w0`` (Modelica ``SignTorque``):
    ``reg`` 0 (exp, the default) ``tanh(ω/(0.02·w0))``; 1 (sine) ``sin(π/2·ω/w0)``;
    2 (linear) ``ω/w0``; 3 (cosine) ``sign(ω)·(1 − cos(π/2·ω/w0))``; beyond ``|ω| >= w0``
    (1–3) ``sign(ω)``, whose kinks are located events."""

    kind = "sign_torque"
    title = "constant torque changing sign with speed (Modelica SignTorque)"
    params = (Param("tau_nominal", "N·m", "torque (negative: a load, like dry friction)"),
              Param("w0", "rad/s", "regularisation speed", default=0.1, low=0.0, strict=True),
              Param("reg", "-", "regularisation: 0 exp, 1 sine, 2 linear, 3 cosine",
                    default=0.0, low=0.0, high=3.0))

    def law(self, e, w):
        tn, w0, reg = (e.par(p.name) for p in self.params)
        x = e.let("x", f"{w} / {w0}")
        sgn = e.let("sgn", f"math.copysign(1.0, {w})")
        hp = "0.5 * math.pi"
        th = e.let("th", f"math.tanh(50.0 * {x})")
        out = e.let("out", f"abs({x}) >= 1.0")
        g = (f"{th} if {reg} < 0.5 else ({sgn} if {out} else "
             f"(math.sin({hp} * {x}) if {reg} < 1.5 else ({x} if {reg} < 2.5 else "
             f"{sgn} * (1.0 - math.cos({hp} * {x})))))")
        dg = (f"50.0 * (1.0 - {th} * {th}) / {w0} if {reg} < 0.5 else (0.0 if {out} else "
              f"({hp} * math.cos({hp} * {x}) / {w0} if {reg} < 1.5 else (1.0 / {w0} if "
              f"{reg} < 2.5 else {sgn} * {hp} * math.sin({hp} * {x}) / {w0})))")
        for side in ("+", "-"):
            e.event(f"{self.name}: regularisation {side}{self.params[1].name}", 0,
                    f"1.0 if {reg} < 0.5 else {x} {'-' if side == '+' else '+'} 1.0",
                    "continue")
        return f"{tn} * ({g})", f"{tn} * ({dg})"


class SignForce(SignTorque):
    """``f = f_nominal·sgn(v)`` regularised below ``v0`` (Modelica ``SignForce``)."""

    kind = "sign_force"
    title = "constant force changing sign with velocity (Modelica SignForce)"
    domain = "translational"
    params = (Param("f_nominal", "N", "force (negative: a load, like dry friction)"),
              Param("v0", "m/s", "regularisation velocity", default=0.1, low=0.0, strict=True),
              Param("reg", "-", "regularisation: 0 exp, 1 sine, 2 linear, 3 cosine",
                    default=0.0, low=0.0, high=3.0))
