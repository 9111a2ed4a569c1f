"""The progress line: drawn only for terminals, with rate and ETA, finished by a newline."""

from __future__ import annotations

import io
import types

from clutchsim.progress import Progress, progress_for


def test_progress_line_counts_and_finishes():
    out = io.StringIO()
    bar = Progress("models", min_interval=0.0, stream=out)
    for done in range(4):
        bar(done, 3)
    text = out.getvalue()
    assert "\r[" in text and "3/3 models" in text and "ETA" in text
    assert text.endswith("\n") and text.count("\n") == 1


def test_progress_redraws_are_throttled_but_the_end_is_always_drawn():
    out = io.StringIO()
    bar = Progress("runs", min_interval=3600.0, stream=out)
    for done in range(100):
        bar(done, 100)
    bar(100, 100)
    assert out.getvalue().count("\r") == 2   # the first call and the final state


def test_no_progress_when_quiet_in_ci_or_not_a_terminal(monkeypatch):
    monkeypatch.delenv("CI", raising=False)
    assert progress_for(types.SimpleNamespace(quiet=True)) is None
    monkeypatch.setenv("CI", "true")
    assert progress_for(types.SimpleNamespace(quiet=False)) is None
    monkeypatch.delenv("CI")
    # pytest captures stderr: not a terminal
    assert progress_for(types.SimpleNamespace(quiet=False)) is None


def test_other_libraries_log_warnings_only(capsys):
    """clutchsim's own messages at INFO, a library's (pandas' NumExpr announced its
    threads on every run) only from WARNING, unless --verbose."""
    import logging

    from clutchsim.cli import main
    assert main(["models"]) == 0
    capsys.readouterr()
    logging.getLogger("numexpr.utils").info("NumExpr defaulting to 2 threads.")
    logging.getLogger("numexpr.utils").warning("a library's warning")
    logging.getLogger("clutchsim").info("clutchsim's own progress")
    err = capsys.readouterr().err
    assert "NumExpr" not in err
    assert "a library's warning" in err and "clutchsim's own progress" in err
