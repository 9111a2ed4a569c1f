"""The hand-written plain-Python launch model of benchmarks/launch_speed.py is the same model.

``benchmarks/`` is a directory of scripts, not a package: the module is loaded from its
file, so the test suite does not depend on ``benchmarks`` being importable (or on the
working directory).  Without the directory (an installed package) the tests are skipped.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest

_PATH = Path(__file__).resolve().parents[2] / "benchmarks" / "_launch_plain.py"
_NAME = "_clutchsim_bench_launch_plain"


@pytest.fixture(scope="module")
def plain():
    if not _PATH.is_file():
        pytest.skip(f"{_PATH} not present (benchmarks are not installed)")
    if _NAME not in sys.modules:
        spec = importlib.util.spec_from_file_location(_NAME, _PATH)
        mod = importlib.util.module_from_spec(spec)
        sys.modules[_NAME] = mod        # dataclasses look the module up while it loads
        spec.loader.exec_module(mod)
    return sys.modules[_NAME]


def test_plain_rhs_is_the_plant_rhs(plain):
    from clutchsim.scenario import load_scenario
    assert plain.rhs_mismatch(load_scenario(None), n_states=100) < 1e-12


@pytest.mark.slow
def test_plain_launch_matches_clutchsim(plain):
    rep = plain.check("LSODA", rtol=1e-8, atol=1e-8)
    assert rep["plain_status"] == "completed"
    assert rep["max_abs_speed_diff_rpm"] <= plain.SPEED_TOL_RPM
    assert rep["lockup_diff_s"] is not None and rep["lockup_diff_s"] <= plain.LOCKUP_TOL_S
    assert rep["first_slip_zero_diff_s"] < 1e-6
    assert rep["ok"]
