"""Closed-loop launch control: a PI controller of slip speed or engine speed with
anti-windup and engine-torque feed-forward, producing an actuator command.

Its two flanges are *sensors*: they apply no torque and carry no inertia; the measured
speed is ``y = ω_a − ω_b``.  Connect ``a`` to the clutch's engine side and ``b`` to its
gearbox side to track the slip speed (engine minus disc), or ``a`` alone to the engine
(``b`` is then grounded) to track the engine speed.  The error ``e = y − r`` (``r``: the
``target`` signal [rad/s]) is positive when the clutch slips too much or the engine runs
too fast: the command rises, the clutch closes.  With the engine's torque ``T_e`` (the
signal ``<engine>.torque``) as ``feedforward``, ``ff = offset + k_ff·T_e`` is the command
that would transmit it (``k_ff``: command per N·m of capacity; ``offset``: the command at
which the clutch starts to carry, the touch point or the threshold pressure).  The PI law and its
back-calculation anti-windup: :mod:`clutchsim.network.components._laws`.  The command is
clipped to ``[u_min, u_max]``.  Signal ``<name>.command`` (in ``command_unit``).
"""

from __future__ import annotations

from ..spec import Param
from ._laws import PI_PARAMS, PIController, signal_arg

#: units a controller's command may carry (what actuators and clutches read)
COMMAND_UNITS = ("-", "N", "Pa", "m")


class LaunchController(PIController):
    """PI launch controller (see the module docstring)."""

    kind = "launch_controller"
    title = "PI launch controller of slip or engine speed (anti-windup, feed-forward)"
    params = (
        *PI_PARAMS,
        Param("k_ff", "[command]/(N·m)", "feed-forward gain on the engine torque",
              default=0.0, low=0.0),
        Param("offset", "[command]", "constant feed-forward (the touch point, the threshold "
              "pressure)", default=0.0),
        Param("u_min", "[command]", "lower limit of the command", default=0.0),
        Param("u_max", "[command]", "upper limit of the command", default=1.0),
    )

    def __init__(self, name, target: str, feedforward: str | None = None,
                 command_unit: str = "-", **values):
        super().__init__(name, **values)
        target = signal_arg(self.label, "target", target, "the target speed [rad/s]")
        feedforward = signal_arg(self.label, "feedforward", feedforward,
                                 "the engine torque [N·m], e.g. 'engine.torque'",
                                 optional=True)
        if command_unit not in COMMAND_UNITS:
            raise ValueError(f"{self.label}: command_unit = {command_unit!r} must be one of "
                             f"{', '.join(COMMAND_UNITS)}")
        if not self.u_max > self.u_min:
            raise ValueError(f"{self.label}: u_max = {self.u_max:g} must be greater than "
                             f"u_min = {self.u_min:g}")
        self.target, self.feedforward, self.command_unit = target, feedforward, command_unit

    def options(self):
        return (self.target, self.feedforward, self.command_unit)

    def input_units(self):
        return {self.target: "rad/s", **({self.feedforward: "N·m"} if self.feedforward
                                         else {})}

    def signals(self):
        return {"command": self.command_unit}

    def state_layout(self):
        return [("integral", f"{self.name}.integral", "rad")]

    def emit(self, e):
        P = e.par
        err = e.let("err", f"{e.w('a')} - {e.w('b')} - {e.u(self.target)}")
        err_parts = [(e.kw("a"), "1.0"), (e.kw("b"), "-1.0"),
                     *e.chain(self.target, "-1.0")]
        if self.feedforward:
            ff = e.let("ff", f"{P('offset')} + {P('k_ff')} * {e.u(self.feedforward)}")
            ff_parts = e.chain(self.feedforward, P("k_ff"))
        else:
            ff, ff_parts = P("offset"), []
        self.emit_output(e, "command", err, err_parts, ff, ff_parts, P("u_min"), P("u_max"))
        e.output(f"error_{self.name}", "rad/s", err)
