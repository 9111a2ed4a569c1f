"""Engine torque pulsation: the firing-order excitation of forced judder.

A combustion engine's torque is not smooth: each firing adds a pulse, so the crankshaft
torque carries harmonics at multiples of the firing order (order 2 for a four-cylinder
four-stroke engine: two firings per revolution).  This component adds the dominant one,

    T = A(ω)·sin(order·φ + phase),   dφ/dt = ω = ω_flange − ω_support,

on ``flange`` (reaction on ``support``), with the crank angle ``φ`` as its state
(``angle_<name>`` [rad]) and the amplitude ``A`` [N·m] constant or a table of the speed
(the engine's torque-harmonic amplitude against speed, from a combustion analysis or a
measured crank-torque spectrum).  Its work is booked as input energy, so the energy balance
holds.  Put it in parallel with the ``engine`` on the same flange.

References
----------
Heywood J.B., *Internal Combustion Engine Fundamentals*, McGraw-Hill, 1988 (the crank
torque of a four-stroke engine fluctuates at the firing frequency and its multiples);
the openTorsion library's internal-combustion-engine excitation example does the same in
frequency-domain torsional analysis.
"""

from __future__ import annotations

import numpy as np

from ..component import Component
from ..spec import Param, check_table, table_entry


class TorquePulsation(Component):
    """``T = A(ω)·sin(order·φ + phase)`` (see the module docstring)."""

    kind = "torque_pulsation"
    title = "engine torque pulsation of one firing order"
    flanges = ("flange", "support")
    grounded = ("support",)
    params = (
        Param("order", "-", "harmonic order per revolution (firing order: 2 for a four-"
              "cylinder four-stroke engine)", default=2.0, low=0.0, strict=True),
        Param("amplitude", "N·m", "amplitude when no amplitude table is given", default=0.0,
              low=0.0),
        Param("phase", "rad", "phase of the harmonic at zero crank angle", default=0.0),
        Param("angle0", "rad", "initial crank angle", default=0.0),
    )

    def __init__(self, name, amplitude_table=None, **values):
        super().__init__(name, **values)
        self.amplitude_table = None
        if amplitude_table is not None:
            x, v = check_table(self.label, "amplitude_table (speed, amplitude)",
                               amplitude_table[0], amplitude_table[1], min_points=1)
            if min(v) < 0.0:
                raise ValueError(f"{self.label}: amplitude_table amplitudes must be >= 0 N·m "
                                 f"(got {min(v):g})")
            self.amplitude_table = (x, v)

    def options(self):
        return (None if self.amplitude_table is None else len(self.amplitude_table[0]),)

    def described_values(self):
        if self.amplitude_table is None:
            return {}
        x, v = self.amplitude_table
        return {"amplitude_table": table_entry("amplitude of the harmonic over the speed",
                                               x, "rad/s", v, "N·m")}

    def pack(self):
        d = dict(self.values)
        if self.amplitude_table is not None:
            d["amplitude_table"] = np.concatenate(self.amplitude_table)
        return d

    def state_layout(self):
        return [("angle", f"angle_{self.name}", "rad")]

    def initial_state(self, ctx):
        return [self.angle0]

    def emit(self, e):
        w = e.let("w", f"{e.w('flange')} - {e.w('support')}")
        arg = e.let("arg", f"{e.par('order')} * {e.x('angle')} + {e.par('phase')}")
        sn, cs = e.let("sn", f"math.sin({arg})"), e.let("cs", f"math.cos({arg})")
        if self.amplitude_table is not None:
            amp, damp = e.lookup("amplitude_table", f"abs({w})", "amp")
            e.line(f"{damp} = {damp} * (1.0 if {w} >= 0.0 else -1.0)")
        else:
            amp, damp = e.let("amp", e.par("amplitude")), e.let("damp", "0.0")
        tq = e.let("tq", f"{amp} * {sn}")
        dtw = e.let("dtw", f"{damp} * {sn}")
        dtx = e.let("dtx", f"{amp} * {e.par('order')} * {cs}")
        e.deriv("angle", w)
        e.dderiv("angle", e.kw("flange"), "1.0")
        e.dderiv("angle", e.kw("support"), "-1.0")
        for fl, s in (("flange", ""), ("support", "-")):
            e.torque(fl, f"{s}{tq}")
            e.dtorque(fl, e.kw("flange"), f"{s}{dtw}")
            e.dtorque(fl, e.kw("support"), f"{'-' if not s else ''}{dtw}")
            e.dtorque(fl, e.kx("angle"), f"{s}{dtx}")
        e.power("in", f"{tq} * {w}")
        e.dpower("in", e.kw("flange"), f"{dtw} * {w} + {tq}")
        e.dpower("in", e.kw("support"), f"-({dtw} * {w} + {tq})")
        e.dpower("in", e.kx("angle"), f"{dtx} * {w}")
        e.output(f"T_{self.name}", "N·m", tq)
