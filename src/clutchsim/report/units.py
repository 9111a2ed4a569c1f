"""Units and readable labels from metric names (``lockup_time_s`` -> "lockup time" [s]).

A name carries a unit when it ends in ``_<unit>`` with a stem of at least three
characters, so parameter symbols such as ``F_s`` (static friction force) or ``v_s``
(Stribeck velocity) are not mistaken for times.
"""

from __future__ import annotations

__all__ = ["SUFFIX_UNITS", "label", "split_unit"]

#: name suffix -> unit shown in the report (suffixes are case sensitive: ``_C`` is
#: degrees Celsius, ``_c`` is not a unit)
SUFFIX_UNITS = {
    "s": "s", "ms": "ms", "us": "µs", "min": "min", "h": "h", "Hz": "Hz",
    "J": "J", "kJ": "kJ", "MJ": "MJ", "W": "W", "kW": "kW",
    "N": "N", "kN": "kN", "Nm": "N·m", "kNm": "kN·m",
    "m": "m", "mm": "mm", "km": "km", "kg": "kg", "Pa": "Pa", "kPa": "kPa", "bar": "bar",
    "rpm": "rpm", "rad": "rad", "deg": "°", "radps": "rad/s", "rads": "rad/s",
    "radps2": "rad/s²", "mps": "m/s", "mps2": "m/s²", "mps3": "m/s³", "kmh": "km/h",
    "C": "°C", "K": "K", "pct": "%", "percent": "%", "mps175": "m/s^1.75",
    "J_mm2": "J/mm²", "W_mm2": "W/mm²",
}

_MIN_STEM = 3


def split_unit(name: str) -> tuple[str, str | None]:
    """Split ``name`` into (stem, unit); unit is None when the name carries none.

    Examples
    --------
    >>> split_unit("lockup_time_s")
    ('lockup_time', 's')
    >>> split_unit("F_s")
    ('F_s', None)
    >>> split_unit("friction_energy_density_J_mm2")
    ('friction_energy_density', 'J/mm²')
    """
    parts = str(name).split("_")
    for n in (2, 1):   # a per-area unit (``_J_mm2``) before a plain one
        stem, suffix = "_".join(parts[:-n]), "_".join(parts[-n:])
        if len(parts) > n and len(stem) >= _MIN_STEM and suffix in SUFFIX_UNITS:
            return stem, SUFFIX_UNITS[suffix]
    return str(name), None


def label(name: str) -> tuple[str, str | None]:
    """A readable label and the unit of a metric name: underscores become spaces.

    Examples
    --------
    >>> label("peak_heat_node_temp_C")
    ('peak heat node temp', '°C')
    """
    stem, unit = split_unit(name)
    return stem.replace("_", " "), unit
