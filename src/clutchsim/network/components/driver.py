"""A simple driver model: the throttle from a target speed (or acceleration) profile.

A PI law on the speed error ``e = v_ref − v``, with ``v = radius·(ω_a − ω_b)`` read through
sensor flanges (no torque, no inertia: connect ``a`` to the wheels' or the vehicle's
flange, ``b`` is grounded when left unconnected) and ``v_ref`` the ``target`` signal [m/s].
A target acceleration ``a`` is the speed profile ``v_ref = a·t`` (a formula in
``[inputs]``); an optional ``feedforward`` signal [-] adds to the throttle.  The throttle
is clipped to [0, 1]; the PI law and its back-calculation anti-windup:
:mod:`clutchsim.network.components._laws`.  Signal ``<name>.throttle`` [-], which an engine
reads as its ``throttle``.
"""

from __future__ import annotations

from ..spec import Param
from ._laws import PI_PARAMS, PIController, signal_arg


class Driver(PIController):
    """Speed-tracking driver (see the module docstring)."""

    kind = "driver"
    title = "driver model: PI throttle from a target speed profile"
    params = (
        *PI_PARAMS,
        Param("radius", "m", "speed per sensor speed: the wheel radius (1: the target is "
              "the sensor speed in rad/s)", default=1.0, low=0.0, strict=True),
    )

    def __init__(self, name, target: str, feedforward: str | None = None, **values):
        super().__init__(name, **values)
        target = signal_arg(self.label, "target", target, "the target speed [m/s]")
        feedforward = signal_arg(self.label, "feedforward", feedforward,
                                 "a throttle feed-forward [-]", optional=True)
        self.target, self.feedforward = target, feedforward

    def options(self):
        return (self.target, self.feedforward)

    def input_units(self):
        return {self.target: "m/s", **({self.feedforward: "-"} if self.feedforward else {})}

    def signals(self):
        return {"throttle": "-"}

    def state_layout(self):
        return [("integral", f"{self.name}.integral", "m")]

    def emit(self, e):
        P = e.par
        r = P("radius")
        err = e.let("err", f"{e.u(self.target)} - {r} * ({e.w('a')} - {e.w('b')})")
        err_parts = [(e.kw("a"), f"-{r}"), (e.kw("b"), r), *e.chain(self.target, "1.0")]
        if self.feedforward:
            ff, ff_parts = e.u(self.feedforward), e.du(self.feedforward)
        else:
            ff, ff_parts = "0.0", []
        self.emit_output(e, "throttle", err, err_parts, ff, ff_parts, "0.0", "1.0")
