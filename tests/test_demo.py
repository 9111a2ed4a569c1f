"""The demo (what ``make demo`` runs) end to end, and the compile-time overlap it relies on."""

import json
import multiprocessing

from clutchsim.demo import DEMO_MODELS, run_demo


def test_the_demo_writes_its_outputs_and_leaves_no_process_behind(tmp_path):
    out = tmp_path / "demo"
    summary = run_demo(out, plots=False)
    on_disk = json.loads((out / "demo.json").read_text())
    assert on_disk["launch"].keys() == summary["launch"].keys() == set(DEMO_MODELS)
    launch = on_disk["launch"]
    # model (6) and the robust switching model launch through lock-up; the naive model
    # chatters at lock-up and is stopped (the seed's Figs. 9-10)
    assert launch["mykhailevych2020"]["completed"] and launch["coulomb-robust"]["completed"]
    assert launch["coulomb-robust"]["lockup_time_s"] > launch["mykhailevych2020"][
        "engagement_start_s"]
    assert not launch["coulomb-naive"]["completed"]
    assert "chatter" in launch["coulomb-naive"]["message"]
    # the drift test (the seed's Figs. 3-5): model (6) does not drift, Dahl does
    drift = on_disk["drift"]
    assert abs(drift["mykhailevych2020"]["D1"]["drift_per_cycle_m"]) < 1e-9
    assert drift["dahl"]["D1"]["drift_per_cycle_m"] > 1e-6
    # the child that compiled the launch metrics beside the integrator is gone
    assert not [p for p in multiprocessing.active_children()
                if p.name == "clutchsim-demo-metrics"]


def test_the_reference_backend_compiles_the_metrics_the_integrator_uses():
    """The demo compiles the launch metrics in a second process through a launch on scipy's
    LSODA while it compiles the integrator.  That only saves time when both launches call
    the metrics kernel with the same argument types: one compiled signature for both."""
    from clutchsim.analysis import _kernels
    from clutchsim.scenario import load_scenario
    from clutchsim.scenario.run import run_scenario
    sc = load_scenario(None)
    run_scenario(sc, "mykhailevych2020", solver="scipy-lsoda")
    run_scenario(sc, "mykhailevych2020")
    assert len(_kernels.launch_kernel.signatures) == 1, _kernels.launch_kernel.signatures
