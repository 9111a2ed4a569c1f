"""A wet multi-plate clutch: N oil-cooled friction interfaces, engaged by a piston, with
the viscous drag of the open pack.

Engagement.  The command is the piston pressure ``p`` [Pa] (a signal).  The piston (area
``A``) travels its clearance ``stroke`` against a return spring (``spring_preload`` F0,
``spring_rate`` k) and then clamps the pack with::

    F = max(0, p·A − (F0 + k·stroke))

(quasi-static: the fill time is the pressure signal's business).  The ``interfaces``
(N_int) friction faces in series share the clamp force, so the capacity is
``N_int·μ·F·R_m`` with ``R_m = (r_inner + r_outer)/2`` (uniform wear).  The friction is
the friction clutch's (:mod:`.friction`): any friction model of the library, its force
levels read as ``μ`` [-] (as the cone clutch's), ``mu_slip`` and ``mu_temperature``
tables for a wet-paper characteristic ``μ(Δω, θ)``, heat by shares into thermal nodes
(the plates).

Open-clutch drag.  Each open interface shears an oil film of thickness ``gap`` (h); the
Couette flow between an annulus turning at the slip ``w`` and a still one gives::

    T_drag = drag_factor·N_int·π·η(θ)·w·(r_e⁴ − r_i⁴)/(2·h)

with ``r_e = r_o`` for a full film.  With a finite oil ``flow`` Q through the pack
(``Q/N_int`` per gap) the centrifugal pumping of the sheared film needs more oil than is
supplied above a critical speed and the film shrinks to the radius where the radial flow
of the thin-film (lubrication) equations equals the supply::

    Q/N_int = π·ρ·w²·h³·r_e²/(20·η)   ->   r_e² = 20·ν·(Q/N_int)/(π·h³·w²)

clipped to ``[r_i, r_o]`` (the film-shrinkage model of Kitabayashi et al. 2003, Hu, Peng
& Yuan 2009 and Iqbal et al. 2013, without their surface-tension term; the derivation is
in docs/components.md).  Outside ``r_e`` the gap holds an air-oil mist of viscosity
``mist·η`` (Iqbal et al.'s mist film; ``mist`` = 0: none)::

    T_drag = drag_factor·N_int·π·η·w·((1 − mist)·r_e⁴ − r_i⁴ + mist·r_o⁴)/(2·h)

The drag is linear in ``w`` up to the critical speed
``w_c = sqrt(20·ν·Q/N_int/(π·h³))/r_o``, peaks there, then falls as ``a²/w³ − r_i⁴·w``
(``a = r_e²·w²``, without mist) to the mist's share where ``r_e`` reaches ``r_i``.
``flow`` = 0 is a flooded pack: the full film at every speed.

Viscosity.  Walther's equation of ASTM D341 through the oil's two data-sheet points
``nu40`` and ``nu100`` [mm²/s]: ``log10(log10(ν + 0.7)) = A − B·log10(T)`` (T in K), and
``η = ρ·ν``; ``θ`` is the temperature of the thermal node ``oil`` (else ``oil_temperature``).

The drag power ``T_drag·w >= 0`` is viscous: it is booked in ``W_damping`` (the energy
balance closes), heats the ``oil`` node, and its work is the element's own state
``W_drag_<name>`` [J].  Outputs: ``T_drag_<name>``, ``P_drag_<name>`` [W],
``F_clamp_<name>`` [N], ``r_film_<name>`` [m], ``nu_oil_<name>`` [mm²/s].

References
----------
Kitabayashi H., Li C.Y., Hiraki H., Analysis of the Various Factors Affecting Drag Torque
in Multiple-Plate Wet Clutches, SAE 2003-01-1973; Hu J., Peng Z., Yuan S., Drag torque
modelling for disengaged wet clutches and its validation, Proc. IMechE Part D 2009;
Iqbal S., Al-Bender F., Pluymers B., Desmet W., Mathematical Model and Experimental
Evaluation of Drag Torque in Disengaged Wet Clutches, ISRN Tribology 2013, 206539;
ASTM D341, Standard Practice for Viscosity-Temperature Equations and Charts for Liquid
Petroleum or Hydrocarbon Products (Walther's equation, ``Z = ν + 0.7``).
"""

from __future__ import annotations

import math
from typing import ClassVar

from ..spec import Param
from .cone_clutch import MU_MAX
from .friction import Clutch

#: Walther's constant of ASTM D341 (``Z = ν + 0.7``, ν in mm²/s, for ν >= 2 mm²/s)
WALTHER_C = 0.7
#: the data-sheet temperatures of ``nu40`` and ``nu100`` [K]
T40, T100 = 313.15, 373.15


def walther_coefficients(nu40: float, nu100: float) -> tuple[float, float]:
    """``(A, B)`` of ``log10(log10(ν + 0.7)) = A − B·log10(T/K)`` through the two points."""
    y40 = math.log10(math.log10(nu40 + WALTHER_C))
    y100 = math.log10(math.log10(nu100 + WALTHER_C))
    b = (y40 - y100) / (math.log10(T100) - math.log10(T40))
    return y40 + b * math.log10(T40), b


def walther_nu(theta: float, A: float, B: float) -> float:
    """Kinematic viscosity [mm²/s] at ``theta`` [°C] by Walther's equation."""
    return 10.0 ** (10.0 ** (A - B * math.log10(theta + 273.15))) - WALTHER_C


def couette_drag(w: float, eta: float, h: float, r_i: float, r_o: float,
                 n: float = 1.0) -> float:
    """The full-film drag ``n·π·η·w·(r_o⁴ − r_i⁴)/(2·h)`` [N·m] (the closed form)."""
    return n * math.pi * eta * w * (r_o ** 4 - r_i ** 4) / (2.0 * h)


class WetClutch(Clutch):
    """A wet multi-plate clutch between flanges a and b (see the module docstring)."""

    kind = "wet_clutch"
    fault_keys = ()
    title = "wet multi-plate clutch (N·μ·F·R_m, piston and return spring, oil-film drag)"
    params = (
        Param("interfaces", "-", "number of friction interfaces N_int (2 per friction "
              "plate), an integer", low=1.0, high=100.0),
        Param("r_inner", "m", "inner radius of the friction faces", low=0.0, strict=True,
              high=1.0),
        Param("r_outer", "m", "outer radius of the friction faces (> r_inner)", low=0.0,
              strict=True, high=1.0),
        Param("piston_area", "m²", "piston area", low=0.0, strict=True, high=1.0),
        Param("spring_preload", "N", "return spring force at the open position",
              default=0.0, low=0.0, high=1e7),
        Param("spring_rate", "N/m", "return spring stiffness", default=0.0, low=0.0,
              high=1e9),
        Param("stroke", "m", "piston travel to the kiss point (the pack's clearance)",
              default=0.0, low=0.0, high=0.1),
        Param("gap", "m", "oil film thickness h of each open interface", low=0.0,
              strict=True, high=0.01),
        Param("drag_factor", "-", "factor on the modelled drag (1: the model; grooves and "
              "waviness change it)", default=1.0, low=0.0, high=100.0),
        Param("flow", "m³/s", "oil flow through the pack, shared by the interfaces (0: a "
              "flooded pack, the full film at every speed)", default=0.0, low=0.0,
              high=0.1),
        Param("mist", "-", "viscosity of the aerated (air-oil mist) part of a shrunk film, "
              "r_e..r_o, relative to the oil's (0: no drag there)", default=0.0, low=0.0,
              high=1.0),
        Param("nu40", "mm²/s", "kinematic viscosity of the oil at 40 °C (data sheet)",
              default=30.0, low=2.0, high=1e5),
        Param("nu100", "mm²/s", "kinematic viscosity of the oil at 100 °C (data sheet, "
              "< nu40)", default=6.0, low=2.0, high=1e5),
        Param("density", "kg/m³", "density of the oil", default=850.0, low=100.0,
              high=3000.0),
        Param("oil_temperature", "°C", "oil temperature without an oil node",
              default=40.0, low=-60.0, high=300.0),
    )
    signal_docs: ClassVar[dict] = {
        "oil": (("Thermal node of the oil: its temperature sets the viscosity, and the drag "
                 "power heats it (default: none, `oil_temperature`)."), False)}

    def __init__(self, name, model, command, mu_temperature=None, mu_slip=None, heat=(),
                 locked0=None, z0=None, oil=None, **values):
        super().__init__(name, model, command, mu_temperature=mu_temperature,
                         mu_slip=mu_slip, heat=heat, locked0=locked0, z0=z0, **values)
        o = self.label
        mu_s = model.static_capacity()
        v = self.values

        def bad(key, text):
            err = ValueError(f"{o}: {text}")
            err.key = key               # the scenario key it concerns (scenario/build.py)
            return err

        if not mu_s <= MU_MAX:
            raise bad("friction", f"the friction model's static level {mu_s:g} must be a "
                      f"friction coefficient <= {MU_MAX:g}: a wet clutch reads its model's "
                      "force levels as mu [-] (e.g. F_c = 0.12, F_s = 0.13 for "
                      "coulomb-robust)")
        if v["interfaces"] != round(v["interfaces"]):
            raise bad("interfaces", f"interfaces = {v['interfaces']:g} must be an integer "
                      ">= 1 (2 per friction plate)")
        if not v["r_inner"] < v["r_outer"]:
            raise bad("r_inner", f"r_inner = {v['r_inner']:g} m must be < r_outer = "
                      f"{v['r_outer']:g} m")
        if not v["nu100"] < v["nu40"]:
            raise bad("nu100", f"nu100 = {v['nu100']:g} mm²/s must be < nu40 = "
                      f"{v['nu40']:g} mm²/s (an oil thins as it warms)")
        if oil is not None and (not isinstance(oil, str) or not oil):
            raise bad("oil", f"oil = {oil!r} must name a thermal node")
        self.oil = oil

    @property
    def reads_force(self) -> bool:
        return True

    @property
    def R_m(self) -> float:
        """Mean friction radius [m], uniform wear."""
        return 0.5 * (self.r_inner + self.r_outer)

    @property
    def kiss_pressure(self) -> float:
        """Pressure [Pa] at which the piston touches the pack: ``(F0 + k·stroke)/A``."""
        return (self.spring_preload + self.spring_rate * self.stroke) / self.piston_area

    def clamp_force(self, p: float) -> float:
        """The clamp force [N] at the pressure ``p`` [Pa]: ``max(0, p·A − F_spring)``."""
        return max(0.0, (p - self.kiss_pressure) * self.piston_area)

    def capacity_at(self, p: float) -> float:
        """The static capacity [N·m] at ``p``: ``N_int·μ_s·F·R_m``."""
        return (self.interfaces * self.model.static_capacity() * self.clamp_force(p)
                * self.R_m)

    def nu(self, theta: float) -> float:
        """Kinematic viscosity [mm²/s] of the oil at ``theta`` [°C] (ASTM D341)."""
        return walther_nu(theta, *walther_coefficients(self.nu40, self.nu100))

    def drag_torque(self, w: float, theta: float) -> float:
        """The open-pack drag [N·m] at the slip ``w`` [rad/s] and oil temperature
        ``theta`` [°C] (the model of the module docstring, for checks and reports)."""
        nu = self.nu(theta) * 1e-6
        ri2, ro2 = self.r_inner ** 2, self.r_outer ** 2
        re2 = ro2
        if self.flow > 0.0 and w != 0.0:
            a = 20.0 * nu * self.flow / self.interfaces / (math.pi * self.gap ** 3)
            re2 = min(max(a / (w * w), ri2), ro2)
        g = (1.0 - self.mist) * re2 * re2 - ri2 * ri2 + self.mist * ro2 * ro2
        return (self.drag_factor * self.interfaces * math.pi * self.density * nu * w * g
                / (2.0 * self.gap))

    def options(self):
        return (*super().options(), self.oil, self.flow > 0.0)

    def check_network(self, net):
        super().check_network(net)
        if self.oil is not None:
            nodes = [c.name for c in net.components if getattr(c, "thermal", False)]
            if self.oil not in nodes:
                raise ValueError(f"{self.label}: oil = {self.oil!r} is not a thermal node "
                                 f"(thermal nodes: {', '.join(nodes) or 'none'})")

    def input_units(self):
        return {self.command: "Pa"}

    def pack(self):
        d = super().pack()
        # the command less the kiss-point pressure, over clamp_reference, is the model's
        # scale: (p − p_kiss)·A·N_int·R_m [m·N]
        d["clamp_reference"] = 1.0 / (self.piston_area * self.interfaces * self.R_m)
        d["p_kiss"] = self.kiss_pressure
        d["walther_A"], d["walther_B"] = walther_coefficients(self.nu40, self.nu100)
        d["drag_k"] = (self.drag_factor * self.interfaces * math.pi * self.density * 1e-6
                       / (2.0 * self.gap))
        d["ri2"], d["ro2"] = self.r_inner ** 2, self.r_outer ** 2
        d["shrink_c"] = 20.0 * 1e-6 * self.flow / self.interfaces / (math.pi * self.gap ** 3)
        return d

    def state_layout(self):
        return [*super().state_layout(), ("W_drag", f"W_drag_{self.name}", "J")]

    def initial_state(self, ctx):
        return [*super().initial_state(ctx), 0.0]

    def _command(self, e) -> str:
        return f"({e.u(self.command)} - {e.par('p_kiss')})"

    def emit(self, e):
        super().emit(e)
        P = e.par
        w = e.let("wd", f"{e.w('b')} - {e.w('a')}")
        # viscosity [mm²/s] by Walther's equation and its derivative by the temperature
        th = P("oil_temperature") if self.oil is None else e.theta(self.oil)
        tk = e.let("tk", f"{th} + 273.15")
        ln10 = repr(math.log(10.0))
        y = e.let("wy", f"math.exp(({P('walther_A')} - {P('walther_B')} * math.log({tk}) "
                        f"/ {ln10}) * {ln10})")
        z = e.let("wz", f"math.exp({y} * {ln10})")
        nu = e.let("nu", f"{z} - {WALTHER_C!r}")
        dnu = e.let("dnu", f"-{z} * {y} * {ln10} * {P('walther_B')} / {tk}")
        ri4 = f"({P('ri2')} * {P('ri2')})"
        k = P("drag_k")
        if self.flow > 0.0:
            # the film's outer radius: r_e² = c·ν/w², clipped to [r_i², r_o²]
            ww = e.let("ww", f"max({w} * {w}, 1e-300)")
            re2 = e.let("re2", f"min(max({P('shrink_c')} * {nu} / {ww}, {P('ri2')}), "
                               f"{P('ro2')})")
            mid = e.let("fmid", f"1.0 if {P('ri2')} < {re2} < {P('ro2')} else 0.0")
        else:
            re2, mid = P("ro2"), "0.0"
        re4 = e.let("re4", f"{re2} * {re2}")
        e.output(f"r_film_{self.name}", "m", f"math.sqrt({re2})")
        # T = k·ν·w·g: g = (1 − m)·r_e⁴ − r_i⁴ + m·r_o⁴ (oil film inside r_e, mist of relative
        # viscosity m outside); r_e⁴ = c²ν²/w⁴ on the shrinking branch (mid), constant else
        m1 = f"(1.0 - {P('mist')})"
        g = e.let("g", f"{m1} * {re4} - {ri4} + {P('mist')} * {P('ro2')} * {P('ro2')}")
        dtw = e.let("dtw", f"{k} * {nu} * ({g} - 4.0 * {mid} * {m1} * {re4})")
        dtn = e.let("dtn", f"{k} * {w} * ({g} + 2.0 * {mid} * {m1} * {re4})")
        td = e.let("td", f"{k} * {nu} * {w} * {g}")
        pd = e.let("pd", f"{td} * {w}")
        dpw = e.let("dpw", f"{dtw} * {w} + {td}")
        # the drag opposes the slip: −T on b, +T on a
        e.torque("b", f"-{td}")
        e.torque("a", td)
        speeds = [(e.kw("b"), "1.0"), (e.kw("a"), "-1.0")]
        for key, s in speeds:
            e.dtorque("b", key, f"-{s} * {dtw}")
            e.dtorque("a", key, f"{s} * {dtw}")
        e.power("damp", pd)
        e.deriv("W_drag", pd)
        for key, s in speeds:
            e.dpower("damp", key, f"{s} * {dpw}")
            e.dderiv("W_drag", key, f"{s} * {dpw}")
        if self.oil is not None:
            kt = e.ktheta(self.oil)
            dtt = e.let("dtt", f"{dtn} * {dnu}")
            e.dtorque("b", kt, f"-{dtt}")
            e.dtorque("a", kt, dtt)
            e.dpower("damp", kt, f"{dtt} * {w}")
            e.dderiv("W_drag", kt, f"{dtt} * {w}")
            e.heat(self.oil, pd)
            for key, s in speeds:
                e.dheat(self.oil, key, f"{s} * {dpw}")
            e.dheat(self.oil, kt, f"{dtt} * {w}")
        e.output(f"T_drag_{self.name}", "N·m", td)
        e.output(f"P_drag_{self.name}", "W", pd)
        e.output(f"nu_oil_{self.name}", "mm²/s", nu)
        e.output(f"F_clamp_{self.name}", "N",
                 f"max(({e.u(self.command)} - {P('p_kiss')}) * {P('piston_area')}, 0.0)")
