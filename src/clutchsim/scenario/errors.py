"""The one error a bad scenario raises: file, key path, line, what is wrong."""

from __future__ import annotations

from pathlib import Path

__all__ = ["ScenarioError"]


class ScenarioError(ValueError):
    """A mistake in a scenario file.

    The message reads ``<file>:<line>: <key path>: <problem>`` (the line is omitted when it
    cannot be found), or ``<file>: <key path>: <problem> (from --set ITEM)`` for a value
    given on the command line.  Attributes ``file``, ``key``, ``line`` and ``origin`` (the
    ``--set`` item, or ``None``) hold the parts.
    """

    def __init__(self, problem: str, *, file: str | Path | None = None, key: str = "",
                 line: int | None = None, origin: str | None = None):
        self.file = str(file) if file is not None else "<scenario>"
        self.key = key
        self.line = line
        self.problem = problem
        self.origin = origin
        where = self.file + (f":{line}" if line else "")
        tail = f" (from --set {origin})" if origin else ""
        super().__init__(f"{where}: {key + ': ' if key else ''}{problem}{tail}")
