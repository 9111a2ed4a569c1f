"""Vehicle logs: CSV, MDF4 and CAN (through a DBC) round trips, time-base rules, the channel
map, and the launch finder."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from clutchsim.data.channels import load_channel_map, map_log
from clutchsim.data.launches import cut_launch, find_launches
from clutchsim.data.logs import Channel, VehicleLog, read_log, write_log
from clutchsim.identify.synthetic import synthetic_log

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples" / "calibration"
DBC = EXAMPLES / "j1939_launch.dbc"


@pytest.fixture(scope="module")
def synthetic():
    return synthetic_log(launches=2, seed=4)


@pytest.fixture(scope="module")
def cmap():
    return load_channel_map(EXAMPLES / "channels.toml")


def test_csv_round_trip_is_exact_and_keeps_each_rate(synthetic, tmp_path):
    log, _ = synthetic
    path = write_log(log, tmp_path / "log.csv")
    back = read_log(path)
    assert set(back.channels) == set(log.channels)
    for name, ch in log.channels.items():
        assert np.array_equal(back[name].t, ch.t)
        assert np.array_equal(back[name].values, ch.values)
        assert back[name].unit == ch.unit
    # mixed rates: 25 Hz engine, 17 Hz vehicle speed, 50 Hz input shaft and actuator
    assert back["EngineSpeed"].rate == pytest.approx(25.0, rel=0.02)
    assert back["WheelBasedVehicleSpeed"].rate == pytest.approx(17.0, rel=0.02)
    assert back["InputShaftSpeed"].rate == pytest.approx(50.0, rel=0.02)


def test_mdf4_round_trip_is_bit_exact(synthetic, tmp_path):
    log, _ = synthetic
    path = write_log(log, tmp_path / "log.mf4")
    back = read_log(path)
    for name, ch in log.channels.items():
        assert np.array_equal(back[name].t, ch.t), name
        assert np.array_equal(back[name].values, ch.values), name
        assert back[name].unit == ch.unit


@pytest.mark.parametrize("suffix", [".blf", ".asc"])
def test_can_round_trip_through_the_dbc(synthetic, tmp_path, suffix):
    import can
    import cantools
    log, _ = synthetic
    path = write_log(log, tmp_path / f"log{suffix}", dbc=DBC)
    db = cantools.database.load_file(str(DBC))
    # the frames on file are bit for bit the ones cantools encodes from the log's values
    frames = [m for m in can.LogReader(str(path))]
    eec1 = db.get_message_by_name("EEC1")
    mine = [f for f in frames if f.arbitration_id == eec1.frame_id]
    speed, torque = log["EngineSpeed"], log["ActualEnginePercentTorque"]
    assert len(mine) == speed.t.size
    for k in (0, 17, speed.t.size - 1):
        want = eec1.encode({s.name: (speed.values[k] if s.name == "EngineSpeed" else
                                     torque.values[k] if s.name == "ActualEnginePercentTorque"
                                     else s.minimum) for s in eec1.signals})
        assert bytes(mine[k].data) == want
    back = read_log(path, dbc=DBC)
    shift = back["EngineSpeed"].t[0] - speed.t[0]     # ASC counts from its first frame
    for name in ("EngineSpeed", "ActualEnginePercentTorque", "InputShaftSpeed",
                 "ClutchSwitch"):
        assert np.array_equal(back[name].values, log[name].values), name   # exact in the DBC
        assert np.allclose(back[name].t - shift, log[name].t, atol=2e-6)
    # 0.1 km/h steps in a 1/256 km/h signal: within half a bit
    assert np.max(np.abs(back["WheelBasedVehicleSpeed"].values
                         - log["WheelBasedVehicleSpeed"].values)) <= 1 / 512 + 1e-12
    assert back["EngineSpeed"].unit == "rpm"


def test_a_dbc_that_decodes_none_of_the_frames_is_refused(synthetic, tmp_path):
    log, _ = synthetic
    path = write_log(log, tmp_path / "log.blf", dbc=DBC)
    other = tmp_path / "other.dbc"
    other.write_text('VERSION ""\n\nNS_ :\n\nBS_:\n\nBU_: A\n\n'
                     'BO_ 2565799934 OTHER: 8 A\n SG_ X : 0|8@1+ (1,0) [0|255] "" A\n')
    with pytest.raises(ValueError, match=r"decodes none of its \d+ frames"):
        read_log(path, dbc=other)


def _channel_log(t, v, name="EngineSpeed"):
    return VehicleLog("x.csv", {name: Channel(name, np.asarray(t, float), np.asarray(v, float),
                                              "rpm", "g")})


def test_time_base_going_backwards_is_refused_or_sorted(tmp_path):
    path = tmp_path / "back.csv"
    path.write_text("t [s],EngineSpeed [rpm]\n0.0,800\n0.04,801\n0.02,802\n0.06,803\n")
    with pytest.raises(ValueError, match=r"back.csv: channel 'EngineSpeed': the time base "
                                         r"goes backwards at sample 2"):
        read_log(path)
    log = read_log(path, time_order="sort")
    assert np.array_equal(log["EngineSpeed"].values, [800, 802, 801, 803])
    assert "sorted" in log.notes[0]


def test_duplicated_stamps_by_policy(tmp_path):
    path = tmp_path / "dup.csv"
    path.write_text("t,EngineSpeed [rpm]\n0.0,800\n0.04,801\n0.04,803\n0.08,804\n")
    with pytest.raises(ValueError, match="duplicated time stamp t = 0.04 s"):
        read_log(path)
    assert np.array_equal(read_log(path, duplicates="first")["EngineSpeed"].values,
                          [800, 801, 804])
    assert np.array_equal(read_log(path, duplicates="mean")["EngineSpeed"].values,
                          [800, 802, 804])


def test_csv_groups_with_gaps_and_short_columns(tmp_path):
    path = tmp_path / "groups.csv"
    path.write_text("t_a [s],A [rpm],t_b [s],B [km/h]\n0.0,1,0.0,5\n0.1,,0.2,6\n0.2,3,,\n")
    log = read_log(path)
    assert np.array_equal(log["A"].t, [0.0, 0.2]) and log["A"].unit == "rpm"
    assert np.array_equal(log["B"].t, [0.0, 0.2]) and log["B"].group == "b"


def test_channel_map_errors_name_file_line_and_rule(tmp_path, synthetic, cmap):
    bad = tmp_path / "map.toml"
    bad.write_text('[log]\nreference_torque = 250.0\n\n[channels.engine_sped]\n'
                   'name = "EngineSpeed"\nunit = "rpm"\n')
    with pytest.raises(ValueError, match=r"map.toml:4: \[channels.engine_sped\]: unknown "
                                         r"signal \(did you mean 'engine_speed'\?\)"):
        load_channel_map(bad)
    bad.write_text('[channels.vehicle_speed]\nname = "WheelBasedVehicleSpeed"\nunit = "rpm"\n')
    with pytest.raises(ValueError, match=r"map.toml:3: .*vehicle_speed is a speed, in one of "
                                         r"'km/h', 'm/s'"):
        load_channel_map(bad)
    log, _ = synthetic
    # the log records km/h, the map says m/s: refused, not converted
    bad.write_text('[channels.vehicle_speed]\nname = "WheelBasedVehicleSpeed"\nunit = "m/s"\n')
    with pytest.raises(ValueError, match=r"channel 'WheelBasedVehicleSpeed' is in 'km/h' but "
                                         r".*map.toml:3 \[channels.vehicle_speed\] unit says "
                                         r"'m/s'"):
        map_log(log, load_channel_map(bad))
    bad.write_text('[channels.engine_speed]\nname = "EngSpeed"\nunit = "rpm"\n')
    with pytest.raises(ValueError, match=r"no channel 'EngSpeed' \(mapped to engine_speed at "
                                         r".*map.toml:2\)"):
        map_log(log, load_channel_map(bad))


def test_mapping_converts_to_si(synthetic, cmap):
    log, _ = synthetic
    m = map_log(log, cmap)
    assert m["engine_speed"].unit == "rad/s"
    assert np.allclose(m["engine_speed"].values, log["EngineSpeed"].values * np.pi / 30)
    assert np.allclose(m["engine_torque"].values,
                       log["ActualEnginePercentTorque"].values * 2.5)      # 250 N·m = 100 %
    assert np.allclose(m["clutch_position"].values, log["ClutchActuatorPosition"].values * 1e-3)


def test_launch_finder_finds_each_launch_and_its_lock_up(synthetic, cmap):
    log, truth = synthetic
    launches = find_launches(map_log(log, cmap))
    assert len(launches) == 2
    t, we, wi = truth["t"], truth["engine_speed"], truth["input_speed"]
    for la in launches:
        inside = (t > la.t_clutch) & (t < la.t_end)
        # (model (6), the truth's clutch, sticks with a pre-sliding slip below 1e-3 rad/s)
        locked = t[inside][np.abs(we[inside] - wi[inside]) < 1e-2]
        # the finder's lock-up lies within two engine-speed samples of the true one
        assert abs(la.t_lockup - locked[0]) < 0.08
        assert la.t_start < la.t_clutch < la.t_move < la.t_lockup < la.t_end
        # each signal keeps its own stamps
        assert la.signals["engine_speed"].t.size < la.signals["input_speed"].t.size


def test_no_launch_and_a_window_without_clutch_event(synthetic, cmap):
    log, _ = synthetic
    m = map_log(log, cmap)
    standing = m.window(0.0, 0.9)      # idle before the first launch
    still = type(m)(m.source, {n: c for n, c in standing.items()}, m.log, m.map)
    assert find_launches(still) == []
    la = find_launches(m)[0]
    # a window starting after the clutch began to close holds no clutch event
    with pytest.raises(ValueError, match="has no clutch event"):
        cut_launch(m, la.t_clutch + 0.3, la.t_end)


def test_a_clutch_switch_instead_of_a_position_finds_the_launches(synthetic, tmp_path):
    log, _ = synthetic
    text = (EXAMPLES / "channels.toml").read_text()
    text = text[:text.index("[channels.clutch_position]")]
    (tmp_path / "map.toml").write_text(text)
    m = map_log(log, load_channel_map(tmp_path / "map.toml"))
    launches = find_launches(m)
    assert len(launches) == 2
    with_position = find_launches(map_log(log, load_channel_map(EXAMPLES / "channels.toml")))
    for a, b in zip(launches, with_position):
        # the switch is released when the travel passes 1 mm before the touch point
        assert abs(a.t_lockup - b.t_lockup) < 1e-9 and a.t_clutch > b.t_clutch
