"""Where the shared measured data sets live (outside the repository, never copied into it)."""

from __future__ import annotations

import os
from pathlib import Path

__all__ = ["shared_dir"]


def shared_dir() -> Path:
    """``$CLUTCHSIM_SHARED``, else ``<repo root>/../shared``, else ``<cwd>/../shared``.

    The directory may not exist; callers check (tests skip with a reason).
    """
    env = os.environ.get("CLUTCHSIM_SHARED")
    if env:
        return Path(env)
    repo = Path(__file__).resolve().parents[3]
    for cand in (repo.parent / "shared", Path.cwd().parent / "shared"):
        if cand.is_dir():
            return cand
    return repo.parent / "shared"
