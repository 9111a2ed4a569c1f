"""An open (bevel-gear) differential.

The case turns with the mean of the two side shafts, ``ω_case = (ω_left + ω_right)/2``,
and the input (the pinion, driving the crown wheel on the case) ``ratio`` times faster::

    2·ω_input/ratio = ω_left + ω_right

An ideal, rigid and lossless set of gears (a linear constraint of the network, like
:mod:`.planetary`): by virtual work each side shaft receives ``ratio·T_input/2`` whatever
the two speeds (the open differential's equal torque split), and no power is lost.
Outputs ``T_<name>_<flange>``: the torque the differential exerts on the part at each
flange [N·m].

References
----------
Modelica Standard Library 4.x, ``Modelica.Mechanics.Rotational.Components.IdealPlanetary``
(a differential is a planetary set with ``ratio = 1`` between the side gears, the carrier
the case); MathWorks Simscape Driveline, Differential block; Genta G., Morello L., *The
Automotive Chassis*, vol. 1, Springer, 2009, §12 (the open differential's torque split).
"""

from __future__ import annotations

from ..component import Component
from ..spec import Param


class OpenDifferential(Component):
    """``2·ω_input/ratio = ω_left + ω_right`` (see the module docstring)."""

    kind = "open_differential"
    title = "open differential (equal torque split)"
    flanges = ("input", "left", "right")
    params = (Param("ratio", "-", "final-drive ratio ω_input/ω_case (crown wheel over "
                    "pinion teeth)", default=1.0, low=0.0, strict=True, high=100.0),)

    def constraints(self):
        return [{"input": 2.0 / self.ratio, "left": -1.0, "right": -1.0}]

    def emit(self, e):
        for fl in self.flanges:
            e.output(f"T_{self.name}_{fl}", "N·m", e.constraint_torque(0, fl))
