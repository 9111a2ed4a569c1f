"""What a fresh process pays before its first result: lazy imports, no scipy.linalg from
numba's start-up, no objmode block compiled per process (see docs/performance.md)."""

import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

from clutchsim.core._clock import NATIVE, now


def _python(code: str) -> str:
    done = subprocess.run([sys.executable, "-c", textwrap.dedent(code)], check=False,
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    return done.stdout.strip().splitlines()[-1]


def test_import_clutchsim_loads_nothing_heavy_until_a_name_is_used():
    out = _python("""
        import sys
        import clutchsim
        before = [m for m in ("numba", "clutchsim.core", "clutchsim.friction", "pandas")
                  if m in sys.modules]
        clutchsim.run_rig, clutchsim.make_model, clutchsim.SolverOptions
        try:
            clutchsim.no_such_name
        except AttributeError as exc:
            missing = str(exc)
        print(before, "clutchsim.studies.sweeps" in sys.modules, "run_rig" in dir(clutchsim),
              missing)
    """)
    assert out == ("[] False True module 'clutchsim' has no attribute 'no_such_name'")
    import clutchsim
    assert set(clutchsim.__all__) == {*clutchsim._EXPORTS, "__version__"}


def test_a_cached_run_in_a_fresh_process_imports_no_scipy_linalg_pandas_or_matplotlib():
    from clutchsim.friction import make_model
    from clutchsim.rig import run_rig
    run_rig(make_model("lugre"), 1.0, force=0.0, spring=2.0, pull_speed=0.1)  # cache warm
    out = _python("""
        import sys
        from clutchsim.friction import make_model
        from clutchsim.rig import run_rig
        res = run_rig(make_model("lugre"), 1.0, force=0.0, spring=2.0, pull_speed=0.1)
        from numba.np import arraymath
        print(res.status, arraymath._HAVE_BLAS,
              [m for m in ("scipy.linalg", "pandas", "pyarrow", "matplotlib")
               if m in sys.modules])
    """)
    assert out == "completed True []"


def test_numba_linear_algebra_still_checks_and_imports_scipy_when_used():
    out = _python("""
        import sys
        import numba
        import numpy as np
        from clutchsim.core.signals import Constant
        Constant(1.0)(0.0)            # a clutchsim kernel: numba's start-up under the patch
        assert "scipy.linalg" not in sys.modules

        @numba.njit
        def solve(a, b):
            return np.linalg.solve(a, b), np.dot(a, b)

        x, d = solve(np.array([[2.0, 1.0], [1.0, 3.0]]), np.array([3.0, 5.0]))
        print(x.round(12).tolist(), d.tolist(), "scipy.linalg" in sys.modules)
    """)
    assert out == "[0.8, 1.4] [11.0, 18.0] True"


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="the native clock is checked "
                    "where the project runs")
def test_the_compiled_clock_is_native_on_linux_and_keeps_time():
    assert NATIVE
    t0, c0 = now(), time.perf_counter()
    time.sleep(0.2)
    t1, c1 = now(), time.perf_counter()
    assert (t1 - t0) == pytest.approx(c1 - c0, abs=5e-3)
    assert np.isfinite(t1) and t1 > t0
