"""Fixtures: an explorer session on the packaged launch and a run output directory."""

from __future__ import annotations

import pytest

pytest.importorskip("bokeh", reason="the explorer needs Bokeh (the extra clutchsim[explore])")


@pytest.fixture(scope="session")
def launch_dir(tmp_path_factory):
    """``clutchsim run`` of the packaged launch with its two models (no PNGs)."""
    from clutchsim.scenario import load_scenario
    from clutchsim.scenario.outputs import write_runs
    d = tmp_path_factory.mktemp("launch")
    sc = load_scenario(None)
    write_runs(sc, sc.models, d, plots=False)
    return d
