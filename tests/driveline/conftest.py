import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent))

from _dl_paths import shared_dir


@pytest.fixture
def modelica_csv():
    path = (shared_dir() / "reference" / "modelica" / "Modelica" / "Mechanics" / "Rotational"
            / "Examples" / "CoupledClutches" / "CoupledClutches.csv")
    if not path.exists():
        pytest.skip(f"Modelica reference results not found at {path} "
                    "(set CLUTCHSIM_SHARED to the shared folder)")
    return path
