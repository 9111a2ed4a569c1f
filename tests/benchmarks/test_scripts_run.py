"""Every benchmark script still runs, at its smallest size, and prints its JSON line.

The scripts of ``benchmarks/`` are run by hand, so nothing else notices when a refactor of
the library breaks one: ``run_overhead.py`` imported the module ``launch_metrics`` through
a name the package's ``__init__`` had turned into the function of that name, and
``launch_floor.py`` asked for an output grid that the launch metrics now refuse (found in
session 28, both broken for days).  Each script runs here as it is run by hand (a new
process, in a scratch directory) with arguments that make it short; what it measures is not
checked, only that it completes and ends with one JSON object.  The scripts that take a
minute even at their smallest (``compile_time.py``: cold compiles; ``rt_fuzz.py``: builds
the real-time kernel; ``core_speed.py`` and ``durability_speed.py``: no size argument) are
left to their own runs.  Without the directory (an installed package) the tests skip.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

BENCH = Path(__file__).resolve().parents[2] / "benchmarks"

SMALL = {
    "run_overhead.py": ["--calls", "2", "--sweep-runs", "4"],
    "launch_floor.py": ["--repeats", "1"],
    "step_cost.py": ["--repeats", "1"],
    "launch_speed.py": ["--repeats", "1", "--scipy-repeats", "1", "--t-end", "0.5"],
    "rt_step.py": ["--steps", "2000"],
    "sweep_throughput.py": ["--runs", "8", "--scaling-runs", "4", "--no-dask"],
    "uq_study.py": ["--runs", "16", "--sobol-base", "4", "--only", "grade_low"],
    "calibration_coverage.py": ["--trials", "1", "--launches", "1"],
}
#: left to their own runs (see the module docstring)
LONG = {"compile_time.py", "rt_fuzz.py", "core_speed.py", "durability_speed.py"}

pytestmark = pytest.mark.skipif(not BENCH.is_dir(),
                                reason=f"{BENCH} not present (benchmarks are not installed)")


def test_every_script_is_run_here_or_named_as_long():
    scripts = {p.name for p in BENCH.glob("*.py") if not p.name.startswith("_")}
    assert scripts == set(SMALL) | LONG


@pytest.mark.slow
@pytest.mark.parametrize("script", sorted(SMALL))
def test_benchmark_script_runs_at_its_smallest(script, tmp_path):
    proc = subprocess.run([sys.executable, str(BENCH / script), *SMALL[script]], cwd=tmp_path,
                          capture_output=True, text=True, timeout=600, check=False)
    assert proc.returncode == 0, proc.stderr[-3000:]
    last = proc.stdout.strip().splitlines()[-1]
    assert isinstance(json.loads(last), dict), last
