"""The launch metrics and warnings of a driveline run (a :class:`~clutchsim.core.Result`).

This module reads results only; running a scenario is :mod:`clutchsim.scenario.run`
(the dependency runs one way: scenario -> analysis -> network -> core)."""

from __future__ import annotations

import contextlib
import math
from collections.abc import Callable, Iterator, Mapping
from dataclasses import replace
from types import MappingProxyType
from typing import NamedTuple

import numba
import numpy as np

from ..core import Outcome, Result
from ..core.compile_notice import compile_notice
from . import _kernels as _k
from . import launch_quality as lq
from .judder_band import JUDDER_BAND_HZ, JUDDER_SLIP_RAD_S

__all__ = ["DT_OUT_MAX_S", "ENERGY_STATES", "LAUNCH_DRIVES", "LOCK_HOLD", "LOCK_SLIP",
           "STEP_RATE_LIMIT", "RunSummary", "analyse_run", "energy_balance", "grid_problem",
           "is_launch", "kernel_compiled_elsewhere", "launch_metrics", "launch_warnings", "metrics_of",
           "shaft_torque_metrics", "warnings_of", "with_weighted_acceleration"]

#: energy-account states of a launch driveline (integrals) [J]: the work put in, then the
#: losses and stores it goes to (:func:`energy_balance`)
ENERGY_STATES = ("W_in", "W_friction", "W_damping", "W_road", "E_grade", "W_sync")

#: steps per simulated second above which a run is warned about [1/s].  The shipped
#: scenarios take 7 to 1,900 (measured: default launch 365-530, ten launches 440-610, tip-out
#: 1,850); a model-(6) clutch ringing after lock-up takes 17,000-37,000.
STEP_RATE_LIMIT = 5000.0
#: ... but never below this many steps in all (a very short run may be dense) [-]
STEP_COUNT_FLOOR = 10_000
#: slip below which an engaged clutch counts as held [rad/s], and for how long [s] at least
LOCK_SLIP = 1.0
LOCK_HOLD = 0.05


#: coarsest output grid the launch metrics are computed on [s]: they read the sampled
#: signals (peaks, times, integrals of the friction power), and on this grid or a finer one
#: they agree with those of a 1 ms grid within 1 % (tests/driveline/test_metrics_grid.py;
#: docs/launch-quality.md); 0 (every step) is fine as well
DT_OUT_MAX_S = 0.01


def grid_problem(dt_out_s: float) -> str:
    """Why the launch metrics cannot be computed on an output grid of ``dt_out_s``
    seconds ("" when they can): a grid coarser than :data:`DT_OUT_MAX_S` misses the
    engagement (a 10 s grid on a 4 s launch gives a slip energy of 6e-11 J instead of
    2.5 kJ)."""
    if dt_out_s > DT_OUT_MAX_S:
        return (f"solver.dt_out = {dt_out_s:g} s is coarser than the {DT_OUT_MAX_S:g} s the "
                "launch metrics need (they are read from the output grid: a coarser one "
                "misses the engagement's peaks and energy, docs/launch-quality.md); set "
                f"solver.dt_out <= {DT_OUT_MAX_S:g} s, or 0 for every step")
    return ""


_EMPTY = np.empty(0)
_EMPTY.flags.writeable = False


def kernel_signature() -> tuple:
    """The argument types of the launch kernel's one specialisation: eleven contiguous
    columns (the run's times, its signals, the clutch's events), the four filter arrays,
    the constants."""
    a1 = numba.types.Array(numba.float64, 1, "C")
    c2 = numba.types.Array(numba.float64, 2, "C")
    f, i = numba.float64, numba.int64
    return (a1,) * 11 + (c2,) * 4 + (f, i, f, f, f, f, f, f, f, f)


def energy_balance_signature() -> tuple:
    """The argument types :func:`energy_balance` calls the compiled balance with: the work
    put in, then the losses, the kinetic and the spring energies as contiguous arrays."""
    a1 = numba.types.Array(numba.float64, 1, "C")
    return (numba.float64, a1, a1, a1)


def _kernel_entry():
    """The compiled :func:`~clutchsim.analysis._kernels.launch_kernel` for contiguous
    arrays, called directly: one specialisation, and no typing of its 25 arguments per call
    (so :class:`_Run` checks the arrays' dtype and shape itself).  A result's columns are
    strided views of the integrator's output blocks; they are copied (about 10 µs a run):
    with strided arguments a dozen of the kernel's helpers compiled twice, once for them
    and once for the kernel's own arrays, and a sweep's batch, which passes contiguous
    copies too, shares this specialisation instead of compiling its own."""
    global _ENTRY
    if _ENTRY is None:
        sig = kernel_signature()
        if _WAIT is not None:
            _WAIT()
        with compile_notice(("launch_kernel", sig), "launch metrics",
                            subject="the launch-metrics kernel"):
            _k.launch_kernel.compile(sig)
        _ENTRY = _k.launch_kernel.overloads[sig].entry_point
    return _ENTRY


_ENTRY = None
_WAIT: Callable[[], None] | None = None


@contextlib.contextmanager
def kernel_compiled_elsewhere(wait: Callable[[], None]) -> Iterator[None]:
    """Within the block, the launch kernel is being compiled into numba's on-disk cache by
    another process (:func:`clutchsim.scenario.warmup.metrics_compiled_beside`): the first
    run analysed here calls ``wait()`` (which returns when that process has ended) and
    then loads the kernel from the cache, instead of compiling it a second time beside
    it.  Runs before that compile and integrate meanwhile."""
    global _WAIT
    previous, _WAIT = _WAIT, wait
    try:
        yield
    finally:
        _WAIT = previous


class _Run:
    """What the launch kernel found in one run: the values ``k`` at the ``_k.K_*`` slots,
    the weighted acceleration ``aw``, the clutch's event times ``ev``."""

    __slots__ = ("aw", "ev", "k")

    def __init__(self, res: Result, clutch: str, lining: tuple | None):
        data, t = res.data, res.t
        if t.dtype != np.float64 or t.ndim != 1:
            raise ValueError(f"result times of dtype {t.dtype} and shape {t.shape}: need "
                             "a 1-D float64 array")

        def col(name):
            x = data.get(name)
            if x is None:
                return _EMPTY
            if x.dtype != np.float64 or x.shape != t.shape:
                raise ValueError(f"signal {name!r} of dtype {x.dtype} and shape {x.shape} "
                                 f"does not match the result's times {t.shape}")
            return np.ascontiguousarray(x)

        temps = [s for s in data if s.startswith("theta_")]
        self.ev = ev = np.ascontiguousarray(res.events.times(clutch), dtype=np.float64)
        dt = lq.filter_step_s(t) if t.size > 1 else lq.FILTER_DT_S
        wd_sos, wd_zi = lq._wd_sos(dt)
        lp_sos, lp_zi = lq._lowpass_sos(lq.JERK_CUTOFF_HZ, dt)
        area = lq.lining_area_mm2(*lining) if lining is not None else math.nan
        lo, hi = JUDDER_BAND_HZ
        self.k, self.aw = _kernel_entry()(
            np.ascontiguousarray(t), col("a_vehicle"), col(f"T_friction_{clutch}"), col(f"w_slip_{clutch}"),
            col(f"capacity_{clutch}"), col(f"{clutch}.locked"), col(f"P_{clutch}"),
            col("omega_engine"), col(f"T_{clutch}"), col(temps[0]) if temps else _EMPTY, ev,
            wd_sos, wd_zi, lp_sos, lp_zi, lq.FILTER_DT_S, lq.FILTER_MAX_SAMPLES, LOCK_SLIP,
            LOCK_HOLD, lq.SHOCK_WINDOW_S, lq.ENGAGE_THRESHOLD_REL, area, lo, hi, JUDDER_SLIP_RAD_S)


def with_weighted_acceleration(res: Result) -> Result:
    """``res`` with the signal ``a_weighted`` [m/s²]: ``a_vehicle`` weighted with ISO
    2631-1 W_d (:func:`clutchsim.analysis.launch_quality.weighted_acceleration_mps2`);
    ``res`` itself when it has no ``a_vehicle``."""
    if "a_vehicle" not in res.signals or "a_weighted" in res.signals:
        return res
    aw = lq.weighted_acceleration_mps2(res.t, res["a_vehicle"])
    aw.flags.writeable = False
    return replace(res, data=MappingProxyType({**res.data, "a_weighted": aw}),
                   units=MappingProxyType({**res.units, "a_weighted": "m/s²"}))


def energy_balance(res: Result) -> dict:
    """Energy account of a run [J] and ``energy_balance_rel``.

    ``residual = W_in - ΔE_kinetic - ΔE_spring - W_friction - W_damping - W_road - E_grade
    - W_sync``; ``energy_balance_rel = |residual| / max(|W_in|, E_kinetic(0), max E_kinetic)``.
    """
    out = {k: float(res[k][-1]) for k in ENERGY_STATES}
    # (the types of energy_balance_signature: a child compiles it from an empty cache)
    d_ke, d_pe, resid, scale = _k.energy_balance(
        out["W_in"], np.array([out[k] for k in ENERGY_STATES[1:]]),
        np.ascontiguousarray(res["E_kinetic"]), np.ascontiguousarray(res["E_spring"]))
    out.update(delta_E_kinetic=d_ke, delta_E_spring=d_pe, residual=resid,
               energy_balance_rel=abs(resid) / scale)
    return out


class RunSummary(NamedTuple):
    """What a run's launch metrics and warnings are computed from (:func:`metrics_of`,
    :func:`warnings_of`): the run's end and statistics, and the launch kernel's values
    ``k`` at the ``_kernels.K_*`` slots.  Built from a :class:`~clutchsim.core.Result` by
    :func:`summary` or, for a sweep's chunk run in one compiled call, from its arrays
    (:mod:`clutchsim.analysis.launch_batch`)."""

    status: str             #: "completed", "stopped" or "failed"
    outcome: Outcome
    message: str
    warnings: tuple         #: the run's warnings so far
    ended_by: str           #: the component whose event ended the run ("" if none did)
    kinds: Mapping          #: component -> kind (the system's metadata)
    n_t: int                #: output rows
    span_s: float           #: last output time minus the first [s]
    has_slip: bool          #: whether the run has the clutch's slip signal
    steps: int
    rhs_evals: int
    events: int
    min_step_s: float
    wall_s: float
    k: np.ndarray
    energy_balance_rel: float

    @classmethod
    def of(cls, end, stats, kinds, n_t: int, span_s: float, has_slip: bool, k,
           energy_balance_rel: float) -> RunSummary:
        """From how the run ended (``end``: its outcome, message, warnings, the event that
        ended it and that event's source, e.g. a :class:`clutchsim.core.simulate.RunEnd`
        or a :class:`~clutchsim.core.Result`), its :class:`~clutchsim.core.Stats` and the
        rest."""
        outcome = Outcome(end.outcome)
        return cls(outcome.status, outcome, end.message, tuple(end.warnings),
                   end.event_source if end.event else "", kinds, n_t, span_s, has_slip,
                   stats.steps, stats.rhs_evals, stats.events, stats.min_step_s,
                   stats.wall_s, k, energy_balance_rel)


def summary(res: Result, clutch: str, run: _Run, *, energy: bool = True) -> RunSummary:
    """The :class:`RunSummary` of ``res`` with the launch kernel's values ``run``
    (``energy``: with its energy balance; else NaN)."""
    return RunSummary.of(res, res.stats, res.metadata.get("kinds", {}), int(res.t.size),
                         float(res.t[-1] - res.t[0]) if res.t.size else 0.0,
                         f"w_slip_{clutch}" in res.signals, run.k,
                         energy_balance(res)["energy_balance_rel"] if energy else math.nan)


def _ringing(k, clutch: str) -> str | None:
    """The warning for a contact whose torque swings, after it first held, further both
    ways than its capacity (half its peak-to-peak above the capacity), else None (``k``:
    the launch kernel's values)."""
    if k[_k.K_RING] != 1.0:
        return None
    t0, amplitude, capacity = (float(k[s]) for s in (_k.K_RING_T0, _k.K_RING_AMP,
                                                     _k.K_RING_CAP))
    n_ev = int(k[_k.K_RING_N_EV])
    first, last = float(k[_k.K_RING_EV_FIRST]), float(k[_k.K_RING_EV_LAST])
    rate = ""
    if n_ev > 2 and last > first:
        hz = 0.5 * (n_ev - 1) / (last - first)
        rate = (f" with {n_ev:,} events of {clutch!r} (~{hz:.0f} Hz if each is a "
                "slip reversal)")
    return (f"contact {clutch!r} rings after lock-up: from t = {t0:.3g} s its torque swings "
            f"±{amplitude:.0f} N·m{rate}, above its capacity {capacity:.0f} N·m, so it keeps "
            f"slipping back and forth instead of holding (largest slip afterwards "
            f"{float(k[_k.K_RING_WMAX]):.3g} rad/s). Cause: a locked contact with too little "
            "damping (model (6): its only damping is k_v) or a friction torque that falls "
            "with slip speed (judder: k_din < 1 with a small omega0). Remedy: raise the "
            "contact damping (k_v), use a friction curve that does not fall steeply "
            "(k_din nearer 1, a larger omega0), add driveline damping, or compare with "
            "coulomb-robust; do not trust this run's torques and lock-up time")


#: component kinds that make a network with a friction clutch a launch: what the launch
#: metrics read (a vehicle: comfort, jerk, lock-up shock; an engine: dip, flare, stall)
LAUNCH_DRIVES = ("vehicle", "engine")


def is_launch(kinds, clutch: str) -> bool:
    """Whether a network is a launch, the rule ``clutchsim run`` and its outputs follow:
    its element ``clutch`` (``[scenario] clutch``) is a friction clutch (kind ``"clutch"``,
    not a brake, a one-way clutch or a lossy gear) and it has a vehicle or an engine
    (:data:`LAUNCH_DRIVES`).  ``kinds``: component name -> kind, as a network plant's
    ``metadata["kinds"]`` (:class:`~clutchsim.core.Result`, :class:`~clutchsim.core.System`)
    gives it.  A launch gets the launch metrics and figure, any other network the summary
    of :func:`clutchsim.analysis.network_summary.network_summary` (docs/outputs.md)."""
    return kinds.get(clutch) == "clutch" and any(k in LAUNCH_DRIVES for k in kinds.values())


def launch_warnings(res: Result, clutch: str = "clutch", *, expect_lockup: bool = True,
                    friction: bool = True, engine_max_radps: float | None = None
                    ) -> list[str]:
    """Reasons not to trust a run that completed, each with its cause and remedy.

    * the clutch never held although ``expect_lockup`` (see
      :func:`clutchsim.scenario.run.expects_lockup`);
    * (``friction``: the element is a friction clutch) its contact rings after lock-up
      with a torque amplitude above its capacity;
    * the step count is far above what the scenarios need: more than
      :data:`STEP_RATE_LIMIT` steps per simulated second (and more than
      :data:`STEP_COUNT_FLOOR` steps);
    * the engine ran faster than ``engine_max_radps`` (the last speed of its full-load
      table, where its fuel is cut) [rad/s];
    * (``expect_lockup``, and the network is a launch: :func:`is_launch`) the run has no
      vehicle (``a_vehicle``) or no engine (``omega_engine``), so the metrics that read
      them are null.

    A failed run gets none (its outcome and message say what went wrong).
    """
    if res.status == "failed" or res.t.size < 2:
        return []
    return warnings_of(summary(res, clutch, _Run(res, clutch, None), energy=False), clutch,
                       expect_lockup=expect_lockup, friction=friction,
                       engine_max_radps=engine_max_radps)


def warnings_of(sm: RunSummary, clutch: str, *, expect_lockup: bool = True,
                friction: bool = True, engine_max_radps: float | None = None) -> list[str]:
    """:func:`launch_warnings` of the run summarised by ``sm``."""
    if sm.status == "failed" or sm.n_t < 2:
        return []
    out = []
    k = sm.k
    span = sm.span_s
    n_max = float(k[_k.K_OMEGA_MAX])
    if engine_max_radps is not None and n_max > engine_max_radps * 30.0 / math.pi:
        out.append(f"the engine overspeeds: it reached {n_max:,.0f} rpm, above the "
                   f"{engine_max_radps * 30.0 / math.pi:,.0f} rpm where its full-load table "
                   "ends and its fuel is cut (the rev limiter): the throttle held it against "
                   "the limiter (an open clutch, too low a gear) or the driveline drove it "
                   "there (a downshift, a steep downhill). Remedy: check the throttle, the "
                   "gear and the grade; a real engine would hunt on its limiter or be "
                   "damaged")
    if expect_lockup:
        missing = [what for what, slot in (("vehicle ([vehicle]: a_vehicle)", _k.K_AW_RMS),
                                            ("engine ([engine]: omega_engine)",
                                             _k.K_OMEGA_MIN))
                   if math.isnan(float(k[slot]))]
        # another network (no vehicle and no engine component, whatever its inertias are
        # called) has no launch metrics to be null
        if missing and is_launch(sm.kinds, clutch):
            out.append(f"this launch has no {' and no '.join(missing)}: the launch metrics "
                       "that read it (vehicle: vdv, aw r.m.s., jerk, lock-up shock; engine: "
                       "dip, flare, engine speeds) are null. Remedy: add the missing table, "
                       "or, if the scenario is not a launch, set [scenario] expect_lockup = "
                       "false")
    if expect_lockup and sm.has_slip and k[_k.K_HELD] != 1.0:
        cap_max = float(k[_k.K_CAP_MAX])
        if not k[_k.K_ENGAGED] > 0:
            cause = ("it never engaged (its capacity stayed below half its largest value "
                     f"{cap_max:.0f} N·m)")
        elif k[_k.K_W_MIN_ENG] >= LOCK_SLIP:
            cause = (f"its slip never fell below {LOCK_SLIP:g} rad/s while engaged (smallest "
                     f"{float(k[_k.K_W_MIN_ENG]):.3g} rad/s): the capacity "
                     f"{cap_max:.0f} N·m is too low for the torque it must carry, "
                     "or the run is too short")
        else:
            cause = (f"its slip came near zero but never stayed below {LOCK_SLIP:g} rad/s for "
                     f"{LOCK_HOLD:g} s (largest slip after engagement "
                     f"{float(k[_k.K_W_MAX_ENG]):.3g} rad/s): stick-slip or judder")
        out.append(f"clutch {clutch!r} never locked up although the scenario expects it: "
                   f"{cause}. Remedy: raise the clamp load or capacity, lengthen t_end, use "
                   "a friction model or parameters that can hold (see the ringing warning if "
                   "there is one), or, if the clutch is meant to slip, set [scenario] "
                   "expect_lockup = false")
    if friction:
        ring = _ringing(k, clutch)
        if ring:
            out.append(ring)
    steps = sm.steps
    if span > 0 and steps > STEP_COUNT_FLOOR and steps / span > STEP_RATE_LIMIT:
        n_ev = sm.events
        out.append(f"the run took {steps:,} steps, {steps / span:,.0f} per simulated second, "
                   f"far above the {STEP_RATE_LIMIT:,.0f}/s that clutchsim's scenarios need "
                   f"(usually 300-2,000/s), with {n_ev:,} events. Cause: something fast was "
                   "excited or keeps switching (an undamped contact mode, stick-slip, "
                   "chattering events); the result may be right but is costly and suspect. "
                   "Remedy: look at the slip speeds and the events; add contact damping or "
                   "choose a smoother friction model or reset policy; if the fast dynamics is "
                   "real, this warning can be ignored")
    return out


def _lockup_time(res: Result, clutch: str) -> float | None:
    """:func:`clutchsim.analysis.launch_quality.lockup_time_s` of ``clutch`` in ``res``:
    engaged = capacity above half its largest value; the clutch's located events."""
    return _value(_Run(res, clutch, None).k, _k.K_LOCKUP)


#: the launch-quality metrics of docs/launch-quality.md and their slots in the kernel's
#: values
_QUALITY = (("engagement_start_s", _k.K_ENGAGE), ("lockup_time_s", _k.K_LOCKUP),
            ("vdv_mps175", _k.K_VDV), ("aw_rms_mps2", _k.K_AW_RMS),
            ("jerk_peak_mps3", _k.K_JERK_PEAK), ("jerk_rms_mps3", _k.K_JERK_RMS),
            ("lockup_shock_mps2", _k.K_SHOCK),
            ("friction_energy_density_J_mm2", _k.K_E_DENS),
            ("friction_power_density_peak_W_mm2", _k.K_P_DENS),
            ("engine_dip_rpm", _k.K_DIP), ("engine_flare_rpm", _k.K_FLARE))


def launch_metrics(res: Result, clutch: str = "clutch", *, lining: tuple | None = None
                   ) -> dict:
    """Per-run metrics: completed, outcome, message, warnings (``res.warnings``: see
    :func:`launch_warnings`), the launch-quality metrics of docs/launch-quality.md
    (engagement_start_s, lockup_time_s, vdv_mps175, aw_rms_mps2, jerk_peak_mps3,
    jerk_rms_mps3, lockup_shock_mps2, friction_energy_density_J_mm2,
    friction_power_density_peak_W_mm2, engine_dip_rpm, engine_flare_rpm; the densities
    need ``lining`` = ``(r_inner [m], r_outer [m], faces [-])``), slip_energy_J,
    peak_heat_node_temp_C (the largest temperature of the run's first thermal node
    ``theta_<node>``: a lumped bulk mass, the pressure plate in the shipped scenarios, not
    the friction surface), peak_surface_temp_C (:func:`analyse_run` with a surface layer;
    else None), engine_speed_min_rpm, engine_speed_max_rpm, engine_stalled,
    energy_balance_rel,
    judder_amplitude_Nm (:func:`clutchsim.analysis.judder_amplitude`), steps, rhs_evals,
    events, min_step_s, wall_s.

    All of them but the energy balance come from one compiled call over the run's arrays
    (:func:`clutchsim.analysis._kernels.launch_kernel`: the formulas of
    :mod:`clutchsim.analysis.launch_quality`); None where a signal is missing or a value
    is not finite."""
    return metrics_of(summary(res, clutch, _Run(res, clutch, lining)), clutch)


def _quality(run_or_res, clutch: str = "clutch", lining: tuple | None = None) -> dict:
    """The launch-quality metrics of docs/launch-quality.md (None where a signal is
    missing or a value is not finite) of a :class:`_Run` or of a result."""
    run = run_or_res if isinstance(run_or_res, _Run) else _Run(run_or_res, clutch, lining)
    return {key: _value(run.k, slot) for key, slot in _QUALITY}


def _value(k, slot: int) -> float | None:
    """The launch kernel's value at ``slot`` of ``k`` (None where it is not finite)."""
    v = float(k[slot])
    return v if math.isfinite(v) else None


def metrics_of(sm: RunSummary, clutch: str) -> dict:
    """:func:`launch_metrics` of the run summarised by ``sm``."""
    m: dict = {"completed": sm.status == "completed", "outcome": str(sm.outcome),
               "message": sm.message, "warnings": list(sm.warnings)}
    if sm.outcome == Outcome.CHATTER and sm.ended_by == clutch:
        m["message"] = ("stopped by chatter detection at clutch lock-up (the slip speed of "
                        f"{clutch!r} reached zero and the switching law re-fired): "
                        + sm.message)
    k = sm.k

    def value(slot):
        return _value(k, slot)
    m.update({key: value(slot) for key, slot in _QUALITY})
    m["slip_energy_J"] = value(_k.K_SLIP_ENERGY)
    m["peak_heat_node_temp_C"] = value(_k.K_THETA_MAX)
    m["peak_surface_temp_C"] = None        # with a surface layer: analyse_run
    m["engine_speed_min_rpm"] = value(_k.K_OMEGA_MIN)
    m["engine_speed_max_rpm"] = value(_k.K_OMEGA_MAX)
    m["engine_stalled"] = (sm.outcome == Outcome.EVENT_FAILED
                           and sm.kinds.get(sm.ended_by, "") == "engine")
    if m["engine_stalled"]:
        m["outcome"] = "stalled"
    m["energy_balance_rel"] = sm.energy_balance_rel
    m["judder_amplitude_Nm"] = value(_k.K_JUDDER)
    m.update(steps=sm.steps, rhs_evals=sm.rhs_evals, events=sm.events,
             min_step_s=sm.min_step_s, wall_s=sm.wall_s)
    return m


def _grid_peak(t: np.ndarray, x: np.ndarray) -> float:
    """The largest value of the sampled signal ``x(t)``, refined by the parabola through the
    largest sample and its neighbours (the vertex, where it lies between them): a peak read
    off the samples alone is low by up to ``(ω·Δt)²/8`` of an oscillation at ω.  The clutch
    dump's driveshaft peak on a 10 ms grid: the largest sample 0.25 % low, the vertex
    0.05 % (against a 0.2 ms grid; tests/network/test_abuse.py)."""
    k = int(np.argmax(x))
    if 0 < k < x.size - 1:
        (ta, tb, tc), (a, b, c) = t[k - 1:k + 2], x[k - 1:k + 2]
        den = (ta - tb) * (ta - tc) * (tb - tc)
        p2 = (tc * (b - a) + tb * (a - c) + ta * (c - b)) / den
        p1 = (tc * tc * (a - b) + tb * tb * (c - a) + ta * ta * (b - c)) / den
        if p2 < 0.0:
            tv = -p1 / (2.0 * p2)
            if ta <= tv <= tc:
                return float(b + p1 * (tv - tb) + p2 * (tv * tv - tb * tb))
    return float(x[k])


def shaft_torque_metrics(res: Result, clutch: str, shaft: str, ratio: float) -> dict:
    """The abuse-case metrics of a shaft (a clutch dump's driveshaft, docs/components.md,
    abuse load cases): ``peak_shaft_torque_Nm``, the largest ``|T_<shaft>|`` of the run
    (:func:`_grid_peak`); ``shaft_capacity_Nm``, the clutch's nominal capacity (the largest
    static capacity ``capacity_<clutch>`` of the run) times ``ratio``, the gears' ratio
    from the clutch's output to the shaft (:meth:`clutchsim.network.network.Assembly.
    static_ratio`): what the clutch can put through the shaft quasi-statically; and
    ``peak_shaft_torque_over_capacity``, their quotient (above 1: the impact overshoots
    what the clutch can hold)."""
    torque = res.data.get(f"T_{shaft}")
    cap = res.data.get(f"capacity_{clutch}")
    out = {"peak_shaft_torque_Nm": None, "shaft_capacity_Nm": None,
           "peak_shaft_torque_over_capacity": None}
    if torque is None or not torque.size:
        return out
    peak = _grid_peak(res.t, np.abs(torque))
    out["peak_shaft_torque_Nm"] = peak
    if cap is not None and cap.size and np.max(cap) > 0.0:
        out["shaft_capacity_Nm"] = capacity = float(np.max(cap)) * abs(ratio)
        out["peak_shaft_torque_over_capacity"] = peak / capacity
    return out


def analyse_run(res: Result, clutch: str = "clutch", *, expect_lockup: bool = True,
                friction: bool = True, lining: tuple | None = None,
                engine_max_radps: float | None = None, surface_node: str | None = None
                ) -> tuple[Result, dict]:
    """``(result, metrics)``: ``res`` with its :func:`launch_warnings` appended and the
    signal ``a_weighted`` (:func:`with_weighted_acceleration`), and its
    :func:`launch_metrics`, from one call of the compiled launch kernel (what
    :func:`clutchsim.scenario.run.run_system` does with every run).  ``surface_node``: the
    thermal node that is the clutch's friction-surface layer (its peak temperature is
    ``peak_surface_temp_C``; :func:`clutchsim.scenario.run.surface_node`)."""
    run = _Run(res, clutch, lining)
    sm = summary(res, clutch, run)
    warnings = tuple(warnings_of(sm, clutch, expect_lockup=expect_lockup, friction=friction,
                                 engine_max_radps=engine_max_radps))
    data, units = res.data, res.units
    if "a_vehicle" in res.signals and "a_weighted" not in res.signals:
        aw = run.aw
        aw.flags.writeable = False
        data = MappingProxyType({**data, "a_weighted": aw})
        units = MappingProxyType({**units, "a_weighted": "m/s²"})
    if warnings or data is not res.data:
        res = replace(res, data=data, units=units, warnings=res.warnings + warnings)
    m = metrics_of(sm._replace(warnings=sm.warnings + warnings), clutch)
    theta = data.get(f"theta_{surface_node}") if surface_node else None
    if theta is not None and theta.size:
        m["peak_surface_temp_C"] = _value(np.array([np.max(theta)]), 0)
    return res, m
