#!/usr/bin/env python
"""Write the example logs of docs/calibration.md (examples/calibration/): synthetic launches
of the default launch scenario with a known truth (clutchsim.identify.synthetic, seeds
fixed), degraded as a logger records them.

    PYTHONPATH=src .venv/bin/python scripts/calibration_example_logs.py

launch_log.csv: two launches (seed 1), fitted by launch_calibration.toml; validate_log.csv:
one launch (seed 2), predicted; validate_log.asc: the launch of validate_log.csv as J1939 CAN
frames encoded with j1939_launch.dbc.  The truth: clutchsim.identify.synthetic.DEFAULT_TRUTH.
"""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

from clutchsim.data.logs import write_log
from clutchsim.identify.synthetic import synthetic_log

HERE = ROOT / "examples" / "calibration"


def main() -> int:
    fit, _ = synthetic_log(launches=2, seed=1, source="launch_log")
    val, _ = synthetic_log(launches=1, seed=2, source="validate_log")
    write_log(fit, HERE / "launch_log.csv")
    write_log(val, HERE / "validate_log.csv")
    write_log(val, HERE / "validate_log.asc", dbc=HERE / "j1939_launch.dbc")
    for name in ("launch_log.csv", "validate_log.csv", "validate_log.asc"):
        print(f"wrote {HERE / name} ({(HERE / name).stat().st_size:,} bytes)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
