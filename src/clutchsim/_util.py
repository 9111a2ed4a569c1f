"""Helpers shared by the command line, the scenario loader and the sweeps.

* :func:`quote`: a value for an error message, shortened (a 200 KB formula is not repeated);
* :func:`check_output_dir` / :func:`check_output_file`: refuse an output path that cannot be
  written *before* anything is simulated;
* :func:`estimate_run` / :func:`check_run_size`: the output rows, values and memory a run
  will need, refused above a limit (``--max-output-rows``) before it starts;
* :func:`check_run_count`: the same for the number of runs of a sweep (``--max-runs``).
"""

from __future__ import annotations

import math
import os
import tempfile
from dataclasses import dataclass
from pathlib import Path

__all__ = [
    "DEFAULT_MAX_OUTPUT_ROWS",
    "DEFAULT_MAX_RUNS",
    "OutputPathError",
    "ResourceError",
    "RunEstimate",
    "check_output_dir",
    "check_output_file",
    "check_run_count",
    "check_run_size",
    "estimate_run",
    "format_bytes",
    "quote",
]

#: most output rows of one run (``--max-output-rows``): 500,000 rows of a 70-signal launch
#: are ~0.3 GB of arrays and ~1 GB of CSV
DEFAULT_MAX_OUTPUT_ROWS = 500_000
#: most runs of one sweep (``--max-runs``)
DEFAULT_MAX_RUNS = 100_000

#: bytes per output value: the float64 arrays, the result and the frame built from it
_MEMORY_PER_VALUE = 3 * 8
#: bytes per output value on disk: CSV text (~%.17g) and Parquet
_DISK_PER_VALUE = 24 + 8


class OutputPathError(ValueError):
    """An output path that cannot be written (a file in the way, no permission, ...)."""


class ResourceError(ValueError):
    """A run or sweep larger than the limits (raise the limit with the flag named)."""


def quote(value, limit: int = 60) -> str:
    """``repr(value)``, cut to ``limit`` characters with its full length said."""
    text = repr(value)
    if len(text) <= limit:
        return text
    size = len(value) if isinstance(value, (str, bytes)) else len(text)
    return f"{text[:limit]}... ({size:,} characters)"


def format_bytes(n: float) -> str:
    """``1.2 GB``-style size (decimal units)."""
    for unit, scale in (("TB", 1e12), ("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if n >= scale:
            return f"{n / scale:.3g} {unit}"
    return f"{int(n)} B"


# --------------------------------------------------------------------------- outputs
def _probe(directory: Path, flag: str, path: Path) -> None:
    """Create and remove a temporary directory in ``directory`` (the one real test of
    writability: permissions, read-only file systems, /proc)."""
    try:
        os.rmdir(tempfile.mkdtemp(prefix=".clutchsim-probe-", dir=directory))
    except OSError as exc:
        raise OutputPathError(f"{flag} {str(path)!r}: cannot write in {str(directory)!r} "
                              f"({exc.strerror}); choose another {flag}") from None


def _existing_ancestor(path: Path, flag: str, shown: Path) -> Path:
    """The nearest existing ancestor of ``path``; a file in the way is an error."""
    parent = path.parent if str(path.parent) else Path(".")
    while not parent.exists():
        if parent == parent.parent:
            break
        parent = parent.parent
    if not parent.is_dir():
        raise OutputPathError(f"{flag} {str(shown)!r}: {str(parent)!r} is a file, not a "
                              "directory")
    return parent


def check_output_dir(path, flag: str = "--out") -> Path:
    """Refuse an output directory that cannot be created (before any work is done).

    The directory is built as ``PATH.partial`` beside ``PATH``, so the nearest existing
    ancestor must be writable.  Raises :class:`OutputPathError` naming the flag, the path
    and the reason.
    """
    p = Path(path)
    if str(path).strip() == "":
        raise ValueError(f"{flag}: an empty path")
    if p.exists() and not p.is_dir():
        raise OutputPathError(f"{flag} {str(path)!r}: exists and is not a directory")
    _probe(_existing_ancestor(p, flag, p), flag, p)
    return p


def check_output_file(path, flag: str = "--out") -> Path:
    """Refuse an output file path that is a directory or cannot be written."""
    p = Path(path)
    if str(path).strip() == "":
        raise ValueError(f"{flag}: an empty path")
    if p.is_dir() or str(path).endswith(("/", os.sep)):
        raise OutputPathError(f"{flag} {str(path)!r}: is a directory; give a file name, "
                              f"e.g. {str(p / 'out.csv')!r}")
    _probe(_existing_ancestor(p, flag, p), flag, p)
    return p


# --------------------------------------------------------------------------- sizes
@dataclass(frozen=True)
class RunEstimate:
    """What one run will produce, estimated before it starts.

    ``rows`` is exact for a fixed output grid (``dt_out > 0``) and an upper bound (the
    step budget, capped by the output limit) when every step is stored.
    """

    rows: int
    signals: int
    fixed_grid: bool
    min_steps: int

    @property
    def values(self) -> int:
        return self.rows * (self.signals + 1)

    @property
    def memory_bytes(self) -> float:
        return float(self.values) * _MEMORY_PER_VALUE

    @property
    def disk_bytes(self) -> float:
        return float(self.values) * _DISK_PER_VALUE

    def describe(self) -> str:
        how = "" if self.fixed_grid else "at most "
        return (f"{how}{self.rows:,} output rows x {self.signals + 1} signals: about "
                f"{format_bytes(self.memory_bytes)} in memory and "
                f"{format_bytes(self.disk_bytes)} on disk")


def estimate_run(span: float, options, signals: int) -> RunEstimate:
    """Output rows and the least number of steps of a run over ``span`` seconds.

    ``options`` is a :class:`~clutchsim.core.SolverOptions`; ``signals`` the number of
    columns besides time (states, inputs and outputs).
    """
    span = float(span)
    if options.dt_out > 0:
        rows = math.floor(min(span / options.dt_out, 1e18)) + 1
        fixed = True
    else:
        rows = min(options.max_steps, options.max_output) + 1
        fixed = False
    min_steps = math.ceil(min(span / options.h_max, 1e18)) if options.h_max > 0 else 1
    return RunEstimate(rows=int(rows), signals=int(signals), fixed_grid=fixed,
                       min_steps=int(min_steps))


def check_run_size(est: RunEstimate, options, *, what: str, max_rows: int,
                   flag: str = "--max-output-rows", where: str = "solver.dt_out"):
    """Refuse a run whose output or step count is beyond the limits; return the options
    to run it with (the output store capped at ``max_rows`` when every step is stored).

    Raises :class:`ResourceError` naming the estimate, the limit and the remedies.
    """
    from dataclasses import replace
    if est.min_steps > options.max_steps:
        raise ResourceError(
            f"{what}: the span needs at least {est.min_steps:,} steps of h_max = "
            f"{options.h_max:g} s, more than the step budget max_steps = "
            f"{options.max_steps:,}: the run would stop unfinished. Shorten t_end, raise "
            "h_max or raise max_steps")
    if est.fixed_grid:
        if est.rows > max_rows:
            raise ResourceError(
                f"{what}: {est.describe()}, above the limit of {max_rows:,} rows. Raise "
                f"{where}, shorten t_end, or raise the limit with {flag} N")
        return options
    if options.max_output > max_rows:
        # every accepted step is stored: the count is not known before the run, so the
        # store is capped (the result then says so in its warnings)
        return replace(options, max_output=max(2, int(max_rows)))
    return options


def check_run_count(n: int, max_runs: int, *, what: str = "sweep",
                    flag: str = "--max-runs") -> None:
    """Refuse a sweep of more than ``max_runs`` runs (before the design is built)."""
    if n > max_runs:
        raise ResourceError(f"{what}: {n:,} runs is above the limit of {max_runs:,} runs "
                            f"(the design alone would take {format_bytes(n * 8.0)} per key); "
                            f"use fewer points or samples, or raise the limit with {flag} N")
