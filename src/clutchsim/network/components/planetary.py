"""An ideal planetary gear set (sun, carrier, ring)."""

from __future__ import annotations

from typing import ClassVar

from ..component import Component
from ..spec import Param


class Planetary(Component):
    """``(1 + ratio)·ω_carrier = ω_sun + ratio·ω_ring`` with ``ratio = z_ring/z_sun``
    (Modelica ``IdealPlanetary``; speeds absolute).

    Give ``ratio`` or the tooth counts ``z_sun`` and ``z_ring`` (integers, ``z_ring >
    z_sun``, ``z_ring − z_sun`` even so that the planets, of ``(z_ring − z_sun)/2`` teeth,
    mesh with both).  Outputs ``T_<name>_<flange>``: the torque the set exerts on the part
    at each flange [N·m].
    """

    kind = "planetary"
    title = "ideal planetary gear set"
    flanges = ("sun", "carrier", "ring")
    params = (Param("ratio", "-", "z_ring/z_sun", low=1.0, strict=True),)
    alternative_keys: ClassVar[dict] = {"ratio": "z_sun and z_ring"}

    def __init__(self, name, z_sun=None, z_ring=None, **values):
        if z_sun is not None or z_ring is not None:
            label = f"planetary {name!r}"
            for key, z in (("z_sun", z_sun), ("z_ring", z_ring)):
                if isinstance(z, bool) or not isinstance(z, int) or z < 1:
                    raise ValueError(f"{label}: {key} = {z!r} must be a whole number of "
                                     "teeth >= 1 (give both z_sun and z_ring, or ratio)")
            if z_ring <= z_sun:
                raise ValueError(f"{label}: z_ring = {z_ring} must exceed z_sun = {z_sun} "
                                 "(the ring gear surrounds the sun)")
            if (z_ring - z_sun) % 2:
                raise ValueError(f"{label}: z_ring - z_sun = {z_ring - z_sun} must be even: "
                                 f"the planets would need {(z_ring - z_sun) / 2:g} teeth")
            if "ratio" in values:
                raise ValueError(f"{label}: give ratio or z_sun/z_ring, not both")
            values["ratio"] = z_ring / z_sun
        super().__init__(name, **values)

    def constraints(self):
        r = self.ratio
        return [{"carrier": 1.0 + r, "sun": -1.0, "ring": -r}]

    def emit(self, e):
        for fl in self.flanges:
            e.output(f"T_{self.name}_{fl}", "N·m", e.constraint_torque(0, fl))
