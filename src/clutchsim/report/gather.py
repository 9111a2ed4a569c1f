"""Read an output directory into a :class:`ReportData` (no HTML here).

The directory is read generically: every top-level ``*.json`` (metrics, status,
parameters, solver statistics), ``*.toml`` (scenario, shown verbatim), ``*.png`` (figures,
captions from ``figures.json``), ``command.txt`` and the remaining files (listed as data).
"""

from __future__ import annotations

import datetime as _dt
import json
import shlex
import struct
from dataclasses import dataclass, field
from pathlib import Path

from .._version import __version__
from .tables import Sections, StatusEntry, Table, analyse

__all__ = ["KIND_FILES", "REPORT_NAME", "Figure", "FileEntry", "ReportData", "check_output",
           "gather"]

REPORT_NAME = "report.html"
#: JSON file name -> directory kind, when no document has a ``"kind"`` key
KIND_FILES = {"summary.json": "run", "bench.json": "bench", "sweep.json": "sweep",
              "fit.json": "fit"}
_SUBJECT_KEYS = ("name", "scenario", "benchmark", "model", "title")
_SPECIAL = {"figures.json", "command.txt", REPORT_NAME}
_PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


@dataclass(frozen=True)
class Figure:
    """A PNG to embed: file name, caption, bytes and pixel size."""

    name: str
    caption: str
    data: bytes
    width: int
    height: int


@dataclass(frozen=True)
class FileEntry:
    """A file or sub-directory listed with a relative link."""

    name: str
    size: int | None        # bytes; None for a directory
    kind: str               # "CSV", "Parquet", "directory", ...
    link: str               # relative href


@dataclass
class ReportData:
    """Everything a report shows, as plain data."""

    directory: Path
    title: str
    kind: str
    version: str
    created: str
    command: str | None = None
    status: list[StatusEntry] = field(default_factory=list)
    warnings: list[tuple[str, str]] = field(default_factory=list)
    tables: list[Table] = field(default_factory=list)
    parameters: list[Table] = field(default_factory=list)
    solver: Table | None = None
    scenarios: list[tuple[str, str]] = field(default_factory=list)
    figures: list[Figure] = field(default_factory=list)
    files: list[FileEntry] = field(default_factory=list)
    problems: list[str] = field(default_factory=list)

    @property
    def failed(self) -> list[StatusEntry]:
        return [s for s in self.status if s.ok is False]


def report_inputs(directory: Path) -> list[Path]:
    """The entries of ``directory`` a report is built from (not the report, not hidden)."""
    return sorted(p for p in directory.iterdir()
                  if p.name != REPORT_NAME and not p.name.startswith("."))


def check_output(directory: Path) -> dict:
    """The manifest of a clutchsim output directory, after checking that its JSON
    documents read (:func:`clutchsim._util.read_manifest`); a sweep's directory is known by
    its ``sweep.json``.  Raises ValueError saying what is wrong: not a clutchsim output, or
    a damaged one."""
    from .._util import MANIFEST, read_manifest
    d = Path(directory)
    manifest = read_manifest(d)
    sweep = d / "sweep.json"
    if manifest is None and sweep.is_file():
        manifest = {"kind": "sweep", "files": ["sweep.json"]}
    if manifest is None:
        raise ValueError(f"{str(d)!r} is not a clutchsim output directory (no {MANIFEST}, "
                         "the manifest that run, bench, fit, durability, judder and demo "
                         "write with --out, and no sweep.json); give a directory clutchsim "
                         "wrote")
    for name in manifest["files"]:
        p = d / name
        if p.suffix.lower() != ".json" or "/" in name:
            continue
        try:
            doc = json.loads(p.read_text(encoding="utf-8"))
        except FileNotFoundError:
            raise ValueError(f"{str(p)!r} is missing from this clutchsim {manifest['kind']} "
                             "output: re-run the command that made it") from None
        except (OSError, UnicodeDecodeError, ValueError) as exc:
            raise ValueError(f"{str(p)!r} is damaged ({exc}): re-run the command that made "
                             "this output") from None
        if isinstance(doc, dict):
            continue
        raise ValueError(f"{str(p)!r} is damaged (a JSON {type(doc).__name__}, not the "
                         "document clutchsim writes): re-run the command that made this "
                         "output")
    return manifest


def gather(directory: str | Path, *, title: str | None = None) -> ReportData:
    """Read ``directory`` into a :class:`ReportData`.

    Parameters
    ----------
    directory : str or Path
        An output directory of ``clutchsim run``/``bench``/``sweep``/``fit``.
    title : str, optional
        Overrides the title derived from the directory kind and subject.

    Raises
    ------
    FileNotFoundError
        ``directory`` does not exist.
    NotADirectoryError
        ``directory`` is a file.
    ValueError
        ``directory`` holds nothing to report on.
    """
    d = Path(directory)
    if not d.exists():
        raise FileNotFoundError(f"output directory {str(d)!r} does not exist")
    if not d.is_dir():
        raise NotADirectoryError(f"{str(d)!r} is not a directory")
    entries = report_inputs(d)
    if not entries:
        raise ValueError(f"output directory {str(d)!r} is empty: nothing to report")
    # a directory being built atomically (DIR.partial) is reported under its final name
    shown = d.with_name(d.name[:-len(".partial")]) if d.name.endswith(".partial") else d
    data = ReportData(directory=shown, title="", kind="output", version=__version__,
                      created=_dt.datetime.now().astimezone().isoformat(timespec="seconds"))
    docs = _read_json(d, entries, data)
    _from_documents(docs, data)
    data.title = title or _title(shown, docs, data.kind)
    cmd = d / "command.txt"
    if cmd.is_file():
        data.command = cmd.read_text(encoding="utf-8", errors="replace").strip()
    data.scenarios = [(p.name, p.read_text(encoding="utf-8", errors="replace"))
                      for p in entries if p.suffix.lower() == ".toml" and p.is_file()]
    data.figures = _figures(d, entries, docs.get("figures.json"), data)
    # figures of immediate sub-directories (e.g. the demo's launch/ and drift/) follow
    for sub in entries:
        if sub.is_dir():
            data.figures += _figures(sub, report_inputs(sub), None, data, prefix=f"{sub.name}/")
    data.files = _files(entries)
    return data


def _read_json(d: Path, entries, data: ReportData) -> dict:
    docs = {}
    for p in entries:
        if p.suffix.lower() != ".json" or not p.is_file():
            continue
        try:
            docs[p.name] = json.loads(p.read_text(encoding="utf-8"))
        except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
            data.problems.append(f"{p.name} could not be read: {exc}")
    return docs


def _from_documents(docs: dict, data: ReportData) -> None:
    stats_rows: list[tuple[str, dict]] = []
    for name, doc in docs.items():
        if name == "figures.json":
            continue
        sec: Sections = analyse(name, doc)
        data.tables += sec.tables
        data.parameters += sec.parameters
        data.status += sec.status
        data.warnings += sec.warnings
        stats_rows += sec.stats
        if "kind" in sec.meta and data.kind == "output":
            data.kind = str(sec.meta["kind"])
        if "command" in sec.meta and data.command is None:
            c = sec.meta["command"]
            data.command = shlex.join(map(str, c)) if isinstance(c, list) else str(c)
    if data.kind == "output":
        data.kind = next((KIND_FILES[n] for n in docs if n in KIND_FILES), "output")
    if stats_rows:
        cols = []
        for _, s in stats_rows:
            cols += [k for k in s if k not in cols]
        prefix, names = _common_prefix([w for w, _ in stats_rows])
        rows = tuple((w,) + tuple(s.get(c) for c in cols) for w, (_, s) in zip(names, stats_rows))
        data.solver = Table(prefix, tuple(cols), rows, row_label="run")


def _common_prefix(paths: list[str], sep: str = " › ") -> tuple[str, list[str]]:
    """Split the path parts all ``paths`` share: ("a › b", ["c", "d"]) from a › b › c, ..."""
    parts = [p.split(sep) for p in paths]
    n = 0
    while all(len(p) > n + 1 for p in parts) and len({p[n] for p in parts}) == 1:
        n += 1
    return sep.join(parts[0][:n]), [sep.join(p[n:]) for p in parts]


def _title(d: Path, docs: dict, kind: str) -> str:
    main = next((docs[n] for n, k in KIND_FILES.items() if k == kind and n in docs), None)
    if main is None:
        main = next(iter(docs.values()), None)
    subject = None
    if isinstance(main, dict):
        subject = next((main[k] for k in _SUBJECT_KEYS if isinstance(main.get(k), str)), None)
    subject = subject or d.resolve().name
    return f"clutchsim {kind} report: {subject}"


def _figures(d: Path, entries, captions, data: ReportData, prefix: str = "") -> list[Figure]:
    captions = captions if isinstance(captions, dict) else {}
    figs = []
    for p in entries:
        if p.suffix.lower() != ".png" or not p.is_file():
            continue
        raw = p.read_bytes()
        size = png_size(raw)
        if size is None:
            data.problems.append(f"{prefix}{p.name} is not a readable PNG image and was not "
                                 "embedded")
            continue
        cap = captions.get(p.name)
        cap = str(cap) if cap else prefix + p.stem.replace("_", " ").replace("-", " ")
        figs.append(Figure(prefix + p.name, cap, raw, *size))
    return figs


def png_size(raw: bytes) -> tuple[int, int] | None:
    """(width, height) from a PNG header, or None when ``raw`` is not a PNG."""
    if len(raw) < 33 or not raw.startswith(_PNG_MAGIC) or raw[12:16] != b"IHDR":
        return None
    w, h = struct.unpack(">II", raw[16:24])
    return (w, h) if w > 0 and h > 0 else None


_KINDS = {".csv": "CSV", ".parquet": "Parquet", ".json": "JSON", ".toml": "TOML",
          ".npz": "NumPy", ".mat": "MATLAB", ".md": "Markdown", ".txt": "text",
          ".png": "PNG (embedded)", ".html": "HTML", ".h5": "HDF5", ".nc": "netCDF"}


def _files(entries) -> list[FileEntry]:
    from urllib.parse import quote
    out = []
    for p in entries:
        if p.is_dir():
            sub = p / REPORT_NAME
            link = f"{quote(p.name)}/{REPORT_NAME}" if sub.is_file() else f"{quote(p.name)}/"
            out.append(FileEntry(p.name + "/", None, "directory", link))
        elif p.is_file():
            out.append(FileEntry(p.name, p.stat().st_size,
                                 _KINDS.get(p.suffix.lower(), p.suffix.lstrip(".") or "file"),
                                 quote(p.name)))
    data_first = ("CSV", "Parquet", "NumPy", "MATLAB", "HDF5", "netCDF")
    return sorted(out, key=lambda f: (f.kind not in data_first, f.kind == "directory", f.name))
