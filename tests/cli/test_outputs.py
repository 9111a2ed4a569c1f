"""Output directories never lose a file clutchsim did not write (clutchsim._util).

The one writer of output directories, through ``clutchsim run`` with its simulation
replaced by a stand-in (what is tested here happens before and after it) and directly:
a user's folder is refused (exit 2, before anything runs) or, with ``--force``, written
beside; an earlier output of the same kind is replaced; a link is followed, never renamed;
a second command for the same directory stops with "in use by process N"; an interrupt
leaves the directory as it was.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from clutchsim._util import MANIFEST, OutputPathError, claim_output_dir, read_manifest
from clutchsim.cli import main

RUN = ["run", "--model", "coulomb-robust", "--no-plots", "-q"]


@pytest.fixture
def fake_runs(monkeypatch):
    """``write_runs`` replaced by one that writes a time series and returns a summary (the
    command's own steps run as they are); ``calls`` counts the "simulations"."""
    from clutchsim.scenario import outputs
    calls = []

    def write_runs(scenario, models, directory, **kw):
        calls.append(directory)
        (directory / "timeseries.csv").write_text("t [s],x [m]\n0,0\n")
        return {"kind": "run", "scenario": scenario.name, "file": scenario.file,
                "models": {"coulomb-robust": {"completed": True, "outcome": "completed",
                                              "message": "completed", "warnings": []}}}
    monkeypatch.setattr(outputs, "write_runs", write_runs)
    return calls


def _tree(d: Path) -> dict:
    return {str(p.relative_to(d)): p.read_bytes() if p.is_file() else None
            for p in sorted(d.rglob("*"))}


def test_a_folder_of_user_files_is_refused_before_anything_runs(tmp_path, capsys, fake_runs):
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "notes.txt").write_text("my notes\n")
    before = _tree(tmp_path)
    assert main([*RUN, "--out", str(mine)]) == 2
    err = capsys.readouterr().err
    assert "notes.txt" in err and "--force" in err and str(mine) in err
    assert fake_runs == [] and _tree(tmp_path) == before


def test_force_writes_beside_user_files_and_replaces_only_its_own(tmp_path, capsys,
                                                                 fake_runs):
    mine = tmp_path / "mine"
    (mine / "sub").mkdir(parents=True)
    (mine / "notes.txt").write_text("my notes\n")
    (mine / "sub" / "data.bin").write_bytes(b"\x00\x01")
    assert main([*RUN, "--out", str(mine), "--force"]) == 0
    assert (mine / "notes.txt").read_text() == "my notes\n"
    assert (mine / "sub" / "data.bin").read_bytes() == b"\x00\x01"
    manifest = read_manifest(mine)
    assert manifest["kind"] == "run"
    assert {"timeseries.csv", "summary.json", "command.txt", "report.html"} <= \
        set(manifest["files"])
    assert "notes.txt" not in manifest["files"]
    # an earlier output's file that the new one does not write goes; the user's stay
    (mine / "timeseries_old.csv").write_text("old\n")
    manifest["files"].append("timeseries_old.csv")
    (mine / MANIFEST).write_text(json.dumps(manifest))
    assert main([*RUN, "--out", str(mine), "--force"]) == 0
    assert not (mine / "timeseries_old.csv").exists()
    assert (mine / "notes.txt").is_file() and (mine / "sub" / "data.bin").is_file()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["mine"]   # no partial, no lock


def test_an_output_of_the_same_kind_is_replaced_and_said(tmp_path, capsys, fake_runs):
    out = tmp_path / "o"
    assert main([*RUN, "--out", str(out)]) == 0
    (out / "timeseries.csv").write_text("stale\n")
    assert main(["run", "--model", "coulomb-robust", "--no-plots", "--out", str(out)]) == 0
    assert "replacing the earlier clutchsim run output" in capsys.readouterr().err
    assert (out / "timeseries.csv").read_text() != "stale\n"
    # a file the user added to it makes it theirs: refused, kept
    (out / "notes.txt").write_text("mine\n")
    assert main([*RUN, "--out", str(out)]) == 2
    assert "notes.txt" in capsys.readouterr().err and (out / "notes.txt").is_file()
    # another command's output is refused too, before its benchmark runs
    (out / "notes.txt").unlink()
    assert main(["bench", "drift", "--model", "lugre", "--out", str(out), "-q"]) == 2
    assert "holds the output of `clutchsim run`" in capsys.readouterr().err


def test_a_link_to_a_directory_is_followed_never_renamed(tmp_path, capsys, fake_runs):
    target = tmp_path / "target"
    target.mkdir()
    link = tmp_path / "link"
    link.symlink_to(target, target_is_directory=True)
    for _ in range(2):            # written, then replaced through the link
        assert main([*RUN, "--out", str(link)]) == 0, capsys.readouterr().err
        assert link.is_symlink() and os.readlink(link) == str(target)
        assert (target / "summary.json").is_file()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link", "target"]


def test_a_second_command_on_the_same_directory_stops_with_the_first_ones_pid(
        tmp_path, capsys, fake_runs):
    out = tmp_path / "o"
    holder = subprocess.Popen(
        [sys.executable, "-c", textwrap.dedent("""
            import sys, time
            from clutchsim._util import claim_output_dir
            claim = claim_output_dir(sys.argv[1], "run")
            print("held", flush=True)
            time.sleep(60)
        """), str(out)], stdout=subprocess.PIPE, text=True,
        env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)})
    try:
        assert holder.stdout.readline().strip() == "held"
        assert main([*RUN, "--out", str(out)]) == 2
        err = capsys.readouterr().err
        assert f"in use by process {holder.pid}" in err and fake_runs == []
    finally:
        holder.kill()        # killed holding it: the lock goes with the process
        holder.communicate()
    assert main([*RUN, "--out", str(out)]) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["o"]


@pytest.mark.parametrize("interrupt", [KeyboardInterrupt, SystemExit])
def test_an_interrupt_while_building_leaves_the_directory_as_it_was(tmp_path, interrupt):
    from clutchsim.cli import Terminated
    out = tmp_path / "d"
    with claim_output_dir(out, "run") as claim, claim.build() as part:
        (part / "summary.json").write_text("{}")
    before = _tree(tmp_path)
    for exc in (interrupt, Terminated):
        with pytest.raises(exc), claim_output_dir(out, "run") as claim, \
                claim.build() as part:
            (part / "summary.json").write_text('{"half": 1}')
            raise exc()
        assert _tree(tmp_path) == before


def test_partial_directories_clutchsim_did_not_make_are_refused(tmp_path):
    out = tmp_path / "d"
    (tmp_path / "d.partial").mkdir()
    (tmp_path / "d.partial" / "keep.txt").write_text("x")
    with pytest.raises(OutputPathError, match="was not made by clutchsim"):
        claim_output_dir(out, "run")
    assert (tmp_path / "d.partial" / "keep.txt").is_file()
    # one left by a clutchsim that was killed (its mark inside) is removed
    (tmp_path / "d.partial" / "keep.txt").unlink()
    (tmp_path / "d.partial" / ".clutchsim-partial").write_text("123\n")
    with claim_output_dir(out, "run") as claim, claim.build() as part:
        (part / "x.json").write_text("{}")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["d"]


def test_every_file_a_run_writes_is_named_by_its_kind(tmp_path, capsys):
    """``OUTPUT_KINDS`` names the files of each kind (``--force`` refuses a user's file of
    such a name up front); a real run with figures and report writes only such names."""
    import fnmatch

    from clutchsim._util import OUTPUT_KINDS
    out = tmp_path / "o"
    assert main(["run", "--model", "coulomb-robust", "--set", "scenario.t_end=0.3", "-q",
                 "--out", str(out)]) == 0, capsys.readouterr().err
    files = read_manifest(out)["files"]
    assert "launch_coulomb-robust.png" in files and "report.html" in files
    for f in files:
        assert any(fnmatch.fnmatchcase(f, p) for p in OUTPUT_KINDS["run"]), f
    assert sorted(os.listdir(out)) == sorted([*files, MANIFEST])
