"""Lining wear of a friction element: the rate law and its use in the generated plant.

The wear volume rate is proportional to the friction power (Archard's law written per
dissipated energy, the usual form for clutch facings: the specific wear rate ``k`` is the
worn volume per joule of friction work), with an Arrhenius-type temperature factor and an
optional linear rise above a critical temperature::

    dV/dt = k(θ)·|τ·w|,   k(θ) = k_w · exp(E_a/R · (1/T_ref − 1/T)) · (1 + g·max(θ − θ_crit, 0))

with ``T = θ + 273.15`` K read at the element's first heat node.  The axial thickness loss
of the disc is ``h = V / area`` (``area``: rubbing area of one face; the volume of both faces
over one face's area is what the pressure plate moves), the state ``wear_<element>`` [m].
It is a quadrature of the plant: no derivative reads it, so it stays out of the implicit
solve; its Jacobian row is exact.

Sources:

* J. F. Archard, "Contact and rubbing of flat surfaces", J. Appl. Phys. 24 (1953) 981-988
  (wear volume ∝ load × sliding distance, i.e. ∝ friction work at constant μ);
* VDI 2241 Blatt 1 (1982), "Schaltbare fremdbetätigte Reibkupplungen und -bremsen": the
  specific wear of dry friction linings per friction work [cm³/kWh] as the sizing quantity;
* the temperature dependence of organic facings' wear (an Arrhenius-type rise and a sharp
  increase beyond a critical temperature, where the resin binder degrades) as used in the
  cycle-wise dry-clutch wear model of Appl. Sci. 15 (2025) 8150 (mdpi 2076-3417/15/15/8150).

The numbers in the examples are illustrative (no measured facing), stated where used.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

__all__ = ["GAS_CONSTANT", "WearLaw"]

#: molar gas constant [J/(mol·K)]
GAS_CONSTANT = 8.314462618


def _num(owner, key, value, *, low=None, strict=False, unit=""):
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ValueError(f"{owner}: {key} = {value!r} must be a finite number [{unit}]")
    v = float(value)
    if low is not None and (v < low or (strict and v == low)):
        rule = f"> {low:g}" if strict else f">= {low:g}"
        raise ValueError(f"{owner}: {key} = {v:g} {unit} must be {rule}".rstrip())
    return v


@dataclass(frozen=True)
class WearLaw:
    """The wear law of one friction element (see the module docstring).

    Parameters
    ----------
    k_w : float
        Specific wear rate at ``theta_ref`` [m³/J] (>= 0).
    area : float
        Rubbing area of one lining face [m²] (> 0).
    reserve : float
        Axial wear reserve [m]: the clutch is worn out at ``h >= reserve`` (> 0, <= lining).
    lining : float
        Axial thickness of the lining material that can wear (both faces) [m].
    E_a : float
        Activation energy of the temperature factor [J/mol] (>= 0; 0: no dependence).
    theta_ref : float
        Temperature at which ``k_w`` holds [°C].
    theta_crit : float or None
        Above it the rate rises by ``1 + crit_gain·(θ − theta_crit)`` [°C].
    crit_gain : float
        Slope of that rise [1/K] (>= 0).
    shift : float
        Change of the clamp-table position per metre of axial wear [1/m]: the diaphragm
        spring's installed position moves by ``shift·h`` (0: wear does not move it).
    """

    k_w: float
    area: float
    reserve: float
    lining: float
    E_a: float = 0.0
    theta_ref: float = 20.0
    theta_crit: float | None = None
    crit_gain: float = 0.0
    shift: float = 0.0

    #: the unit of each field (its checks, the scenario key's documentation and a run's
    #: parameter records read it here)
    UNITS: ClassVar[dict[str, str]] = {
        "k_w": "m³/J", "area": "m²", "reserve": "m", "lining": "m", "E_a": "J/mol",
        "theta_ref": "°C", "theta_crit": "°C", "crit_gain": "1/K", "shift": "1/m"}

    def __post_init__(self):
        o, u = "wear", self.UNITS
        set_ = object.__setattr__
        set_(self, "k_w", _num(o, "k_w", self.k_w, low=0.0, unit=u["k_w"]))
        set_(self, "area", _num(o, "area", self.area, low=0.0, strict=True, unit=u["area"]))
        set_(self, "reserve", _num(o, "reserve", self.reserve, low=0.0, strict=True,
                                   unit=u["reserve"]))
        set_(self, "lining", _num(o, "lining", self.lining, low=0.0, strict=True,
                                  unit=u["lining"]))
        if self.reserve > self.lining:
            raise ValueError(f"{o}: reserve = {self.reserve:g} m must be <= lining = "
                             f"{self.lining:g} m (the wear reserve cannot exceed the lining)")
        set_(self, "E_a", _num(o, "E_a", self.E_a, low=0.0, unit=u["E_a"]))
        set_(self, "theta_ref", _num(o, "theta_ref", self.theta_ref, low=-273.15, strict=True,
                                     unit=u["theta_ref"]))
        if self.theta_crit is not None:
            set_(self, "theta_crit", _num(o, "theta_crit", self.theta_crit, low=-273.15,
                                          strict=True, unit=u["theta_crit"]))
        set_(self, "crit_gain", _num(o, "crit_gain", self.crit_gain, low=0.0,
                                     unit=u["crit_gain"]))
        set_(self, "shift", _num(o, "shift", self.shift, unit=u["shift"]))

    def factor(self, theta: float) -> float:
        """``k(θ)/k_w`` [-]."""
        T, Tr = theta + 273.15, self.theta_ref + 273.15
        f = math.exp(self.E_a / GAS_CONSTANT * (1.0 / Tr - 1.0 / T))
        if self.theta_crit is not None and theta > self.theta_crit:
            f *= 1.0 + self.crit_gain * (theta - self.theta_crit)
        return f

    def rate(self, power: float, theta: float) -> float:
        """Axial wear rate ``dh/dt`` [m/s] at friction power ``power`` [W] and ``theta``."""
        return self.k_w * self.factor(theta) * abs(power) / self.area

    def pack(self) -> dict[str, float]:
        """The values the generated plant reads."""
        return {"wear_k": self.k_w / self.area,
                "wear_EaR": self.E_a / GAS_CONSTANT,
                "wear_Tref": self.theta_ref + 273.15,
                "wear_thc": 1e300 if self.theta_crit is None else self.theta_crit,
                "wear_gain": self.crit_gain}

    @classmethod
    def from_table(cls, table: dict, fail=None, key: str = "wear") -> WearLaw:
        """From a ``wear = {...}`` table; ``fail(message, key)`` reports errors with the
        file and line (default: ValueError)."""
        known = ("k_w", "area", "reserve", "lining", "E_a", "theta_ref", "theta_crit",
                 "crit_gain", "shift")
        if not isinstance(table, dict):
            msg = f"{key} = {table!r} must be a table {{k_w = ..., area = ..., ...}}"
            if fail:
                fail(msg, key)
            raise TypeError(msg)
        for k in table:
            if k not in known:
                msg = f"unknown key {k!r}; keys: {', '.join(known)}"
                if fail:
                    fail(msg, f"{key}.{k}")
                raise ValueError(f"{key}: {msg}")
        try:
            return cls(**table)
        except (TypeError, ValueError) as exc:
            msg = str(exc).removeprefix("wear: ")
            bad = next((k for k in known if msg.startswith(f"{k} =")), None)
            if fail:
                fail(msg, f"{key}.{bad}" if bad else key)
            raise ValueError(f"{key}: {msg}") from None
