"""A load torque quadratic in speed (Modelica ``QuadraticSpeedDependentTorque``)."""

from __future__ import annotations

from ..component import Component
from ..spec import Param


class QuadraticSpeedTorque(Component):
    """``τ = tau_nominal·(ω/w_nominal)²`` on ``flange`` (relative to ``support``), times
    ``sign(ω)`` when ``signed`` = 1 (Modelica's ``TorqueDirection = false``); its power
    ``τ·ω`` is booked as input (negative for a load)."""

    kind = "quadratic_speed_torque"
    title = "torque quadratic in speed"
    flanges = ("flange", "support")
    grounded = ("support",)
    params = (
        Param("tau_nominal", "N·m", "torque at w_nominal (negative: a load)"),
        Param("w_nominal", "rad/s", "nominal speed", low=0.0, strict=True),
        Param("signed", "-", "1: the torque changes sign with the speed; 0: it does not",
              default=0.0, low=0.0, high=1.0),
    )

    def emit(self, e):
        tn, wn, sg = e.par("tau_nominal"), e.par("w_nominal"), e.par("signed")
        wr = e.let("wr", f"{e.w('flange')} - {e.w('support')}")
        f = e.let("f", f"(math.copysign(1.0, {wr}) if {sg} > 0.5 else 1.0)")
        tau = e.let("tau", f"{tn} * ({wr} / {wn}) ** 2 * {f}")
        dt = e.let("dt", f"2.0 * {tn} * {wr} / ({wn} * {wn}) * {f}")
        e.torque("flange", tau)
        e.torque("support", f"-{tau}")
        for fl, s in (("flange", ""), ("support", "-")):
            e.dtorque(fl, e.kw("flange"), f"{s}{dt}")
            e.dtorque(fl, e.kw("support"), f"{'-' if not s else ''}{dt}")
        e.power("in", f"{tau} * {wr}")
        e.dpower("in", e.kw("flange"), f"{dt} * {wr} + {tau}")
        e.dpower("in", e.kw("support"), f"-({dt} * {wr} + {tau})")
        e.output(f"T_{self.name}", "N·m", tau)
