"""Every ```python example in the README and docs/ runs (so the docs cannot rot).

Each markdown file's blocks run in order in one fresh interpreter, in a temporary working
directory, so later blocks may use names from earlier ones and files they write stay out of
the repository.
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
FILES = sorted([ROOT / "README.md", *(ROOT / "docs").rglob("*.md")])
BLOCK = re.compile(r"^```python\n(.*?)^```", re.DOTALL | re.MULTILINE)


def _examples():
    for path in FILES:
        blocks = BLOCK.findall(path.read_text(encoding="utf-8"))
        if blocks:
            yield pytest.param(path, blocks, id=str(path.relative_to(ROOT)))


@pytest.mark.parametrize("path, blocks", list(_examples()))
def test_documented_python_examples_run(path, blocks, tmp_path):
    code = "\n\n".join(blocks)
    done = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True,
                          text=True, timeout=900, check=False)
    assert done.returncode == 0, f"{path.name}:\n{done.stderr[-3000:]}"
