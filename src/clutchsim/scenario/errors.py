"""The one error a bad scenario raises: file, key path, line, what is wrong."""

from __future__ import annotations

import re
from pathlib import Path

__all__ = ["ScenarioError", "find_line"]


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


_PART = re.compile(r"([A-Za-z0-9_\-]+)(?:\[(\d+)\])?")


def find_line(text: str, key_path: str) -> int | None:
    """Line number (1-based) where ``key_path`` (e.g. ``coupling[1].friction.model``) is set.

    Walks the TOML text: each path part moves to its table header (the n-th ``[[part]]``
    for arrays of tables) or to its ``part =`` line after the current position.
    """
    lines = text.splitlines()
    pos = 0
    parts = [m.groups() for m in _PART.finditer(key_path)]
    prefix = ""
    for name, index in parts:
        found = None
        full = f"{prefix}.{name}" if prefix else name
        if index is not None:
            count = -1
            for i in range(pos, len(lines)):
                if lines[i].strip().startswith(f"[[{full}]]"):
                    count += 1
                    if count == int(index):
                        found = i
                        break
            if found is None:   # inline array: find the key, stay there
                found = _key_line(lines, pos, name)
        else:
            for i in range(pos, len(lines)):
                s = lines[i].strip()
                if s in (f"[{full}]", f"[[{full}]]") or s.startswith(f"[{full}]"):
                    found = i
                    break
            if found is None:
                found = _key_line(lines, pos, name)
        if found is None:
            return pos + 1 if pos else None
        pos = found
        prefix = full
    return pos + 1


def _key_line(lines, start, name):
    pat = re.compile(rf"(^|[\s{{,]){re.escape(name)}\s*=")
    for i in range(start, len(lines)):
        if pat.search(lines[i].split("#", 1)[0]):
            return i
    return None
