"""``clutchsim log`` and ``clutchsim calibrate``: JSON documents, output files, and exit
status 2 with the file, line and channel for bad input."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from clutchsim.cli import main
from clutchsim.data.logs import Channel, VehicleLog, read_log, write_log

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples" / "calibration"
MAP = str(EXAMPLES / "channels.toml")
LOG = str(EXAMPLES / "launch_log.csv")


def spec_text() -> str:
    """The example spec with absolute paths to its scenario and channel map (for a copy in
    tmp_path)."""
    return (EXAMPLES / "launch_calibration.toml").read_text().replace(
        'scenario = "../launch.toml"', f'scenario = "{ROOT / "examples" / "launch.toml"}"'
    ).replace('channels = "channels.toml"', f'channels = "{MAP}"')


def test_log_info_lists_channels_rates_and_mapped_signals(capsys):
    assert main(["log", "info", LOG, "--channels", MAP, "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    rates = {c["name"]: c["rate_hz"] for c in doc["channels"]}
    assert rates["EngineSpeed"] == pytest.approx(25.0, rel=0.02)
    assert rates["WheelBasedVehicleSpeed"] == pytest.approx(17.0, rel=0.02)
    assert rates["ClutchActuatorPosition"] == pytest.approx(50.0, rel=0.02)
    assert doc["signals"]["vehicle_speed"]["unit"] == "m/s"
    assert main(["log", "info", LOG]) == 0
    assert "EngineSpeed" in capsys.readouterr().out


def test_log_launches_cuts_records(tmp_path, capsys):
    out = tmp_path / "launches"
    assert main(["log", "launches", LOG, "--channels", MAP, "--out", str(out), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert len(doc["launches"]) == 2
    first = read_log(out / "launch_01.csv")
    la = doc["launches"][0]
    assert first["engine_speed"].unit == "rad/s"
    assert first["engine_speed"].t[0] >= la["t_start"] and first["engine_speed"].t[-1] <= la["t_end"]
    assert json.loads((out / "launches.json").read_text())["launches"] == doc["launches"]


def test_calibrate_writes_parameters_intervals_and_report(tmp_path, capsys):
    out = tmp_path / "calib"
    code = main(["calibrate", str(EXAMPLES / "launch_calibration.toml"), "--validate",
                 str(EXAMPLES / "validate_log.csv"), "--out", str(out), "--json", "--quiet"])
    captured = capsys.readouterr()
    assert code == 0, captured.err
    doc = json.loads(captured.out)
    assert {"parameters", "intervals", "correlation", "unidentified", "launches",
            "validation"} <= set(doc)
    cap, (lo, hi) = doc["parameters"]["capacity"], doc["intervals"]["capacity"]
    assert lo < cap < hi and abs(cap / 240.0 - 1) < 0.05          # the example's truth
    assert len(doc["validation"]) == 1 and doc["validation"][0]["engine_rms_rpm"] < 40
    for name in ("calibration.json", "parameters.toml", "traces.csv", "report.md",
                 "calibration.png", "command.txt"):
        assert (out / name).is_file(), name
    import tomllib
    toml = tomllib.loads((out / "parameters.toml").read_text())
    assert toml["parameters"]["capacity"] == pytest.approx(cap)
    assert toml["intervals"]["capacity"] == pytest.approx([lo, hi])


def _run_err(argv, capsys) -> tuple[int, str]:
    code = main(argv)
    return code, capsys.readouterr().err


def test_unknown_channel_exits_2_naming_channel_and_map_line(tmp_path, capsys):
    bad = tmp_path / "map.toml"
    bad.write_text(Path(MAP).read_text().replace('"EngineSpeed"', '"EngSpd"'))
    code, err = _run_err(["log", "launches", LOG, "--channels", str(bad)], capsys)
    assert code == 2
    assert "no channel 'EngSpd' (mapped to engine_speed at" in err and "map.toml:" in err
    assert "Traceback" not in err


def test_wrong_unit_exits_2(tmp_path, capsys):
    bad = tmp_path / "map.toml"
    bad.write_text(Path(MAP).read_text().replace('unit = "km/h"', 'unit = "m/s"'))
    code, err = _run_err(["log", "info", LOG, "--channels", str(bad)], capsys)
    assert code == 2
    assert "channel 'WheelBasedVehicleSpeed' is in 'km/h'" in err and "unit says 'm/s'" in err


def test_log_without_a_launch_exits_2(tmp_path, capsys):
    log = read_log(LOG)
    keep = {n: Channel(n, c.t[c.t < 0.8], c.values[c.t < 0.8], c.unit, c.group)
            for n, c in log.channels.items()}
    path = write_log(VehicleLog("idle", keep), tmp_path / "idle.csv")
    code, err = _run_err(["log", "launches", str(path), "--channels", MAP], capsys)
    assert code == 2 and "idle.csv: no launch found" in err
    spec = tmp_path / "spec.toml"
    spec.write_text(spec_text())
    code, err = _run_err(["calibrate", str(spec), "--log", str(path), "--out",
                          str(tmp_path / "c")], capsys)
    assert code == 2 and "no launch found" in err and "idle.csv" in err


def test_time_base_backwards_exits_2(tmp_path, capsys):
    text = Path(LOG).read_text().splitlines()
    a, b = text[5].split(","), text[6].split(",")
    a[0], b[0] = b[0], a[0]                      # two EEC1 stamps swapped
    text[5], text[6] = ",".join(a), ",".join(b)
    path = tmp_path / "back.csv"
    path.write_text("\n".join(text) + "\n")
    code, err = _run_err(["log", "info", str(path)], capsys)
    assert code == 2
    assert "channel 'EngineSpeed': the time base goes backwards at sample" in err


def test_dbc_that_does_not_decode_exits_2(tmp_path, capsys):
    path = write_log(read_log(LOG), tmp_path / "log.asc", dbc=EXAMPLES / "j1939_launch.dbc")
    other = tmp_path / "other.dbc"
    other.write_text('VERSION ""\n\nNS_ :\n\nBS_:\n\nBU_: A\n\n'
                     'BO_ 2565799934 OTHER: 8 A\n SG_ X : 0|8@1+ (1,0) [0|255] "" A\n')
    code, err = _run_err(["log", "info", str(path), "--dbc", str(other)], capsys)
    assert code == 2 and "decodes none of its" in err and "other.dbc" in err


def test_calibrate_bad_spec_exits_2_with_line(tmp_path, capsys):
    spec = tmp_path / "spec.toml"
    spec.write_text(spec_text().replace("capacity = {", "capasity = {"))
    code, err = _run_err(["calibrate", str(spec), "--out", str(tmp_path / "c")], capsys)
    assert code == 2
    assert "spec.toml:" in err and "'capasity' is neither a parameter of the measured" in err
    assert not (tmp_path / "c").exists()


def test_window_without_clutch_event_exits_2(tmp_path, capsys):
    spec = tmp_path / "spec.toml"
    spec.write_text(spec_text().replace(f'channels = "{MAP}"',
                                        f'channels = "{MAP}"\nwindows = [[3.0, 6.0]]'))
    code, err = _run_err(["calibrate", str(spec), "--log", LOG, "--out",
                          str(tmp_path / "c")], capsys)
    assert code == 2 and "launch window [3, 6] s" in err
    assert np.isfinite(1.0)
