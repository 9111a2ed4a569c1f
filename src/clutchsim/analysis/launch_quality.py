"""Launch and shift quality metrics: pure functions on sampled signals.

Every function takes time [s] and signal arrays (SI units; the unit is in the argument
name) sampled on a possibly non-uniform grid that may hold the same time twice (the
driveline output grid holds a sample before and after each located event).  The
formulas and their sources are in ``docs/launch-quality.md``;
:func:`clutchsim.analysis.launch_metrics.launch_metrics` applies them to a driveline run.

Filters run on a uniform grid: the signal is interpolated linearly onto
``t0, t0 + dt, ...`` with :data:`FILTER_DT_S` (a 2 kHz rate, 20 times the W_d band limit
of 100 Hz) and the filtered signal is interpolated back onto the original times.

The formulas run as compiled code (:mod:`clutchsim.analysis._kernels`); the same code
computes all the metrics of a driveline run in one call
(:func:`clutchsim.analysis._kernels.launch_kernel`).  scipy designs the filters
(:func:`_wd_sos`, :func:`_lowpass_sos`), once per grid step; the designs are kept on disk
(:func:`_designed`), so that a later process does not import ``scipy.signal`` for them.
"""

from __future__ import annotations

import functools
import hashlib
import math
from pathlib import Path

import numpy as np

from .._jit import cache_dir
from .._util import atomic_write
from . import _kernels as _k

__all__ = ["ENGAGE_THRESHOLD_REL", "FILTER_DT_MAX_S", "FILTER_DT_S", "JERK_CUTOFF_HZ",
           "SHOCK_REF_S", "SHOCK_WINDOW_S",
           "WD_F1_HZ", "WD_F2_HZ", "WD_F3_HZ", "WD_F4_HZ", "WD_Q4", "engagement_start_s",
           "engine_dip_flare_rpm", "friction_densities",
           "jerk_mps3", "lining_area_mm2", "lockup_shock_mps2", "lockup_time_s", "rms",
           "uniform_grid", "vdv_mps175", "wd_analog_zpk", "wd_magnitude",
           "weighted_acceleration_mps2"]

#: sampling step of the uniform grid the filters run on [s] (2 kHz)
FILTER_DT_S = 5e-4
#: most samples of that grid; a longer run gets a coarser step, up to FILTER_DT_MAX_S [-]
FILTER_MAX_SAMPLES = 2_000_000

#: ISO 2631-1:1997 Annex A, Table A.2, weighting W_d (x- and y-axis, seated): band
#: limits f1, f2 (2nd-order Butterworth high- and low-pass, Q1 = Q2 = 1/sqrt 2) and the
#: acceleration-velocity transition f3, f4, Q4; W_d has no upward step (f5 = f6 = inf)
WD_F1_HZ = 0.4
WD_F2_HZ = 100.0
WD_F3_HZ = 2.0
WD_F4_HZ = 2.0
WD_Q4 = 0.63

#: engagement starts where the transmitted torque first exceeds this share of its
#: largest magnitude in the run [-]
ENGAGE_THRESHOLD_REL = 0.02
#: corner of the 2nd-order Butterworth low-pass applied before differentiating the
#: acceleration into jerk [Hz]
JERK_CUTOFF_HZ = 10.0
#: the lock-up shock is the largest deviation of the acceleration from its level before
#: lock-up within this time after it [s]: the first swing of the driveline's shuffle mode
#: (2-10 Hz, a half period of 50-250 ms) that the lock-up excites
SHOCK_WINDOW_S = 0.2
#: ... that level: the mean acceleration over this time before lock-up [s]
SHOCK_REF_S = _k.SHOCK_REF_S
#: coarsest step of the filters' uniform grid [s] (400 Hz: twice the W_d band limit of
#: 100 Hz, so every filter stays designable however long the run)
FILTER_DT_MAX_S = _k.FILTER_DT_MAX_S


def _arrays(t_s, *signals):
    """``t_s`` and ``signals`` as contiguous float arrays, checked: 1-D, same shape, time
    not decreasing (repeated times allowed: integrals give them zero width)."""
    t = np.ascontiguousarray(t_s, dtype=float)
    arrays = [np.ascontiguousarray(x, dtype=float) for x in signals]
    if t.ndim != 1:
        raise ValueError(f"time must be a 1-D array, got shape {t.shape}")
    for x in arrays:
        if x.shape != t.shape:
            raise ValueError(f"signal of shape {x.shape} does not match the time grid "
                             f"of shape {t.shape}")
    if t.size > 1 and np.any(np.diff(t) < 0):
        raise ValueError("time must not decrease")
    return (t, *arrays)


def _none(v: float) -> float | None:
    return None if math.isnan(v) else float(v)


def filter_step_s(t_s, dt_s: float = FILTER_DT_S) -> float:
    """The step of the uniform grid :func:`uniform_grid` puts under ``t_s`` [s]
    (``tu[1] - tu[0]``, the step the filters are designed for): ``dt_s``, coarser for a run
    longer than :data:`FILTER_MAX_SAMPLES` steps but never coarser than
    :data:`FILTER_DT_MAX_S` (a ValueError for a ``dt_s`` above it)."""
    if not 0 < float(dt_s) <= FILTER_DT_MAX_S:
        raise ValueError(f"filter step dt_s = {dt_s!r} s must be in (0, {FILTER_DT_MAX_S:g}] s "
                         f"(the filters need a rate of at least {1 / FILTER_DT_MAX_S:g} Hz, "
                         f"twice the W_d band limit of {WD_F2_HZ:g} Hz)")
    t0, t1 = float(t_s[0]), float(t_s[-1])
    dt = max(float(dt_s), min((t1 - t0) / FILTER_MAX_SAMPLES, FILTER_DT_MAX_S))
    return (t0 + dt) - t0


def uniform_grid(t_s, x, dt_s: float = FILTER_DT_S):
    """``(tu_s, xu)``: ``x`` interpolated linearly onto a uniform grid from ``t_s[0]``
    to ``t_s[-1]`` with step ``dt_s`` (coarser if that would exceed
    ``FILTER_MAX_SAMPLES``; the last point is ``t_s[-1]`` itself only when the span is
    a whole number of steps); at a repeated time the last sample (the value after a
    reset) counts."""
    t, x = _arrays(t_s, x)
    idx = _k.grid_index(t, True)
    return _k.uniform_grid(t[idx], x[idx], float(dt_s), FILTER_MAX_SAMPLES)


def wd_analog_zpk():
    """Zeros [rad/s], poles [rad/s] and gain of the W_d weighting as an analog filter,
    ISO 2631-1:1997 Annex A (Table A.2 for W_d, k = 1):

    ``H(s) = Hh(s)·Hl(s)·Ht(s)`` with
    ``Hh = s² / (s² + ω1 s/Q1 + ω1²)`` (high-pass, f1 = 0.4 Hz, Q1 = 1/√2),
    ``Hl = ω2² / (s² + ω2 s/Q2 + ω2²)`` (low-pass, f2 = 100 Hz, Q2 = 1/√2),
    ``Ht = (1 + s/ω3) / (1 + s/(Q4 ω4) + s²/ω4²)`` (a-v transition, f3 = f4 = 2 Hz,
    Q4 = 0.63), ω = 2πf.
    """
    w1, w2, w3, w4 = (2 * math.pi * f for f in (WD_F1_HZ, WD_F2_HZ, WD_F3_HZ, WD_F4_HZ))
    q = 1 / math.sqrt(2)
    poles = np.concatenate([np.roots([1, w1 / q, w1 ** 2]), np.roots([1, w2 / q, w2 ** 2]),
                            np.roots([1, w4 / WD_Q4, w4 ** 2])])
    zeros = np.array([0.0, 0.0, -w3])
    gain = w2 ** 2 * w4 ** 2 / w3
    return zeros, poles, gain


def wd_magnitude(f_Hz):
    """|W_d| at frequencies ``f_Hz`` [-], from :func:`wd_analog_zpk` (the analog filter,
    not its discretisation)."""
    from scipy import signal
    z, p, k = wd_analog_zpk()
    _, h = signal.freqs_zpk(z, p, k, worN=2 * np.pi * np.atleast_1d(np.asarray(f_Hz, float)))
    return np.abs(h)


@functools.lru_cache(maxsize=16)
def _wd_sos(dt_s: float) -> tuple:
    """``(sos, zi)``: W_d discretised for step ``dt_s`` by the bilinear transform (Tustin,
    without pre-warping: at 2 kHz the frequency warp is below 0.1 % up to 30 Hz) and its
    steady state for a unit constant input (cached per step: designing it costs more
    than filtering a launch).  The compiled filter (``_kernels.sosfilt``) runs these
    second-order sections as difference equations."""
    def design():
        from scipy import signal
        z, p, k = wd_analog_zpk()
        zd, pd, kd = signal.bilinear_zpk(z, p, k, 1.0 / dt_s)
        sos = np.ascontiguousarray(signal.zpk2sos(zd, pd, kd))
        return sos, np.ascontiguousarray(signal.sosfilt_zi(sos))
    return _designed("wd", (dt_s,), design)


@functools.lru_cache(maxsize=16)
def _lowpass_sos(cutoff_Hz: float, dt_s: float):
    """``(sos, zi)``: 2nd-order Butterworth low-pass of corner ``cutoff_Hz`` for step
    ``dt_s`` and its steady state for a unit input (cached; run by ``_kernels.filtfilt``);
    a ValueError for a corner at or above the grid's Nyquist frequency."""
    if not 0 < cutoff_Hz < 0.5 / dt_s:
        raise ValueError(f"low-pass corner cutoff_Hz = {cutoff_Hz:g} Hz must be in (0, "
                         f"{0.5 / dt_s:g}) Hz, below half the filter grid's rate "
                         f"(step {dt_s:g} s)")

    def design():
        from scipy import signal
        sos = np.ascontiguousarray(signal.butter(2, cutoff_Hz, btype="low", fs=1.0 / dt_s,
                                                 output="sos"))
        return sos, np.ascontiguousarray(signal.sosfilt_zi(sos))
    return _designed("lowpass", (cutoff_Hz, dt_s), design)


def _designed(name: str, key: tuple, design) -> tuple:
    """The arrays ``design()`` returns (float64, C-contiguous), kept on disk beside the
    compiled code (:data:`clutchsim._jit.cache_dir`, keyed by clutchsim's sources) under
    ``name``, the exact values of ``key`` and scipy's version: importing ``scipy.signal``,
    which designs them, takes ~0.7 s, more than a hundred launches, and a later process
    loads the same bits in ~1 ms.  Without a cache directory, or where it cannot be read
    or written, they are designed again."""
    import scipy
    tag = hashlib.blake2b(" ".join(float(v).hex() for v in key).encode(),
                          digest_size=8).hexdigest()
    path = Path(cache_dir) / "filters" / f"{name}-scipy{scipy.__version__}-{tag}.npz" \
        if cache_dir else None
    if path is not None:
        try:
            with np.load(path, allow_pickle=False) as f:
                return tuple(np.ascontiguousarray(f[f"a{i}"], dtype=np.float64)
                             for i in range(len(f.files)))
        except (OSError, ValueError, KeyError):
            pass
    arrays = tuple(np.ascontiguousarray(a, dtype=np.float64) for a in design())

    def write(tmp):
        with open(tmp, "wb") as fh:
            np.savez(fh, **{f"a{i}": a for i, a in enumerate(arrays)})
    if path is not None:
        try:
            atomic_write(path, write)
        except OSError:
            pass
    return arrays


def weighted_acceleration_mps2(t_s, a_mps2, dt_s: float = FILTER_DT_S):
    """The acceleration ``a_mps2`` weighted with W_d (ISO 2631-1, x-axis seated) on the
    times ``t_s`` [m/s²].

    The signal is interpolated onto a uniform grid of step ``dt_s``, filtered (the
    second-order sections of W_d by :func:`wd_analog_zpk` and the bilinear transform, as
    ``scipy.signal.sosfilt`` runs them), starting from the filter's steady state for the
    constant acceleration ``a[0]`` (the acceleration is taken as constant before
    ``t_s[0]``: a vehicle cruising at constant acceleration has zero weighted
    acceleration), and interpolated back.
    """
    t_all = np.asarray(t_s, dtype=float)
    if t_all.size < 2 or t_all[-1] <= t_all[0]:
        return np.zeros(t_all.shape)
    t, a = _arrays(t_all, a_mps2)
    sos, zi = _wd_sos(filter_step_s(t, dt_s))
    return _k.weighted(t, a, float(dt_s), FILTER_MAX_SAMPLES, sos, zi)


def rms(t_s, x) -> float:
    """r.m.s. over the run, ``sqrt(1/T ∫ x² dt)`` with T the span of ``t_s`` [unit of x]
    (of the weighted acceleration: ``aw_rms_mps2``, the basic evaluation method of ISO
    2631-1:1997 clause 6)."""
    t, x = _arrays(t_s, x)
    return float(_k.rms(t, x))


def vdv_mps175(t_s, aw_mps2) -> float:
    """Vibration dose value ``(∫ a_w⁴ dt)^(1/4)`` over the run [m/s^1.75] (the fourth
    power vibration dose method of ISO 2631-1:1997 clause 6)."""
    t, aw = _arrays(t_s, aw_mps2)
    return float(_k.vdv(t, aw))


def jerk_mps3(t_s, a_mps2, cutoff_Hz: float = JERK_CUTOFF_HZ, dt_s: float = FILTER_DT_S):
    """``(tu_s, jerk)``: the time derivative of the low-passed acceleration on the
    uniform grid ``tu_s`` [m/s³].

    The acceleration is interpolated onto the uniform grid, filtered forward and
    backward (as ``scipy.signal.sosfiltfilt``: zero phase, so the jerk peak is not
    delayed) with a 2nd-order Butterworth low-pass of corner ``cutoff_Hz`` (the
    forward-backward pass squares its magnitude: -6 dB at the corner, 4th-order
    roll-off), and differentiated by central differences (as ``numpy.gradient``).
    """
    t, a = _arrays(t_s, a_mps2)
    sos, zi = _lowpass_sos(float(cutoff_Hz), filter_step_s(t, dt_s))
    return _k.jerk(t, a, float(dt_s), FILTER_MAX_SAMPLES, sos, zi)


def engagement_start_s(t_s, torque_Nm, threshold_Nm: float | None = None) -> float | None:
    """First time the transmitted clutch torque magnitude exceeds ``threshold_Nm``
    [s], interpolated linearly between samples; ``None`` if it never does.

    Default threshold: :data:`ENGAGE_THRESHOLD_REL` (2 %) of the largest torque
    magnitude in the run, so the metric means the same for a 200 N·m car clutch and a
    3 kN·m truck clutch and lies above an open clutch's drag (about 1 N·m, under 1 % of
    a car clutch's torque).  A clutch already above it at the first sample engaged at
    ``t_s[0]``.
    """
    t, tq = _arrays(t_s, torque_Nm)
    thr = math.nan if threshold_Nm is None else float(threshold_Nm)
    return _none(_k.engagement_start(t, tq, thr, ENGAGE_THRESHOLD_REL))


def lockup_time_s(t_s, slip_radps, engaged, locked=None, event_times_s=None,
                  lock_slip_radps: float = 1.0) -> float | None:
    """Lock-up time [s]: when the clutch speeds first become equal for good; ``None``
    if the clutch does not end the run locked.

    * ``locked`` (a switching model's flag, 1 when stuck) given and set during the run:
      the first time the flag is set (``t_s[0]`` for a clutch locked throughout).  The
      output grid holds a sample at each located event, so that is the located stick
      event; a located event in ``event_times_s`` inside the sample interval that set
      the flag is taken directly.
    * otherwise (a smooth model): the last sample where the ``engaged`` clutch slips at
      ``lock_slip_radps`` or more is found; lock-up is the first zero crossing of the
      slip after it, interpolated linearly between the two samples around it (or the
      located event in that interval).  A slip that decays without crossing zero gives
      the time it falls through ``lock_slip_radps``, interpolated the same way.

    Never snapped to the output grid.
    """
    t, w, eng = _arrays(t_s, slip_radps, np.asarray(engaged, dtype=float))
    lk = _arrays(t, locked)[1] if locked is not None else np.empty(0)
    ev = np.ascontiguousarray(event_times_s if event_times_s is not None else (), dtype=float)
    return _none(_k.lockup_time(t, w, eng, lk, ev.ravel(), float(lock_slip_radps)))


def lockup_shock_mps2(t_s, a_mps2, t_lock_s: float | None,
                      window_s: float = SHOCK_WINDOW_S) -> float | None:
    """The shock the lock-up gives the vehicle [m/s²]: the largest deviation ``|a(t) −
    a_ref|`` of the acceleration for ``t`` in ``[t_lock, t_lock + window_s]`` (clipped to
    the run; the samples of the linear interpolant and the window's ends), ``a_ref`` its
    mean over the :data:`SHOCK_REF_S` (20 ms) before lock-up; ``None`` without lock-up.

    At lock-up the clutch torque jumps from the friction torque to the torque that holds
    the speeds together, and the driveline's first (shuffle) mode, 2-10 Hz, swings the
    vehicle's acceleration away from its level during the slip (the "lurch" of Dolcini,
    Canudas de Wit and Béchart, docs/launch-quality.md).  The default 200 ms spans the
    first half period of that swing down to 2.5 Hz.  A step of height h gives |h|.  At
    the lock-up sample the level takes the value before the event, the window after it
    the value after it (the grid holds both).
    """
    if t_lock_s is None:
        return None
    t, a = _arrays(t_s, a_mps2)
    return _none(_k.lockup_shock(t, a, float(t_lock_s), float(window_s)))


def lining_area_mm2(r_inner_m: float, r_outer_m: float, faces: int) -> float:
    """Friction area of the linings ``faces·π·(r_o² − r_i²)`` [mm²]."""
    if not 0 < r_inner_m < r_outer_m:
        raise ValueError(f"lining radii r_inner = {r_inner_m!r} m, r_outer = {r_outer_m!r} "
                         "m: need 0 < r_inner < r_outer")
    if int(faces) != faces or faces < 1:
        raise ValueError(f"faces = {faces!r}: must be an integer >= 1")
    return float(faces * math.pi * (r_outer_m ** 2 - r_inner_m ** 2) * 1e6)


def friction_densities(t_s, power_W, area_mm2: float | None) -> tuple:
    """``(energy [J/mm²], peak power [W/mm²])`` per lining area: ``∫|P| dt / A`` and
    ``max |P| / A`` with ``P`` the friction power ``T·ω_slip`` [W]; ``(None, None)``
    without an area."""
    if area_mm2 is None:
        return None, None
    t, p = _arrays(t_s, np.abs(np.asarray(power_W, dtype=float)))
    if t.size < 2:
        return None, None
    return float(_k.trapezoid(p, t)) / area_mm2, float(np.max(p)) / area_mm2


def engine_dip_flare_rpm(t_s, omega_radps, t_start_s: float | None,
                         t_end_s: float | None) -> tuple:
    """``(dip, flare)`` of the engine speed during engagement [rpm].

    The engagement window is ``[t_start_s, t_end_s]`` (engagement start to lock-up;
    to the end of the run without lock-up).  ``dip = n(t_start) − min n`` over the
    window: how far the clutch pulls the engine below its speed at engagement start (for
    a launch from rest about idle; for a shift the speed when the oncoming clutch starts
    to carry torque), >= 0.  ``flare = max n − n(t_start)`` over the
    window: how far the engine runs up above its speed at engagement start before the
    clutch catches it (>= 0).  ``(None, None)`` without an engagement start.
    """
    if t_start_s is None:
        return None, None
    t, w = _arrays(t_s, omega_radps)
    dip, flare = _k.dip_flare(t, w, float(t_start_s),
                              math.nan if t_end_s is None else float(t_end_s))
    return float(dip), float(flare)
