"""``build_report``: gather an output directory and write ``report.html`` atomically."""

from __future__ import annotations

import os
from pathlib import Path

from .._util import atomic_write
from .gather import REPORT_NAME, gather
from .html import render

__all__ = ["build_report"]


def build_report(out_dir: str | Path, *, title: str | None = None) -> Path:
    """Write ``out_dir/report.html``: one self-contained page about the directory.

    Parameters
    ----------
    out_dir : str or Path
        An output directory (``clutchsim run``/``bench``/``sweep``/``fit``, or any
        directory holding JSON, TOML, PNG and data files).
    title : str, optional
        Page title; by default derived from the directory kind and subject.

    Returns
    -------
    Path
        The report path.  The file is written under a temporary name and renamed, so a
        reader never sees half a report.

    Raises
    ------
    FileNotFoundError, NotADirectoryError, ValueError
        ``out_dir`` is missing, is a file, or holds nothing to report on.
    """
    data = gather(out_dir, title=title)
    page = render(data)
    return atomic_write(Path(out_dir) / REPORT_NAME, lambda p: _write(Path(p), page))


def _write(path: Path, page: str) -> None:
    path.write_text(page, encoding="utf-8")
    os.chmod(path, 0o644)      # the temporary file is private; a report is for reading
