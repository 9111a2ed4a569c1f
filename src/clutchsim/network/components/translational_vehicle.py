"""A one-dimensional vehicle with its driving resistances (Modelica translational
``Vehicle``): mass, aerodynamic drag, rolling resistance, grade, and a wheel torque."""

from __future__ import annotations

from typing import ClassVar

from ..component import Component
from ..spec import Param
from ._laws import signal_arg


class TranslationalVehicle(Component):
    """Vehicle mass ``m`` at ``flange`` (Modelica translational ``Vehicle`` with ``J = 0``).

    Force on the mass, with ``α = atan(inclination)``::

        F = τ/R − ½·ρ·Cd·A·(v − v_wind)·|v − v_wind| − Cr·m·g·cos α·sat(v/v_reg) − m·g·sin α

    ``τ``: the wheel torque input ``torque`` [N·m] (0 without one), ``sat(x) = x`` for
    ``|x| < 1`` else ``sign(x)`` (MSL's linear regularisation of the rolling resistance;
    its kinks at ``|v| = v_reg`` are located events), ``inclination`` = tan α from the input
    ``inclination`` or the parameter.  Books ``τ/R·v`` as input, drag and rolling
    resistance in ``W_road``, the grade in ``E_grade``.  Outputs ``F_<name>`` (the road
    load, drag + rolling + grade, as a force on the mass).
    """

    kind = "translational_vehicle"
    title = "vehicle with driving resistances (Modelica translational Vehicle)"
    domain = "translational"
    flanges = ("flange",)
    optional_flanges = ("flange",)
    params = (
        Param("m", "kg", "total mass", low=0.0, strict=True),
        Param("R", "m", "wheel radius (the torque input acts as the force torque/R)",
              default=1.0, low=0.0, strict=True),
        Param("A", "m²", "cross section", default=1.0, low=0.0),
        Param("Cd", "-", "drag coefficient", default=0.5, low=0.0),
        Param("rho", "kg/m³", "air density", default=1.2, low=0.0),
        Param("Cr", "-", "rolling resistance coefficient", default=0.015, low=0.0),
        Param("v_wind", "m/s", "wind velocity (along the motion)", default=0.0),
        Param("v_reg", "m/s", "velocity below which the rolling resistance is regularised "
              "linearly", default=1e-3, low=0.0, strict=True),
        Param("inclination", "-", "road inclination tan α (without an inclination input)",
              default=0.0),
        Param("g", "m/s²", "gravity", default=9.80665, low=0.0),
        Param("v0", "m/s", "initial velocity", default=0.0),
        Param("s0", "m", "initial position (its state s_<name> with [outputs] angles)",
              default=0.0),
    )
    signal_keys = ("torque", "inclination_input")
    signal_docs: ClassVar[dict] = {
        "torque": ("Input signal: the wheel torque [N·m] (force torque/R).", False),
        "inclination_input": ("Input signal: the inclination tan α [-] (or the parameter).",
                              False)}

    def __init__(self, name, torque=None, inclination_input=None, **values):
        super().__init__(name, **values)
        self.torque_input = signal_arg(self.label, "torque", torque, optional=True)
        self.incl_input = signal_arg(self.label, "inclination_input", inclination_input,
                                     optional=True)

    def options(self):
        return (self.torque_input, self.incl_input)

    def inputs(self):
        return tuple(n for n in (self.torque_input, self.incl_input) if n is not None)

    def input_units(self):
        return {n: u for n, u in ((self.torque_input, "N·m"), (self.incl_input, "-"))
                if n is not None}

    def inertias(self):
        return {"flange": self.m}

    def initial_speeds(self):
        return {"flange": self.v0}

    def initial_position(self) -> float:
        return self.s0

    def pack(self):
        d = dict(self.values)
        d.update(c_aero=0.5 * self.rho * self.Cd * self.A, mg=self.m * self.g)
        return d

    def emit(self, e):
        P = e.par
        v = e.w("flange")
        vr = e.let("vr", f"{v} - {P('v_wind')}")
        fa = e.let("fa", f"{P('c_aero')} * {vr} * abs({vr})")
        x = e.let("x", f"{v} / {P('v_reg')}")
        sat = e.let("sat", f"{x} if abs({x}) < 1.0 else math.copysign(1.0, {x})")
        dsat = e.let("dsat", f"1.0 / {P('v_reg')} if abs({x}) < 1.0 else 0.0")
        if self.incl_input is None:
            inc = P("inclination")
            dinc = []
        else:
            inc = e.u(self.incl_input)
            dinc = e.du(self.incl_input)
        # cos(atan i) = 1/sqrt(1 + i²), sin(atan i) = i/sqrt(1 + i²)
        q = e.let("q", f"1.0 / math.sqrt(1.0 + {inc} * {inc})")
        fr = e.let("fr", f"{P('Cr')} * {P('mg')} * {q} * {sat}")
        fg = e.let("fg", f"{P('mg')} * {inc} * {q}")
        ft = "0.0" if self.torque_input is None else e.let(
            "ft", f"{e.u(self.torque_input)} / {P('R')}")
        e.torque("flange", f"{ft} - {fa} - {fr} - {fg}")
        dfv = e.let("dfv", f"2.0 * {P('c_aero')} * abs({vr}) + {P('Cr')} * {P('mg')} * {q} * "
                           f"{dsat}")
        e.dtorque("flange", e.kw("flange"), f"-{dfv}")
        e.power("road", f"({fa} + {fr}) * {v}")
        e.dpower("road", e.kw("flange"), f"{dfv} * {v} + {fa} + {fr}")
        e.power("grade", f"{fg} * {v}")
        e.dpower("grade", e.kw("flange"), fg)
        # partials through a produced inclination signal: dq/di = -i·q³
        if dinc:
            dq = e.let("dq", f"-{inc} * {q} * {q} * {q}")
            dfr = e.let("dfr", f"{P('Cr')} * {P('mg')} * {sat} * {dq}")
            dfg = e.let("dfg", f"{P('mg')} * ({q} + {inc} * {dq})")
            for key, d in dinc:
                e.dtorque("flange", key, f"-({dfr} + {dfg}) * {d}")
                e.dpower("road", key, f"{dfr} * {v} * {d}")
                e.dpower("grade", key, f"{dfg} * {v} * {d}")
        if self.torque_input is not None:
            e.power("in", f"{ft} * {v}")
            e.dpower("in", e.kw("flange"), ft)
            for key, d in e.du(self.torque_input):
                e.dtorque("flange", key, f"({d}) / {P('R')}")
                e.dpower("in", key, f"({d}) / {P('R')} * {v}")
        e.output(f"F_{self.name}", "N", f"-({fa} + {fr} + {fg})")
        for side in ("+", "-"):
            e.event(f"{self.name}: rolling resistance regularisation {side}v_reg", 0,
                    f"{v} {'-' if side == '+' else '+'} {P('v_reg')}", "continue")
