"""A tyre with longitudinal slip: brush-model force, first-order relaxation (Pacejka).

Between the wheel (a rotating flange, with the wheel's inertia) and the vehicle body (a
rotating flange in the units of the wheel: the body's speed ``V = ω_body·r``; put the
``vehicle`` component there, with the same radius), the tyre carries the longitudinal force
``F`` of its transient slip ``κ'`` (state ``<name>.kappa``)::

    σ·dκ'/dt = (ω_wheel − ω_body)·r − V_ε·κ',      V_ε = sqrt(V² + v_eps²)
    F = μ·F_z·(3z − 3z·|z| + z³)  for |z| < 1,  else μ·F_z·sign(z),   z = C_κ·κ'/(3·μ·F_z)

``F`` acts as ``−F·r`` on the wheel and ``+F·r`` on the body.  The force law is the brush
model with a parabolic pressure distribution (Pacejka, *Tire and Vehicle Dynamics*, 3rd ed.
2012, ch. 3, written in the practical slip); the slip equation is Pacejka's first-order
single-contact-point relaxation ``σ·dκ'/dt + |V|·κ' = −V_sx`` (ch. 7), with ``|V|``
regularised to ``V_ε`` so that a launch from standstill works: at ``V = 0`` the tyre is a
spring of stiffness ``C_κ/σ`` [N/m] with a damper ``C_κ/v_eps`` in series, and in steady
state ``κ' = (ω_wheel − ω_body)·r/V_ε``, the practical slip once ``|V| >> v_eps``.

Energy: the carcass stores ``E = σ·G(κ')`` with ``G = ∫F dκ'`` (closed form below, in
``E_spring``); the rest of the power it takes in, ``F·κ'·V_ε >= 0``, is the slip loss,
booked in ``W_damping``.
"""

from __future__ import annotations

from ..component import Component
from ..spec import Param, StateSpec


class Tyre(Component):
    """Tyre with longitudinal slip between ``wheel`` and ``body`` (see the module
    docstring); wheel inertia ``J_wheel`` at ``wheel``."""

    kind = "tyre"
    title = "tyre with longitudinal slip (brush model, relaxation length)"
    flanges = ("wheel", "body")
    params = (
        Param("radius", "m", "rolling radius r (the body flange turns at V/r)", low=0.0,
              strict=True, high=5.0),
        Param("J_wheel", "kg·m²", "inertia of the wheels at the wheel flange", low=0.0,
              strict=True, high=1e4),
        Param("Fz", "N", "normal load on the driven tyres", low=0.0, strict=True, high=1e7),
        Param("mu", "-", "peak friction coefficient", default=1.0, low=0.0, strict=True,
              high=5.0),
        Param("C_kappa", "N", "longitudinal slip stiffness dF/dκ at zero slip", low=0.0,
              strict=True, high=1e9),
        Param("sigma", "m", "relaxation length", low=0.0, strict=True, high=10.0),
        Param("v_eps", "m/s", "speed scale of the slip regularisation: V_eps = sqrt(V² + v_eps²)",
              default=0.1, low=0.0, strict=True, high=10.0),
        Param("v0", "m/s", "initial speed of the wheel and the body (ω = v0/r at both; 0: "
              "left to the other components)",
              default=0.0, low=-100.0, high=100.0),
    )
    states = (StateSpec("kappa", "-", "transient longitudinal slip κ'"),)

    def inertias(self):
        return {"wheel": self.J_wheel}

    def initial_speeds(self):
        """``v0/r`` at both flanges; ``v0 = 0`` leaves them to the other components
        (a prescribed speed, an inertia's ``omega0``), 0 where none sets them."""
        if self.v0 == 0.0:
            return {}
        w = self.v0 / self.radius
        return {"wheel": w, "body": w}

    def pack(self):
        d = dict(self.values)
        muf = self.mu * self.Fz
        d.update(muf=muf, kz=self.C_kappa / (3.0 * muf), g0=3.0 * muf * muf / self.C_kappa)
        return d

    def check_network(self, net):
        """A vehicle on the body flange turns at ``V/r`` with its own radius: it must be
        the tyre's."""
        from .vehicle import Vehicle
        me = f"{self.name}.body"
        for group in net.connections:
            if me not in group:
                continue
            for ref in group:
                other = net.component(ref.split(".")[0]) if "." in ref else None
                if isinstance(other, Vehicle) and abs(other.tyre_radius - self.radius) > \
                        1e-12 * self.radius:
                    raise ValueError(f"{self.label}: radius = {self.radius:g} m differs from "
                                     f"{other.label}'s tyre_radius = {other.tyre_radius:g} m "
                                     "at its body flange (both measure V = ω·r: make them "
                                     "equal)")

    def emit(self, e):
        P = e.par
        r, sig, ve0 = P("radius"), P("sigma"), P("v_eps")
        k = e.x("kappa")
        ww, wb = e.w("wheel"), e.w("body")
        v = e.let("v", f"{wb} * {r}")
        ve = e.let("ve", f"math.sqrt({v} * {v} + {ve0} * {ve0})")
        z = e.let("z", f"{P('kz')} * {k}")
        a = e.let("a", f"abs({z})")
        inner = e.let("inn", f"{a} < 1.0")
        f = e.let("f", f"{P('muf')} * ({z} * (3.0 - 3.0 * {a} + {z} * {z})) if {inner} "
                       f"else math.copysign({P('muf')}, {z})")
        fk = e.let("fk", f"{P('C_kappa')} * (1.0 - {a}) * (1.0 - {a}) if {inner} else 0.0")
        e.torque("wheel", f"-{f} * {r}")
        e.torque("body", f"{f} * {r}")
        e.dtorque("wheel", e.kx("kappa"), f"-{fk} * {r}")
        e.dtorque("body", e.kx("kappa"), f"{fk} * {r}")
        e.deriv("kappa", f"(({ww} - {wb}) * {r} - {ve} * {k}) / {sig}")
        e.dderiv("kappa", e.kx("kappa"), f"-{ve} / {sig}")
        e.dderiv("kappa", e.kw("wheel"), f"{r} / {sig}")
        e.dderiv("kappa", e.kw("body"), f"-({r} + {k} * {v} * {r} / {ve}) / {sig}")
        # slip loss F·κ'·V_ε >= 0 (F has the sign of κ')
        e.power("damp", f"{f} * {k} * {ve}")
        e.dpower("damp", e.kx("kappa"), f"({fk} * {k} + {f}) * {ve}")
        e.dpower("damp", e.kw("body"), f"{f} * {k} * {v} * {r} / {ve}")
        # stored: σ·G(κ'), G = g0·(1.5z² − |z|³ + z⁴/4) inside, g0·(|z| − 1/4) outside
        e.spring_energy(f"{sig} * {P('g0')} * ((1.5 * {z} * {z} - {a} * {a} * {a} + 0.25 * "
                        f"{z} * {z} * {z} * {z}) if {inner} else {a} - 0.25)")
        e.output(f"F_x_{self.name}", "N", f)
        e.output(f"slip_speed_{self.name}", "m/s", f"({ww} - {wb}) * {r}")
        e.output(f"kappa_practical_{self.name}", "-", f"({ww} - {wb}) * {r} / {ve}")
