"""Helpers shared by the command line, the scenario loader and the sweeps.

* :func:`quote`: a value for an error message, shortened (a 200 KB formula is not repeated);
* :func:`atomic_write`: write a file under a temporary name and rename it;
* :func:`claim_output_dir`: the one writer of output directories (the rules below);
* :func:`check_output_file`: refuse an output file path that cannot be written *before*
  anything is simulated;
* :func:`estimate_run` / :func:`check_run_size`: the output rows, values and memory a run
  will need, refused above a limit (``--max-output-rows``) before it starts;
* :func:`check_run_count`: the same for the number of runs of a sweep (``--max-runs``).

Output directories (:func:`claim_output_dir`): clutchsim never deletes a file it did not
write.  Every output directory carries a manifest, ``.clutchsim-output.json``: the kind of
output (``run``, ``bench``, ...) and the files clutchsim wrote there.  A command may
replace a directory that is empty or holds only a previous output of its own kind (it says
so on stderr); anything else is refused before any simulation, unless ``--force``: then the
output is written beside the files clutchsim did not write, which are kept (a file of
theirs with the name of an output file is refused even so).  A symbolic link to a
directory is followed (the link is never renamed).  While a command writes a directory it
holds a lock (``.NAME.clutchsim-lock`` beside it, with its process id): a second command
for the same directory stops with "in use by process N".  The directory is built as
``NAME.partial`` and put in place when complete; a failure or an interrupt removes
``NAME.partial`` and leaves the directory as it was.
"""

from __future__ import annotations

import contextlib
import fnmatch
import json
import logging
import math
import os
import re
import shutil
import signal
import tempfile
import threading
from dataclasses import dataclass
from pathlib import Path
from typing import Self

__all__ = [
    "DEFAULT_MAX_OUTPUT_ROWS",
    "DEFAULT_MAX_RUNS",
    "MANIFEST",
    "OUTPUT_KINDS",
    "OutputDir",
    "OutputPathError",
    "ResourceError",
    "RunEstimate",
    "add_to_manifest",
    "atomic_write",
    "check_output_file",
    "check_run_count",
    "check_run_size",
    "claim_output_dir",
    "estimate_run",
    "format_bytes",
    "quote",
    "read_manifest",
    "toml_line",
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


# --------------------------------------------------------------------------- files
def _current_umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


_UMASK = _current_umask()
log = logging.getLogger("clutchsim")


@contextlib.contextmanager
def _signals_held():
    """Hold SIGINT and SIGTERM while a rename or a clean-up runs (a second Ctrl-C must not
    leave half of it done); they are delivered when the block ends.  Only the main thread
    of the interpreter receives signals, so elsewhere this does nothing."""
    if threading.current_thread() is not threading.main_thread() or \
            not hasattr(signal, "pthread_sigmask"):
        yield
        return
    held = {signal.SIGINT, signal.SIGTERM}
    old = signal.pthread_sigmask(signal.SIG_BLOCK, held)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


def atomic_write(path: str | Path, write) -> Path:
    """Write a file atomically: ``write(tmp_path)`` then rename onto ``path``.

    On any exception, Ctrl-C and SIGTERM included (the command line turns SIGTERM into an
    exception), the temporary file is removed and ``path`` is left as it was.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    if path.is_dir():
        raise IsADirectoryError(21, "is a directory, not a file", str(path))
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    os.close(fd)
    try:
        write(Path(tmp))
        os.chmod(tmp, 0o666 & ~_UMASK)   # mkstemp creates 0600; outputs are shared files
        with _signals_held():
            os.replace(tmp, path)
    except BaseException:
        with _signals_held():
            Path(tmp).unlink(missing_ok=True)
        raise
    return path


# --------------------------------------------------------------------------- outputs
#: the manifest of an output directory: {"kind", "files": [relative paths], "clutchsim"}
MANIFEST = ".clutchsim-output.json"
#: marks a directory being built (``NAME.partial``) as clutchsim's
_PARTIAL_MARK = ".clutchsim-partial"

#: kind of output -> the names (glob patterns, top level) its files may have: with
#: ``--force`` a file clutchsim did not write that has one of them is refused up front
#: (tests/cli/test_outputs.py checks that every file a command writes matches)
OUTPUT_KINDS = {
    "run": ("timeseries*.csv", "timeseries*.parquet", "summary.json", "scenario.toml",
            "quality_comparison.json", "*.png", "command.txt", "report.html"),
    "bench": ("*.png", "*_traces.csv", "bench.json", "command.txt", "report.html"),
    "durability": ("durability.csv", "durability.png", "summary.json", "command.txt",
                   "report.html"),
    "fit": ("fit.json", "traces.csv", "report.md", "fit.png", "residuals.png", "command.txt",
            "report.html"),
    "judder": ("judder.*", "judder_map.*", "frf.*", "command.txt", "report.html"),
    "demo": ("launch", "drift", "demo.json", "report.html"),
    "sweep": ("sweep.json", "chunks", "traces", "results.parquet", "*.png", "command.txt",
              "report.html"),
    "uq": ("sweep.json", "chunks", "results.parquet", "uq.json", "probabilities.csv",
           "quantiles.csv", "sensitivity.csv", "uq_*.png", "command.txt", "report.html"),
    "log": ("launch_*.csv", "launches.json", "command.txt"),
    "rt": ("plant.c", "model.h", "clutchsim_rt.h", "rt_kernel.c", "ros2.c",
           "libclutchsim_rt.so", "clutchsim_rt.fmu", "rt.json", "README.md", "command.txt"),
    "calibrate": ("calibration.json", "parameters.toml", "traces.csv", "report.md",
                  "calibration.png", "command.txt", "report.html"),
}


def read_manifest(directory) -> dict | None:
    """The manifest of an output directory; None when it has none.  Raises
    :class:`OutputPathError` when there is one that cannot be read."""
    mf = Path(directory) / MANIFEST
    if not mf.is_file():
        return None
    try:
        doc = json.loads(mf.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        raise OutputPathError(f"{str(mf)!r}: the manifest of a clutchsim output cannot be "
                              f"read ({exc})") from None
    if not (isinstance(doc, dict) and isinstance(doc.get("kind"), str)
            and isinstance(doc.get("files"), list)
            and all(isinstance(f, str) and f and not Path(f).is_absolute()
                    and ".." not in Path(f).parts for f in doc["files"])):
        raise OutputPathError(f"{str(mf)!r}: not a clutchsim output manifest (expected "
                              '{"kind": ..., "files": [paths inside the directory]})')
    return doc


def add_to_manifest(directory, names) -> None:
    """List files clutchsim has just written into an output directory in its manifest (a
    report rebuilt by ``clutchsim report``); a directory without one is left alone."""
    d = Path(directory)
    manifest = read_manifest(d)
    if manifest is None or set(names) <= set(manifest["files"]):
        return
    manifest["files"] = sorted(set(manifest["files"]) | set(names))
    atomic_write(d / MANIFEST, lambda p: p.write_text(json.dumps(manifest, indent=1)))


def _tree(directory: Path) -> set[str]:
    """Every file and directory under ``directory``, as relative POSIX paths."""
    found = set()
    for root, dirs, files in os.walk(directory):
        rel = Path(root).relative_to(directory)
        found.update((rel / n).as_posix() for n in dirs + files)
    return found


def _owned(manifest: dict | None) -> set[str]:
    """The paths a manifest says clutchsim wrote, with the directories that hold them."""
    if manifest is None:
        return set()
    owned = set()
    for f in manifest["files"]:
        p = Path(f)
        owned.add(p.as_posix())
        owned.update(q.as_posix() for q in p.parents if q != Path("."))
    return owned


def _foreign(directory: Path, manifest: dict | None) -> list[str]:
    """The entries of ``directory`` clutchsim did not write (by its manifest), sorted."""
    return sorted(_tree(directory) - _owned(manifest) - {MANIFEST})


def _examples(names: list[str], n: int = 3) -> str:
    shown = ", ".join(repr(x) for x in names[:n])
    return shown + (f" and {len(names) - n} more" if len(names) > n else "")


class OutputDir:
    """An output directory claimed by one command (:func:`claim_output_dir`): checked and
    locked; :meth:`build` writes it."""

    def __init__(self, path: Path, kind: str, force: bool, flag: str, shown: str):
        self.path, self.kind, self.force, self.flag, self.shown = path, kind, force, flag, shown
        self.partial = path.with_name(path.name + ".partial")
        self._lock_path = path.with_name(f".{path.name}.clutchsim-lock")
        self._fd: int | None = None
        self._made: list[Path] = []       # parent directories created for the lock

    # ------------------------------------------------------------------ claim
    def _refuse(self, why: str, hint: str = "") -> OutputPathError:
        return OutputPathError(f"{self.flag} {self.shown!r}: {why}" + (f"; {hint}" if hint
                                                                        else ""))

    def _in_use(self, pid: str, stale: bool = False) -> OutputPathError:
        """``stale``: the lock is a file's existence, left behind by a process killed."""
        self._unmake()
        return self._refuse(f"in use by process {pid or '?'} (another clutchsim command is "
                            "writing it)", f"wait for it to end, or choose another {self.flag}"
                            + (f" (no such process? remove {str(self._lock_path)!r})"
                               if stale else ""))

    def _lock(self) -> None:
        parent = self.path.parent
        missing = [d for d in [parent, *parent.parents] if not d.exists()]
        parent.mkdir(parents=True, exist_ok=True)
        self._made = missing       # innermost first: removed again if nothing is written
        try:
            import fcntl
        except ImportError:        # no advisory locks (Windows): the lock file's existence
            try:
                fd = os.open(self._lock_path, os.O_RDWR | os.O_CREAT | os.O_EXCL, 0o644)
            except FileExistsError:
                raise self._in_use(self._lock_path.read_text(errors="replace").strip(),
                                   stale=True) from None
            os.write(fd, f"{os.getpid()}\n".encode())
            self._fd = fd
            return
        while True:
            fd = os.open(self._lock_path, os.O_RDWR | os.O_CREAT, 0o644)
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                pid = os.read(fd, 32).decode(errors="replace").strip()
                os.close(fd)
                raise self._in_use(pid) from None
            try:   # the holder before us may have removed the file it locked: lock again
                same = os.stat(self._lock_path).st_ino == os.fstat(fd).st_ino
            except FileNotFoundError:
                same = False
            if same:
                break
            os.close(fd)
        os.ftruncate(fd, 0)
        os.write(fd, f"{os.getpid()}\n".encode())
        self._fd = fd

    def _unmake(self) -> None:
        for d in self._made:
            with contextlib.suppress(OSError):
                d.rmdir()
        self._made = []

    def __enter__(self) -> Self:
        return self

    def __exit__(self, *exc) -> None:
        self.release()

    def release(self) -> None:
        """Give up the lock (and the parent directories made for it, if still empty)."""
        if self._fd is not None:
            with _signals_held():
                try:
                    os.unlink(self._lock_path)      # still locked: no one takes it between
                    removed = True
                except OSError:
                    removed = False
                os.close(self._fd)
                self._fd = None
                if not removed:                     # an open file cannot be removed (Windows)
                    with contextlib.suppress(OSError):
                        os.unlink(self._lock_path)
        if not self.path.exists():
            self._unmake()

    def _check(self) -> None:
        """Decide, under the lock, whether this command may write the directory."""
        if self.partial.exists():
            if not (self.partial / _PARTIAL_MARK).is_file():
                raise self._refuse(f"{str(self.partial)!r} exists and was not made by "
                                   "clutchsim", f"move it away or choose another {self.flag}")
            log.info("removing %s, left by an interrupted clutchsim", self.partial)
            with _signals_held():
                shutil.rmtree(self.partial)
        if not self.path.exists():
            return
        try:
            manifest = read_manifest(self.path)
        except OutputPathError as exc:
            if not self.force:
                raise self._refuse(str(exc), f"choose another {self.flag}") from None
            manifest = None
        foreign = _foreign(self.path, manifest)
        if not foreign and manifest is None:
            return                                     # an empty directory
        if not self.force:
            if foreign:
                raise self._refuse(
                    f"the directory holds files clutchsim did not write ({_examples(foreign)})"
                    "; clutchsim never deletes them", f"choose another {self.flag}, or add "
                    "--force to write the output beside them (only clutchsim's own files "
                    "are replaced)")
            if manifest["kind"] != self.kind:
                raise self._refuse(
                    f"holds the output of `clutchsim {manifest['kind']}`, not of "
                    f"`clutchsim {self.kind}`", f"choose another {self.flag}, or add --force "
                    "to replace it")
            log.info("replacing the earlier clutchsim %s output in %s", self.kind, self.shown)
            return
        patterns = OUTPUT_KINDS[self.kind]
        clash = [top for top in sorted({f.split("/")[0] for f in foreign})
                 if any(fnmatch.fnmatchcase(top, pat) for pat in patterns)]
        if clash:
            raise self._refuse(
                f"holds {_examples(clash)}, not written by clutchsim, with the name of a "
                f"file `clutchsim {self.kind}` writes; clutchsim never overwrites it, not "
                "even with --force", f"move it away or choose another {self.flag}")
        log.info("writing the clutchsim %s output into %s beside what clutchsim did not "
                 "write there (%s; --force: kept)", self.kind, self.shown, _examples(foreign))

    # ------------------------------------------------------------------ build
    @contextlib.contextmanager
    def build(self):
        """Yield ``NAME.partial`` to write into; when the block completes, its files
        replace the directory's (only clutchsim's own files are removed, by the manifest),
        with a manifest of them.  If the block fails (Ctrl-C and SIGTERM included) the
        partial directory is removed and the directory is left as it was."""
        partial = self.partial
        partial.mkdir()
        (partial / _PARTIAL_MARK).write_text(f"{os.getpid()}\n")
        try:
            yield partial
            (partial / _PARTIAL_MARK).unlink()
            files = sorted(f for f in _tree(partial) if (partial / f).is_file())
            from ._version import __version__
            atomic_write(partial / MANIFEST, lambda p: p.write_text(json.dumps(
                {"kind": self.kind, "files": files, "clutchsim": __version__}, indent=1)))
            with _signals_held():
                self._commit()
        except BaseException:
            with _signals_held():
                shutil.rmtree(partial, ignore_errors=True)
            raise

    def _commit(self) -> None:
        path, partial = self.path, self.partial
        try:
            old = read_manifest(path) if path.is_dir() else None
        except OutputPathError:
            old = None
        foreign = _foreign(path, old) if path.is_dir() else []
        if not foreign:          # empty, or only clutchsim's files: swap atomically
            if path.exists():
                gone = Path(tempfile.mkdtemp(prefix=f".{path.name}.old-", dir=path.parent))
                os.replace(path, gone)
                try:
                    os.replace(partial, path)
                except BaseException:
                    os.replace(gone, path)          # the earlier output back in place
                    raise
                shutil.rmtree(gone, ignore_errors=True)
            else:
                os.replace(partial, path)
            return
        # beside files clutchsim did not write (--force, or added while the command ran):
        # clutchsim's own old files go, the new ones come in, nothing else is touched
        top = {f.split("/")[0] for f in foreign}
        new = sorted(os.listdir(partial))
        clash = [n for n in new if n in top and n != MANIFEST]
        if clash:
            raise self._refuse(f"{_examples(clash)} appeared while the command ran and was "
                               "not written by clutchsim: it is kept, and the output is not "
                               "written", f"move it away and run again, or choose another "
                               f"{self.flag}")
        for f in sorted(old["files"] if old else (), reverse=True):
            p = path / f
            if p.is_file() or p.is_symlink():
                p.unlink()
            with contextlib.suppress(OSError):    # a directory clutchsim made, if now empty
                for q in Path(f).parents:
                    if q != Path("."):
                        (path / q).rmdir()
        for name in new:
            os.replace(partial / name, path / name)
        partial.rmdir()


def claim_output_dir(path, kind: str, *, force: bool = False, flag: str = "--out",
                     in_place: bool = False) -> OutputDir:
    """Check and lock the output directory ``path`` of a ``kind`` of output, before any work
    is done (the rules are in this module's docstring); a context manager that releases the
    lock.  ``in_place``: a directory its command fills and resumes itself (a sweep's, whose
    store refuses a directory that is not its own): only followed, probed and locked.
    Raises :class:`OutputPathError` naming the flag, the path, the reason and the way
    out."""
    if kind not in OUTPUT_KINDS:
        raise ValueError(f"output kind {kind!r}: not one of {', '.join(OUTPUT_KINDS)}")
    if str(path).strip() == "":
        raise ValueError(f"{flag}: an empty path")
    shown = str(path)
    p = Path(path)
    if p.is_symlink():
        target = Path(os.path.realpath(p))
        if not target.is_dir():
            raise OutputPathError(f"{flag} {shown!r}: a symbolic link to "
                                  f"{str(target)!r}, which is not a directory")
        p = target                         # the output goes where the link points
    if p.exists() and not p.is_dir():
        raise OutputPathError(f"{flag} {shown!r}: exists and is not a directory")
    if p.name in ("", ".."):                  # "." or "..": the directory by its name
        p = Path(os.path.abspath(p))
    _probe(_existing_ancestor(p, flag, Path(shown)), flag, Path(shown))
    out = OutputDir(p, kind, force, flag, shown)
    out._lock()
    try:
        if not in_place:
            out._check()
    except BaseException:
        out.release()
        raise
    return out


# --------------------------------------------------------------------------- output paths
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


# --------------------------------------------------------------------------- TOML lines
#: a part of a key path: a bare or quoted name, optionally an index (``coupling[1]``)
_KEY_PART = re.compile(r'\s*(?:"([^"]*)"|([A-Za-z0-9_\-]+))(?:\[(\d+)\])?\s*(?:\.|$)')
#: a table header ``[a.b]`` or ``[[a.b]]`` (its name without the brackets)
_HEADER = re.compile(r"^\[(\[?)\s*([^\[\]]+?)\s*\]\]?$")


def _key_parts(path) -> list[tuple[str, int | None]]:
    """``[(name, index or None), ...]`` of a key path: a string ``coupling[1].friction.model``
    (a part with dots or spaces quoted: ``channels."engine speed"``) or a sequence of names
    and ``(name, index)`` pairs."""
    if not isinstance(path, str):
        return [(p, None) if isinstance(p, str) else (p[0], p[1]) for p in path]
    parts, pos = [], 0
    while pos < len(path):
        m = _KEY_PART.match(path, pos)
        if m is None or m.end() == pos:
            raise ValueError(f"not a key path: {path!r}")
        name = m.group(1) if m.group(1) is not None else m.group(2)
        parts.append((name, int(m.group(3)) if m.group(3) is not None else None))
        pos = m.end()
    return parts


def _header_name(header: str) -> str:
    """A header's dotted name with its quotes and the spaces around its dots removed."""
    return ".".join(p.strip().strip('"') for p in header.split("."))


def toml_line(text: str, path, key: str | None = None) -> int | None:
    """The 1-based line of a TOML text where the key ``path`` is set (``coupling[1].friction.
    model``, ``calibration.channels``, ``[("records", 2), "file"]``), with ``key`` one more
    part taken as it is (a channel name with dots or spaces): the one place that turns a
    key into the line an error message names.

    Each part moves on from the line reached: to its table header (``[a.b]``, or the n-th
    ``[[a.b]]`` for an index), or to a header below it (``[a.b.c]`` for the part ``b``), or
    to the line that assigns it (``b = ...``, ``"b" = ...``, also inside an inline table:
    ``{ b = ...`` or ``, b = ...``).  A part that is not written leaves the line reached
    (the table's header: the place to add it); None when not even the first part is
    written.  Comments are skipped; a top-level key is found before the first header only."""
    lines = [raw.split("#", 1)[0].strip() for raw in text.splitlines()]
    headers = []        # (line index, dotted name, is an array of tables)
    for i, line in enumerate(lines):
        m = _HEADER.match(line) if line.startswith("[") else None
        if m:
            headers.append((i, _header_name(m.group(2)), bool(m.group(1))))
    first_header = headers[0][0] if headers else len(lines)
    pos, prefix, reached = 0, "", None
    parts = _key_parts(path) + ([(key, None)] if key is not None else [])
    for name, index in parts:
        full = f"{prefix}.{name}" if prefix else name
        found = None
        if index is not None:
            arrays = [i for i, h, arr in headers if i >= pos and arr and h == full]
            if index < len(arrays):
                found = arrays[index]
        else:
            found = next((i for i, h, _arr in headers
                          if i >= pos and (h == full or h.startswith(full + "."))), None)
        if found is None:
            # a key (or an inline table / array of them) in the table reached; at the top
            # level only before the first header
            end = first_header if not prefix else next(
                (i for i, _h, _arr in headers if i > pos), len(lines))
            assign = re.compile(rf'(^|[{{,])\s*"?{re.escape(name)}"?\s*=')
            found = next((i for i in range(pos, end) if assign.search(lines[i])), None)
        if found is None:
            return reached
        pos, prefix = found, full
        reached = found + 1
    return reached
