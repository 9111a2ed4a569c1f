"""A machine without a C compiler still runs everything (issue 41): the generated plant is
compiled by numba, the C engine cannot be built, and the run takes scipy's reference
backend; the command completes (exit 0) and its summary says which integrator made the
numbers and why.  A fresh numba cache, so that no engine or plant built by a compiler is
found there (a cached engine is loaded, not compiled, and would be used)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_a_run_without_a_c_compiler_completes_on_the_reference_backend_and_says_so(tmp_path):
    env = {**os.environ, "CC": str(tmp_path / "no-such-cc"),
           "NUMBA_CACHE_DIR": str(tmp_path / "numba"), "XDG_CACHE_HOME": str(tmp_path / "xdg")}
    proc = subprocess.run(
        [sys.executable, "-m", "clutchsim", "run", str(EXAMPLES / "lossy_gear_demo2.toml"),
         "--out", str(tmp_path / "out"), "--json", "--no-plots"],
        check=False, env=env, capture_output=True, text=True, timeout=900)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert "the C integration engine is not available here" in proc.stderr
    assert "is not an executable compiler" in proc.stderr       # the reason, once
    run = json.loads(proc.stdout)["runs"]["LossyGearDemo2"]
    assert run["completed"] and run["outcome"] == "completed"
    assert any("integrated by scipy's RADAU" in w and "not by rodas4" in w
               for w in run["warnings"]), run["warnings"]
    # the physics checks ran on the reference backend's rows too
    assert abs(run["energy_balance_rel"]) < 1e-6
    assert not list((tmp_path / "numba").rglob("*.so"))        # nothing compiled by a C compiler
