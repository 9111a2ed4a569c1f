"""Real-data fits reach the NRMSE reported in docs/identification.md (fast cases only)."""

from __future__ import annotations

import numpy as np
import pytest
from _identify_helpers import shared_file

from clutchsim.data import read_measurements
from clutchsim.friction import make_model
from clutchsim.identify import FitOptions, FitProblem, evaluate, fit


@pytest.fixture(scope="module")
def tribo():
    path = shared_file("data", "microtribometer_reciprocating", "reciprocating_5N_part1.txt")
    m = read_measurements(path, time="Time [s]",
                          columns={"N": "Normal [uN]", "x": "Position [mm]",
                                   "F": "Friction [uN]"},
                          scale={"N": 1e-6, "x": 1e-3, "F": -1e-6}, tare=["x"])
    return m.with_column("s", m["N"] / 5.0)


def test_microtribometer_elastoplastic_presliding_fit(tribo):
    """Reported: NRMSE 0.056 on 8.5-50.78 s, F_c = 2.40 N, sigma0 = 4.2e4 N/m, z_ba = 20 µm."""
    start = make_model("elastoplastic", F_c=2.2, F_s=2.3, v_s=1e-4, sigma0=5e4, sigma1=10.0,
                       sigma2=0.0, z_ba=2e-5)
    problem = FitProblem(input="x", output="F", plant="rig-velocity",
                         plant_options={"differentiate": True, "smooth": 5, "scale": "s"},
                         params=["F_c", "sigma0", "z_ba", "offset"],
                         bounds={"F_c": (0.5, 5.0), "sigma0": (1e3, 1e7), "z_ba": (1e-7, 1e-3),
                                 "offset": (-0.5, 0.5)})
    res = fit(start, tribo.window(8.5, 30.78), problem, FitOptions(tol=1e-6),
              validate=[tribo.window(8.5, 50.78)])
    assert res.nrmse_fit < 0.056 * 1.25
    assert res.nrmse_validation < 0.056 * 1.25
    assert res.parameters["F_c"] == pytest.approx(2.40, rel=0.05)
    assert res.parameters["sigma0"] == pytest.approx(4.2e4, rel=0.25)
    # the break-away deflection is weakly identified by this record: with numpy 2.4 /
    # scipy 1.17 the fit ends at 26-29 µm (the engine and the landed code of 2026-11 alike)
    # with NRMSE 0.0553-0.0559, i.e. the objective is flat between 20 and 30 µm
    assert res.parameters["z_ba"] == pytest.approx(2.0e-5, rel=0.5)


def test_brfd_reported_dahl_parameters_reproduce_the_table():
    """The Dahl parameters of the BRFD table, simulated on two held tests (no refit)."""
    folder = ("data", "brfd_friction_damper")
    ref = read_measurements(shared_file(*folder, "dataset-2_characterization_0.5Hz30lbtension"
                                                 "1amplitude.npz"),
                            columns=["F_act1", "F_act2"], scale={"F_act1": 4.448222,
                                                                 "F_act2": 4.448222})
    n_ref = float(np.mean(ref["F_act1"] + ref["F_act2"]))
    m = read_measurements(shared_file(*folder, "dataset-2_characterization_1Hz36lbtension"
                                               "1amplitude.npz"),
                          columns=["x", "F", "F_act1", "F_act2"],
                          scale={"x": 0.0254, "F": 4448.222, "F_act1": 4.448222,
                                 "F_act2": 4.448222})
    m = m.with_column("s", (m["F_act1"] + m["F_act2"]) / n_ref)
    model = make_model("dahl", **DAHL)
    tr = evaluate(model, m, input="x", output="F", plant="rig-velocity",
                  plant_options={"differentiate": True, "smooth": 9, "scale": "s",
                                 "offset": DAHL_OFFSET})
    assert tr.nrmse < DAHL_NRMSE_1HZ36 + 0.01


# from docs/identification.md (BRFD table, dahl column, as scripts/validate_real_data.py
# wrote it on 2026-12-02); copy them again when the script is re-run
DAHL = {"F_c": 7318.0, "sigma0": 1.852e6, "alpha": 0.2374}
DAHL_OFFSET = 157.7
DAHL_NRMSE_1HZ36 = 0.102
