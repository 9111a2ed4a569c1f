"""The vehicle at the wheels: mass as inertia, rolling, grade and aerodynamic load."""

from __future__ import annotations

import math

from ..component import Component
from ..spec import Param


class Vehicle(Component):
    """Mass ``m`` on tyres of radius ``r`` at ``flange`` (the wheels): inertia ``m·r²`` and
    the road load ``[m·g·(f_r·cos α·tanh(v/v_eps) + sin α) + ½·ρ·c_d·A·v·|v|]·r`` with
    ``v = ω·r``, ``α = atan(grade/100)``."""

    kind = "vehicle"
    title = "vehicle mass and road load"
    flanges = ("flange",)
    params = (
        Param("mass", "kg", "vehicle mass", low=0.0, strict=True, high=1e6),
        Param("tyre_radius", "m", "dynamic rolling radius", low=0.0, strict=True, high=5.0),
        Param("grade", "%", "road grade (rise/run·100, uphill positive)", default=0.0,
              low=-100.0, high=100.0),
        Param("rolling", "-", "rolling-resistance coefficient", default=0.0, low=0.0, high=0.5),
        Param("cd_area", "m²", "drag area c_d·A", default=0.0, low=0.0, high=100.0),
        Param("air_density", "kg/m³", "air density", default=1.2, low=0.0, high=10.0),
        Param("v_eps", "m/s", "speed over which rolling resistance builds up", default=0.05,
              low=0.0, strict=True, high=10.0),
        Param("gravity", "m/s²", "gravitational acceleration", default=9.81, low=0.0,
              strict=True),
    )

    def inertias(self):
        return {"flange": self.mass * self.tyre_radius ** 2}

    def pack(self):
        d = dict(self.values)
        a = math.atan(self.grade / 100.0)
        mg = self.mass * self.gravity
        d.update(roll=self.rolling * mg * math.cos(a), f_grade=mg * math.sin(a),
                 c_aero=0.5 * self.air_density * self.cd_area)
        return d

    def emit(self, e):
        P = e.par
        r = P("tyre_radius")
        v = e.let("v", f"{e.w('flange')} * {r}")
        tv = e.let("tv", f"math.tanh({v} / {P('v_eps')})")
        froll = e.let("froll", f"{P('roll')} * {tv}")
        faero = e.let("faero", f"{P('c_aero')} * {v} * abs({v})")
        e.torque("flange", f"-({froll} + {faero} + {P('f_grade')}) * {r}")
        e.dtorque("flange", e.kw("flange"),
                  f"-({P('roll')} * (1.0 - {tv} * {tv}) / {P('v_eps')} + 2.0 * {P('c_aero')} * "
                  f"abs({v})) * {r} * {r}")
        e.power("road", f"({froll} + {faero}) * {v}")
        e.power("grade", f"{P('f_grade')} * {v}")
        dfv = e.let("dfv", f"{P('roll')} * (1.0 - {tv} * {tv}) / {P('v_eps')} + 2.0 * "
                           f"{P('c_aero')} * abs({v})")
        e.dpower("road", e.kw("flange"), f"({dfv} * {v} + {froll} + {faero}) * {r}")
        e.dpower("grade", e.kw("flange"), f"{P('f_grade')} * {r}")
        e.output("v_vehicle", "m/s", v)
        e.output("a_vehicle", "m/s²", f"{e.accel('flange')} * {r}")
