"""The figure of a run of any network (clutchsim.plot.network): what it draws, drawn without
a warning of the plotting library (pytest turns warnings into errors)."""

from pathlib import Path

import numpy as np
import pytest

from clutchsim.core import Result, Stats
from clutchsim.plot.network import network_panels, plot_network
from clutchsim.scenario.run import run_scenario

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


@pytest.fixture(scope="module")
def coupled():
    return run_scenario(EXAMPLES / "coupled_clutches.toml").result


def test_panels_of_coupled_clutches(coupled):
    panels = network_panels(coupled)
    assert [p[:2] for p in panels] == [("speeds", "speed [rad/s]"),
                                       ("torques", "torque [N·m]"),
                                       ("friction power", "power [W]")]
    speeds, torques, power = (p[2] for p in panels)
    assert speeds == ["omega_J1", "omega_J2", "omega_J3", "omega_J4"]
    assert {"T_J1_load", "T_clutch1", "T_clutch2", "T_clutch3"} == set(torques)
    assert power == ["P_clutch1", "P_clutch2", "P_clutch3"]
    fig, ax = plot_network(coupled)
    assert ax.shape == (3, 1)
    drawn = [line.get_label() for line in ax[0, 0].get_lines()]
    assert drawn == speeds
    # each line is the signal itself, over the run's times
    x, y = ax[2, 0].get_lines()[0].get_data()
    assert np.array_equal(x, coupled.t) and np.array_equal(y, coupled["P_clutch1"])
    assert "coulomb-robust" in fig.get_suptitle()


def test_a_run_with_nothing_to_draw_still_gets_a_figure_without_warnings():
    t = np.linspace(0.0, 1.0, 5)
    res = Result.build(t, [("x", "-", t)], outcome="completed", message="done",
                       stats=Stats(1, 0, 1, 0, 0, 0, 0.1, 0.0), system="bare")
    assert network_panels(res) == []
    _, ax = plot_network(res)
    assert ax.shape == (1, 1) and ax[0, 0].get_legend() is None
    with pytest.raises(TypeError, match="clutch"):
        plot_network(res, clutch="c")
