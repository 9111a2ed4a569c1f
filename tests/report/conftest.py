"""Fixtures: output directories like the ones ``clutchsim run`` writes, from a real run."""

from __future__ import annotations

import json

import pytest


def _figure(res, signal, path):
    from clutchsim.plot._style import new_figure, save_png
    fig, axes = new_figure(figsize=(7.0, 3.5))
    ax = axes[0, 0]
    ax.plot(res.t, res[signal])
    ax.set_xlabel("t [s]")
    ax.set_ylabel(f"{signal} [{res.units.get(signal, '')}]")
    save_png(fig, path, dpi=100)


@pytest.fixture(scope="session")
def rig_result():
    """A real clutchsim run: the LuGre rig pulled through a spring for 5 s."""
    import clutchsim as cs
    return cs.run_rig(cs.make_model("lugre"), 5.0, force=0.0, spring=2.0, pull_speed=0.1)


@pytest.fixture
def run_dir(tmp_path, rig_result):
    """A run directory: timeseries.csv, two PNG figures, summary.json, a scenario TOML."""
    d = tmp_path / "launch"
    d.mkdir()
    res = rig_result
    res.to_csv(d / "timeseries.csv")
    _figure(res, "x", d / "position.png")
    _figure(res, "F", d / "friction_force.png")
    s = res.summary()
    stats = {k: s[k] for k in ("steps", "rhs_evals", "events", "min_step_s", "wall_s")}
    summary = {
        "scenario": "spring pull",
        "command": ["clutchsim", "rig", "--model", "lugre", "--out", "launch"],
        "models": {
            "lugre": {"completed": True, "message": s["message"], "lockup_time_s": 1.2345678,
                      "slip_energy_J": 12345.678, "peak_heat_node_temp_C": 87.25,
                      "engine_stalled": False, **stats},
            "coulomb-naive": {"completed": False,
                              "message": "stopped by chatter detection at lock-up",
                              "lockup_time_s": None, "slip_energy_J": 9000.0,
                              "peak_heat_node_temp_C": 80.0, "engine_stalled": False,
                              "steps": 100000, "rhs_evals": 1234567, "events": 4000,
                              "min_step_s": 1e-12, "wall_s": 12.5},
        },
        "warnings": ["lining temperature above 80 C in coulomb-naive"],
    }
    (d / "summary.json").write_text(json.dumps(summary, indent=2))
    (d / "figures.json").write_text(json.dumps({"position.png": "Position of the mass"}))
    (d / "scenario.toml").write_text('[rig]\nmodel = "lugre"\nspring = 2.0   # N/m\n')
    from clutchsim._util import MANIFEST  # what clutchsim writes with it: its manifest
    (d / MANIFEST).write_text(json.dumps({"kind": "run", "files": sorted(
        p.name for p in d.iterdir())}))
    return d
