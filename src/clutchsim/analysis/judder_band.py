"""The judder band: the first-mode band of a slipping driveline and the time-domain judder
metric of every run.

:func:`judder_amplitude` is ``judder_amplitude_Nm`` in
:func:`~clutchsim.analysis.launch_metrics.launch_metrics`: the amplitude of the clutch
torque's oscillation in the first-mode band while the clutch slips.  The launch metrics
(:mod:`clutchsim.analysis.launch_metrics`) and the compiled batch
(:mod:`clutchsim.analysis.launch_batch`) use the same band and slip threshold.
"""

from __future__ import annotations

import math

import numpy as np

from . import _kernels as _k

__all__ = ["JUDDER_BAND_HZ", "JUDDER_SLIP_RAD_S", "judder_amplitude"]

#: default first-mode band of a passenger-car driveline while the clutch slips [Hz]: the
#: first torsional mode with the clutch slipping (the disc and gearbox on the damper
#: spring against the vehicle) lies at ~5-20 Hz; 2-30 Hz keeps it with margin and leaves
#: out the slow engagement ramp and the fast contact modes.
JUDDER_BAND_HZ = (2.0, 30.0)
#: slip below which the clutch counts as held [rad/s] (as the lock-up metric)
JUDDER_SLIP_RAD_S = 1.0


def judder_amplitude(res, clutch: str = "clutch", band=JUDDER_BAND_HZ) -> float | None:
    """Amplitude [N·m] of the clutch torque ``T_<clutch>``'s oscillation in ``band`` [Hz]
    while the clutch slips.

    The window runs from the first to the last sample where the engaged clutch (capacity
    above 5 % of its largest) slips faster than 1 rad/s.  The torque is resampled
    uniformly (20 samples per period of the band's upper edge), its linear trend removed,
    band-passed (the DFT bins in ``band``) and its amplitude given as ``√2·RMS`` (the
    amplitude of a sine of the same power; the RMS from the bins by Parseval).  0 for a
    torque without oscillation in the band; None when the run has no such clutch outputs,
    never slips while engaged, or slips for less than one period of the band's lower edge.
    Compiled: :func:`clutchsim.analysis._kernels.judder`.
    """
    lo, hi = (float(b) for b in band)
    if not 0.0 < lo < hi:
        raise ValueError(f"band = {band!r} Hz must satisfy 0 < low < high")
    names = (f"T_{clutch}", f"w_slip_{clutch}", f"capacity_{clutch}")
    if not all(n in res.signals for n in names) or res.t.size < 3:
        return None
    t = np.ascontiguousarray(res.t, dtype=float)
    torque, w, cap = (np.ascontiguousarray(res[n], dtype=float) for n in names)
    v = _k.judder(t, torque, cap, w, lo, hi, JUDDER_SLIP_RAD_S)
    return None if math.isnan(v) else float(v)
