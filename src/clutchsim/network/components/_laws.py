"""Laws the actuation and control components share (each written once): the PI law with
back-calculation anti-windup and the PI controller component around it (launch
controller, driver model), the rate-limited first order lag and the actuator component
(hydraulic and electromechanical actuators) and the check of a key that names a signal.

PI law.
``raw = ff + kp·e + ki·I``, ``u = clip(raw, u_min, u_max)`` and ``dI/dt = e + (u − raw)/
(ki·t_track)``: while ``u`` saturates, the integral is pulled back towards the value that
just reaches the limit with the time constant ``t_track`` (Åström & Hägglund, *Advanced PID
Control*, 2006, on integrator windup), so the right-hand side stays continuous and the output leaves the
limit as soon as the error changes sign (no wind-up).
"""

from __future__ import annotations

from ..component import Component
from ..spec import Param

#: the parameters of the law (the components add their own)
PI_PARAMS = (
    Param("kp", "[command]/[error]", "proportional gain", default=0.0, low=0.0),
    Param("ki", "[command]/([error]·s)", "integral gain", low=0.0, strict=True),
    Param("t_track", "s", "tracking time constant of the back-calculation anti-windup",
          default=0.05, low=0.0, strict=True),
)


def emit_pi(e, err: str, err_parts, ff: str, ff_parts, lo: str, hi: str,
            state: str = "integral") -> tuple[str, list]:
    """Write the law on the error ``err`` (partials ``err_parts``: ``(key, expr)``) with the
    feed-forward ``ff`` (``ff_parts``) and the limits ``lo``/``hi``; the integral is the
    component's state ``state``.  Returns the output's local and its partials."""
    P = e.par
    i = e.x(state)
    raw = e.let("pi_raw", f"{ff} + {P('kp')} * {err} + {P('ki')} * {i}")
    u = e.let("pi_u", f"min(max({raw}, {lo}), {hi})")
    g = e.let("pi_g", f"1.0 if {lo} < {raw} < {hi} else 0.0")
    tt = f"({P('ki')} * {P('t_track')})"
    e.deriv(state, f"{err} + ({u} - {raw}) / {tt}")
    parts = [(k, f"{g} * {P('kp')} * ({d})") for k, d in err_parts]
    parts += [(k, f"{g} * ({d})") for k, d in ff_parts]
    raw_parts = [(k, f"{P('kp')} * ({d})") for k, d in err_parts] + list(ff_parts)
    for k, d in err_parts:
        e.dderiv(state, k, d)
    for k, d in raw_parts:
        e.dderiv(state, k, f"({g} - 1.0) * ({d}) / {tt}")
    e.dderiv(state, e.kx(state), f"({g} - 1.0) / {P('t_track')}")
    parts.append((e.kx(state), f"{g} * {P('ki')}"))
    return u, parts


class PIController(Component):
    """A PI controller (:func:`emit_pi`) of the speed of the sensor flange ``a`` relative
    to ``b`` (no torque, no inertia; ``b`` grounded when unconnected): the ``target``
    signal and an optional ``feedforward`` signal in, one signal out
    (:meth:`emit_output`).  Subclasses set ``target`` and ``feedforward``."""

    flanges = ("a", "b")
    grounded = ("b",)
    signal_keys = ("target", "feedforward")

    def inputs(self):
        return (self.target,) + ((self.feedforward,) if self.feedforward else ())

    def emit_output(self, e, signal: str, err: str, err_parts, ff: str, ff_parts, lo: str,
                    hi: str) -> None:
        """The law (:func:`emit_pi`, arguments as there) as the output ``signal`` with its
        partials."""
        u, parts = emit_pi(e, err, err_parts, ff, ff_parts, lo, hi)
        e.signal(signal, u)
        for key, d in parts:
            e.dsignal(signal, key, d)


def emit_rate_limited_lag(e, state: str, rate: str, limit: str | None, gain: str,
                          inputs) -> None:
    """``d(state)/dt = clip(rate, −limit, limit)`` (no clip with ``limit`` None), where
    ``rate = gain·(input − state)`` is written in ``rate``; ``inputs`` are the partials
    ``(key, expr)`` of the lag's input."""
    if limit is not None:
        e.deriv(state, f"min(max({rate}, -{limit}), {limit})")
        g = e.let(f"g_{state}", f"1.0 if -{limit} < {rate} < {limit} else 0.0")
    else:
        e.deriv(state, rate)
        g = "1.0"
    e.dderiv(state, e.kx(state), f"-{g} * {gain}")
    for key, d in inputs:
        e.dderiv(state, key, f"{g} * {gain} * ({d})")


class Actuator(Component):
    """An actuator: no flanges, the ``command`` signal in (``what`` it is: the message of
    :func:`signal_arg`), its signals out from its own states (no feed-through)."""

    flanges = ()
    feedthrough = False
    signal_keys = ("command",)

    def __init__(self, name, command: str, what: str, **values):
        super().__init__(name, **values)
        self.command = signal_arg(self.label, "command", command, what)

    def inputs(self):
        return (self.command,)


def signal_arg(owner: str, key: str, value, what: str | None = None, *,
               optional: bool = False):
    """``value`` if it names a signal (or is None where ``optional``), else a ValueError
    naming ``owner``, ``key``, the value and what the signal is (without ``what``: an
    input signal)."""
    if value is None and optional:
        return None
    if not isinstance(value, str) or not value:
        raise ValueError(f"{owner}: {key} = {value!r} must name "
                         + (f"a signal ({what})" if what else "an input signal"))
    return value
