"""Paths shared by the driveline tests."""

import os
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
EXAMPLES = REPO / "examples"


def shared_dir() -> Path:
    env = os.environ.get("CLUTCHSIM_SHARED")
    return Path(env) if env else (REPO / ".." / "shared").resolve()
