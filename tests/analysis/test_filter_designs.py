"""The launch metrics' filter designs are kept on disk (``launch_quality._designed``): a
later process gets the same bits without importing ``scipy.signal`` (~0.7 s, the largest
part of importing clutchsim)."""

import subprocess
import sys
import textwrap

import numpy as np
import pytest
from scipy import signal

from clutchsim.analysis import launch_quality as lq


def _scipy_wd(dt):
    z, p, k = lq.wd_analog_zpk()
    sos = signal.zpk2sos(*signal.bilinear_zpk(z, p, k, 1.0 / dt))
    return sos, signal.sosfilt_zi(sos)


def _scipy_lowpass(fc, dt):
    sos = signal.butter(2, fc, btype="low", fs=1.0 / dt, output="sos")
    return sos, signal.sosfilt_zi(sos)


@pytest.mark.parametrize("dt", [lq.FILTER_DT_S, 1e-3, 2.5e-4])
def test_the_designs_are_scipys_to_the_bit(dt):
    for got, want in ((lq._wd_sos.__wrapped__(dt), _scipy_wd(dt)),
                      (lq._lowpass_sos.__wrapped__(lq.JERK_CUTOFF_HZ, dt),
                       _scipy_lowpass(lq.JERK_CUTOFF_HZ, dt))):
        for g, w in zip(got, want, strict=True):
            assert g.dtype == np.float64 and g.flags.c_contiguous
            assert np.array_equal(g, w)


_CHILD = textwrap.dedent("""
    import sys
    from clutchsim.analysis import launch_quality as lq
    sos, zi = lq._wd_sos(lq.FILTER_DT_S)
    lp, lpzi = lq._lowpass_sos(lq.JERK_CUTOFF_HZ, lq.FILTER_DT_S)
    print("scipy.signal" in sys.modules, sos.tobytes().hex(), lp.tobytes().hex())
""")


def test_a_later_process_loads_the_designs_without_scipy_signal(tmp_path):
    env = {"NUMBA_CACHE_DIR": str(tmp_path), "PATH": "/usr/bin:/bin"}

    def child():
        out = subprocess.run([sys.executable, "-c", _CHILD], env=env, capture_output=True,
                             text=True, check=True).stdout.split()
        return out[0] == "True", out[1:]
    first_imported, first = child()
    later_imported, later = child()
    assert first_imported and not later_imported
    assert later == first
    assert later[0] == _scipy_wd(lq.FILTER_DT_S)[0].tobytes().hex()


def test_without_a_usable_cache_directory_it_designs_them(monkeypatch, tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("not a directory")
    monkeypatch.setattr(lq, "cache_dir", str(blocker))      # filters/ cannot be made in it
    got = lq._designed("wd", (1e-3,), lambda: _scipy_wd(1e-3))
    assert np.array_equal(got[0], _scipy_wd(1e-3)[0])
    monkeypatch.setattr(lq, "cache_dir", "")                # no cache directory at all
    got = lq._designed("wd", (1e-3,), lambda: _scipy_wd(1e-3))
    assert np.array_equal(got[1], _scipy_wd(1e-3)[1])
