"""The compiled launch-metrics kernel against the numpy/scipy formulas it replaced.

``_reference`` below is the numpy/scipy arithmetic of the launch metrics before they were
compiled (``scipy.signal.sosfilt``/``sosfiltfilt``, ``np.interp``, ``np.trapezoid``,
``np.gradient``, ``np.fft``), kept here as the oracle: every metric of every run must agree
to 1e-12 relative (the judder amplitude's band power is a direct DFT in the kernel, rounded
differently from numpy's FFT: 1e-15 to 1e-13 relative, and for a torque without band
content both are round-off, compared to 1e-12 of the torque).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from _dl_paths import EXAMPLES
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import signal

from clutchsim import run_scenario
from clutchsim._jit import jit
from clutchsim.analysis import _kernels as _k
from clutchsim.analysis import launch_quality as lq
from clutchsim.core import Event, Events

LAUNCH = EXAMPLES / "launch.toml"
F = "coupling[0].friction.overrides."
#: 3 models x 4 variants: a stall (steep grade), a clutch that never locks, a heavy launch
#: that stalls after lock-up; coulomb-naive ends its runs by chatter detection
VARIANTS = {"default": [], "stall": ["vehicle.grade=12", "scenario.t_end=1.5"],
            "weak": ['inputs.clutch_command="ramp(0.5, 1.2, 0.15)"', "scenario.t_end=2.0"],
            "heavy": ["vehicle.mass=1500", "vehicle.grade=5", "scenario.t_end=2.0"]}
MODELS = ["mykhailevych2020", "coulomb-robust", "coulomb-naive"]


def _grid(t, x, last=True):
    mask = np.ones(t.size, dtype=bool)
    if last:
        mask[:-1] = t[1:] > t[:-1]
    else:
        mask[1:] = t[1:] > t[:-1]
    return t[mask], x[mask]


def _uniform(t, x):
    t, x = _grid(t, x)
    dt = max(lq.FILTER_DT_S, (t[-1] - t[0]) / lq.FILTER_MAX_SAMPLES)
    tu = t[0] + dt * np.arange(math.floor((t[-1] - t[0]) / dt + 1e-9) + 1)
    return tu, np.interp(tu, t, x)


def _window_mean(t, x, lo, hi):
    tw = np.concatenate([[lo], t[(t > lo) & (t < hi)], [hi]])
    return float(np.trapezoid(np.interp(tw, t, x), tw)) / (hi - lo)


def _reference(res, clutch="clutch", area=None):
    """The metrics by the numpy/scipy formulas (None where there is none)."""
    t, a = res.t, res["a_vehicle"]
    m = {}
    tu, au = _uniform(t, a)
    sos = signal.zpk2sos(*signal.bilinear_zpk(*lq.wd_analog_zpk(), 1.0 / (tu[1] - tu[0])))
    aw = np.interp(t, tu, signal.sosfilt(sos, au, zi=signal.sosfilt_zi(sos) * au[0])[0])
    m["a_weighted"] = aw
    m["vdv_mps175"] = float(np.trapezoid(aw ** 2 * aw ** 2, t)) ** 0.25
    m["aw_rms_mps2"] = math.sqrt(float(np.trapezoid(aw ** 2, t)) / (t[-1] - t[0]))
    dt = tu[1] - tu[0]
    lp = signal.butter(2, lq.JERK_CUTOFF_HZ, btype="low", fs=1.0 / dt, output="sos")
    jerk = np.gradient(signal.sosfiltfilt(lp, au), dt)
    m["jerk_peak_mps3"] = float(np.max(np.abs(jerk)))
    m["jerk_rms_mps3"] = math.sqrt(float(np.trapezoid(jerk ** 2, tu)) / (tu[-1] - tu[0]))
    tg, tq = _grid(t, np.abs(res[f"T_friction_{clutch}"]))
    thr = lq.ENGAGE_THRESHOLD_REL * tq.max()
    i = int(np.flatnonzero(tq > thr)[0])
    t_eng = m["engagement_start_s"] = float(
        tg[i - 1] + (tg[i] - tg[i - 1]) * (thr - tq[i - 1]) / (tq[i] - tq[i - 1]))
    t_lock = m["lockup_time_s"] = res_lockup(res, clutch) if _held(res, clutch) else None
    if t_lock is not None:
        ta, al = _grid(t, a)
        tb, ab = _grid(t, a, last=False)
        lo, hi = max(t_lock - lq.SHOCK_REF_S, t[0]), min(t_lock + lq.SHOCK_WINDOW_S, t[-1])
        ref = _window_mean(tb, ab, lo, t_lock)
        tw = np.concatenate([[t_lock], ta[(ta > t_lock) & (ta < hi)], [hi]])
        m["lockup_shock_mps2"] = float(np.max(np.abs(np.interp(tw, ta, al) - ref)))
    p = np.abs(res[f"P_{clutch}"])
    m["slip_energy_J"] = float(np.trapezoid(p, t))
    if area is not None:
        m["friction_energy_density_J_mm2"] = m["slip_energy_J"] / area
        m["friction_power_density_peak_W_mm2"] = float(np.max(p)) / area
    tg, n = _grid(t, res["omega_engine"] * 30.0 / math.pi)
    hi = tg[-1] if t_lock is None else min(t_lock, tg[-1])
    tw = np.concatenate([[t_eng], tg[(tg > t_eng) & (tg < hi)], [hi]])
    nw = np.interp(tw, tg, n)
    m["engine_dip_rpm"], m["engine_flare_rpm"] = float(nw[0] - nw.min()), float(nw.max() - nw[0])
    m["engine_speed_min_rpm"] = float(np.min(res["omega_engine"]) * 30 / math.pi)
    m["engine_speed_max_rpm"] = float(np.max(res["omega_engine"]) * 30 / math.pi)
    m["judder_amplitude_Nm"] = _judder(res, clutch)
    return m


def res_lockup(res, clutch):
    """lockup_time_s by the old numpy formulas (the locked flag's rise, else the last
    slipping sample's zero crossing)."""
    t_all = res.t
    cap = res[f"capacity_{clutch}"]
    t, w = _grid(t_all, res[f"w_slip_{clutch}"])
    eng = _grid(t_all, cap > 0.5 * cap.max())[1].astype(bool)
    ev = res.events.times(clutch)
    if f"{clutch}.locked" in res.signals:
        lk = _grid(t_all, res[f"{clutch}.locked"])[1] > 0.5
        rise = np.flatnonzero(lk[1:] & ~lk[:-1]) + 1
        if rise.size:
            i = int(rise[0])
            inside = ev[(ev > t[i - 1]) & (ev <= t[i])]
            return float(inside[-1]) if inside.size else float(t[i])
    a = np.abs(w)
    if not eng[-1] or a[-1] >= 1.0:
        return None
    start = int(np.flatnonzero(eng & (a >= 1.0))[-1])
    s = np.sign(w[start:])
    j = start + int(np.flatnonzero(s[1:] != s[0])[0])
    tz = float(t[j] + (t[j + 1] - t[j]) * w[j] / (w[j] - w[j + 1]))
    k = int(np.searchsorted(t, tz))
    inside = ev[(ev > t[max(k - 1, 0)]) & (ev <= t[min(k, t.size - 1)])]
    return float(inside[-1]) if inside.size else tz


def _held(res, clutch, lock_slip=1.0, hold=0.05):
    """The clutch held: its locked flag set after the start, or its slip below
    ``lock_slip`` for ``hold`` seconds on end while engaged (lock-up exists only then)."""
    t = res.t
    if f"{clutch}.locked" in res.signals and np.any((res[f"{clutch}.locked"] > 0.5)
                                                     & (t > t[0])):
        return True
    cap, w = res[f"capacity_{clutch}"], np.abs(res[f"w_slip_{clutch}"])
    start = None
    for i in range(t.size):
        if cap[i] > 0.5 * cap.max() and w[i] < lock_slip:
            start = i if start is None else start
            if t[i] - t[start] >= hold:
                return True
        else:
            start = None
    return False


def _judder(res, clutch):
    cap, w = res[f"capacity_{clutch}"], np.abs(res[f"w_slip_{clutch}"])
    slipping = np.flatnonzero((cap > 0.05 * cap.max()) & (w >= 1.0))
    t0, t1 = float(res.t[slipping[0]]), float(res.t[slipping[-1]])
    if t1 - t0 < 0.5:
        return None
    n = max(math.ceil((t1 - t0) * 20.0 * 30.0), 8)
    t = np.linspace(t0, t1, n)
    x = np.interp(t, res.t, res[f"T_{clutch}"])
    tc = t - t.mean()
    x = x - x.mean() - tc * (float(tc @ x) / float(tc @ tc))
    spec = np.fft.rfft(x)
    f = np.fft.rfftfreq(n, d=(t[1] - t[0]))
    spec[(f < 2.0) | (f > 30.0)] = 0.0
    xb = np.fft.irfft(spec, n)
    return float(math.sqrt(2.0) * np.sqrt(np.mean(xb * xb)))


@pytest.mark.parametrize("model", MODELS)
def test_every_metric_matches_the_numpy_formulas(model):
    area = lq.lining_area_mm2(0.080, 0.115, 2)
    outcomes = set()
    for overrides in VARIANTS.values():
        lr = run_scenario(LAUNCH, model, overrides=overrides)
        res, m = lr.result, lr.metrics
        outcomes.add(m["outcome"])
        ref = _reference(res, area=area)
        np.testing.assert_allclose(res["a_weighted"], ref.pop("a_weighted"), rtol=0,
                                   atol=1e-12 * float(np.max(np.abs(res["a_weighted"]))))
        for key, want in ref.items():
            got = m[key]
            if want is None:
                assert got is None, key
                continue
            # the judder amplitude of a torque without band content is round-off (1e-14
            # N·m), rounded differently by the DFT and the FFT
            floor = 1e-12 * float(np.max(np.abs(res["T_clutch"]))) \
                if key == "judder_amplitude_Nm" else 1e-300
            assert got == pytest.approx(want, rel=1e-12, abs=floor), (key, overrides)
    # the variants reach the run ends the comparison is meant to cover
    assert "stalled" in outcomes
    assert ("chatter" in outcomes) == (model == "coulomb-naive")


def test_the_compiled_primitives_are_numpy_and_scipy_to_the_last_bit():
    rng = np.random.default_rng(7)
    for n in (1, 7, 8, 9, 127, 128, 129, 300, 2083, 9000):
        x = rng.standard_normal(n) * np.exp(3 * rng.standard_normal(n))
        assert _k.pairwise_sum(x, 0, n) == np.sum(x)
        tt = np.cumsum(rng.random(n))
        assert _k.trapezoid(x, tt) == np.trapezoid(x, tt)
    # interpolation on a grid with repeated times (a sample before and after each event)
    xp = np.sort(np.concatenate([np.linspace(0, 1, 40), [0.25, 0.5, 0.5, 1.0]]))
    fp = rng.standard_normal(xp.size)
    xq = np.concatenate([[-1.0], np.linspace(-0.1, 1.1, 500), xp, [2.0]])
    xq.sort()
    assert np.array_equal(_k.interp(xq, xp, fp), np.interp(xq, xp, fp))
    # the W_d sections and the jerk low-pass as difference equations
    sos, zi = lq._wd_sos(5e-4)
    u = rng.standard_normal(3000)
    assert np.array_equal(_k.sosfilt(sos, zi, u[0], u),
                          signal.sosfilt(sos, u, zi=zi * u[0])[0])
    lp, lzi = lq._lowpass_sos(10.0, 5e-4)
    np.testing.assert_allclose(_k.filtfilt(lp, lzi, u), signal.sosfiltfilt(lp, u),
                               rtol=0, atol=1e-13)
    # both in one loop (the launch kernel's path): the bits of each alone
    for m in (10, 11, 3000):
        wd, lo = _k._wd_and_lowpass(sos, zi, lp, lzi, u[:m])
        assert np.array_equal(wd, _k.sosfilt(sos, zi, u[0], u[:m]))
        assert np.array_equal(lo, _k.filtfilt(lp, lzi, u[:m]))


_FLOATS = st.floats(allow_nan=True, allow_infinity=True, width=64)


@jit
def _numba_reductions(x, v):
    """What the kernel called before its reductions were written out: numba's own."""
    return np.max(x), np.min(x), np.max(np.abs(x - v))


@settings(max_examples=300, deadline=None)
@given(st.lists(_FLOATS, min_size=1, max_size=40), _FLOATS)
def test_the_kernels_reductions_are_numpys(xs, v):
    """The kernel's own reductions (written out: numba compiled one library each for
    ``np.max``, ``np.min``, ``np.abs``, ``np.argmax`` and ``np.searchsorted``, ~3.5 s of
    the kernel's compilation) give numpy's value, NaN first, and numba's own bits, the
    sign of a zero too (numba keeps the first of equal values; numpy's SIMD reductions may
    return either zero of [0.0, -0.0]: hypothesis found it)."""
    x = np.array(xs)
    with np.errstate(invalid="ignore"):
        mine = (_k.extreme(x, True), _k.extreme(x, False), _k.amax_abs_dev(x, v))
        for got, want, numba_s in zip(mine, (np.max(x), np.min(x), np.max(np.abs(x - v))),
                                      _numba_reductions(x, v)):
            assert got == want or (math.isnan(got) and math.isnan(want)), (xs, v)
            assert (got == numba_s and math.copysign(1, got) == math.copysign(1, numba_s)
                    ) or (math.isnan(got) and math.isnan(numba_s)), (xs, v)
    a = np.sort(x)                  # numpy sorts NaN last, as the search assumes
    assert _k._searchsorted(a, v) == np.searchsorted(a, v), (xs, v)
    assert np.array_equal(_k.fill(len(xs), v), np.full(len(xs), v), equal_nan=True)


def test_events_are_a_lazy_sequence_equal_to_their_tuple():
    ev = Events([0.1, 0.2, 0.3], [0, 1, 0], [0, 1, 0], ["c: slip", "e: stall"], ["c", "e"],
                {0: "recorded", 1: "reset"})
    want = (Event(0.1, "c: slip", "recorded", "c"), Event(0.2, "e: stall", "reset", "e"),
            Event(0.3, "c: slip", "recorded", "c"))
    assert ev == want and len(ev) == 3 and ev[1] == want[1] and list(ev) == list(want)
    assert ev.times("c").tolist() == [0.1, 0.3] and ev.times("x").size == 0
    assert Events.of(want) == ev and Events.of(want).times("e").tolist() == [0.2]
    with pytest.raises(ValueError, match="one length"):
        Events([0.1], [0, 1], [0])
