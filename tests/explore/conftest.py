"""Fixtures: an explorer session on the packaged launch and a run output directory."""

from __future__ import annotations

import logging

import pytest


@pytest.fixture(scope="session")
def launch_dir(tmp_path_factory):
    """The output directory of ``clutchsim run`` (the packaged launch, its two models)."""
    from clutchsim.cli import main
    d = tmp_path_factory.mktemp("launch") / "launch"
    root = logging.getLogger()
    saved = list(root.handlers)
    try:
        assert main(["run", "--out", str(d), "--quiet"]) == 0
    finally:
        root.handlers[:] = saved
    return d
