"""The dependency runs one way: scenario -> analysis -> network -> core."""

from __future__ import annotations

import json
import subprocess
import sys


def test_analysis_and_network_do_not_import_scenario():
    code = ("import json, sys\n"
            "import clutchsim.analysis.launch_metrics, clutchsim.network\n"
            "print(json.dumps(sorted(m for m in sys.modules if m.startswith('clutchsim'))))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, timeout=300)
    loaded = json.loads(out.stdout.splitlines()[-1])
    assert "clutchsim.analysis.launch_metrics" in loaded and "clutchsim.network.plant" in loaded
    assert [m for m in loaded if m.split(".")[:2] in (["clutchsim", "scenario"],
                                                      ["clutchsim", "studies"])] == []


def test_run_scenario_is_public_where_it_was():
    import clutchsim
    from clutchsim.scenario import run_scenario
    assert clutchsim.run_scenario is run_scenario
