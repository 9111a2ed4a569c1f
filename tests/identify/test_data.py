"""Measured-data readers: column mapping, units, and clear errors for bad files."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.io import savemat

from clutchsim.data import Measurement, read_measurements


def _write_csv(path, header, rows):
    path.write_text(",".join(header) + "\n" + "\n".join(",".join(map(str, r)) for r in rows)
                    + "\n")
    return path


def test_csv_mapping_scale_and_tare(tmp_path):
    path = _write_csv(tmp_path / "d.csv", ["time", "pos_mm", "force_uN"],
                      [(0.0, 10.0, 5.0), (0.1, 10.5, -5.0), (0.2, 11.0, 0.0)])
    m = read_measurements(path, time="time", columns={"x": "pos_mm", "F": "force_uN"},
                          scale={"x": 1e-3, "F": -1e-6}, tare=["x"])
    np.testing.assert_allclose(m.t, [0.0, 0.1, 0.2])
    np.testing.assert_allclose(m["x"], [0.0, 0.5e-3, 1.0e-3])
    np.testing.assert_allclose(m["F"], [-5e-6, 5e-6, 0.0])
    assert m.names == ("x", "F")


def test_tab_separated_with_spaces_in_names(tmp_path):
    path = tmp_path / "d.txt"
    path.write_text("Time [s]\tFriction [uN]\n0\t1\n0.005\t2\n0.01\t3\n")
    m = read_measurements(path, time="Time [s]", columns={"F": "Friction [uN]"})
    np.testing.assert_allclose(m["F"], [1.0, 2.0, 3.0])


def test_npz_and_mat_scalars(tmp_path):
    t = np.linspace(0, 1, 11)
    np.savez(tmp_path / "d.npz", t=t, x=t ** 2, gain=np.float64(3.5))
    m = read_measurements(tmp_path / "d.npz")
    assert m.scalars["gain"] == 3.5 and m.names == ("x",)
    savemat(tmp_path / "d.mat", {"t": t[:, None], "qm": t[:, None] * 2, "kp": 160.0})
    m = read_measurements(tmp_path / "d.mat", columns={"q": "qm"})
    np.testing.assert_allclose(m["q"], 2 * t)
    assert m.scalars["kp"] == 160.0


def test_missing_columns_lists_those_found(tmp_path):
    path = _write_csv(tmp_path / "d.csv", ["t", "x", "F"], [(0, 1, 2), (1, 2, 3)])
    with pytest.raises(ValueError, match=r"missing column\(s\) 'force'.*columns found: "
                                         r"'t', 'x', 'F'") as exc:
        read_measurements(path, columns={"f": "force"})
    assert str(path) in str(exc.value)
    with pytest.raises(ValueError, match="missing column.*'time'"):
        read_measurements(path, time="time")


def test_non_monotone_time_names_the_row(tmp_path):
    path = _write_csv(tmp_path / "d.csv", ["t", "x"], [(0, 1), (0.1, 2), (0.05, 3), (0.2, 4)])
    with pytest.raises(ValueError, match=r"must increase strictly, but row 2 has t = 0.05 "
                                         r"after t = 0.1"):
        read_measurements(path)


def test_nan_gaps_are_reported_and_only_fixed_when_asked(tmp_path):
    path = _write_csv(tmp_path / "d.csv", ["t", "x"],
                      [(0, 1), (1, "nan"), (2, ""), (3, 4), (4, 5), (5, "NaN"), (6, 7)])
    with pytest.raises(ValueError, match=r"column 'x' has 3 NaN/inf value\(s\) at rows 1-2 "
                                         r"\(t = 1 s\), row 5 \(t = 5 s\).*nan='drop'.*"
                                         r"nan='interpolate'"):
        read_measurements(path)
    dropped = read_measurements(path, nan="drop")
    np.testing.assert_allclose(dropped.t, [0, 3, 4, 6])
    filled = read_measurements(path, nan="interpolate")
    np.testing.assert_allclose(filled["x"], [1, 2, 3, 4, 5, 6, 7])


def test_non_numeric_cell_and_unknown_format(tmp_path):
    path = _write_csv(tmp_path / "d.csv", ["t", "x"], [(0, 1), (1, "abc")])
    with pytest.raises(ValueError, match=r"column 'x' row 1 \(file line 3\) is not a number"):
        read_measurements(path)
    (tmp_path / "d.xlsx").write_text("")
    with pytest.raises(ValueError, match="unknown data format '.xlsx'"):
        read_measurements(tmp_path / "d.xlsx")
    with pytest.raises(ValueError, match="no such data file"):
        read_measurements(tmp_path / "nothere.csv")


def test_measurement_window_and_lookup():
    m = Measurement.from_arrays(np.arange(10.0), x=np.arange(10.0) * 2)
    w = m.window(2.0, 5.0)
    np.testing.assert_allclose(w.t, [2, 3, 4, 5])
    with pytest.raises(ValueError, match=r"no column 'y'.*columns: x"):
        m["y"]
    with pytest.raises(ValueError, match="fewer than 2 samples"):
        m.window(20.0, 30.0)
    with pytest.raises(ValueError, match=r"column 'x' has 1 NaN"):
        Measurement.from_arrays([0.0, 1.0, 2.0], x=[0.0, np.nan, 1.0])
