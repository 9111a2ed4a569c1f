"""Every documented example runs as documented (so the docs cannot rot): the examples,
how they run and the checks of their claims; ``test_docs_examples.py`` (README, docs/) and
``test_help_examples.py`` (``--help``) run them.

Sources, found by parsing (nothing is listed by hand):

* ``README.md`` and ``docs/**/*.md``: every ```python block, every line of another code
  block that begins with ``clutchsim`` (or ``$ clutchsim``), continued over lines that end
  in ``\\``, and every inline code span that is a command with an option
  (`` `clutchsim run x.toml --out d/` ``; a bare `` `clutchsim run` `` names a command);
* each command's ``--help`` epilog (``clutchsim --help`` and ``clutchsim CMD --help``): the
  indented lines of its ``examples:`` section that begin with ``clutchsim``.

A line that begins with ``usage:`` is a synopsis, not an example, and is not run.

The examples of one source run in document order in one fresh temporary directory that
holds a copy of ``examples/`` (and ``../shared`` linked where it exists), so an example may
name a file of ``examples/`` or one that an earlier example of the same source wrote.  They
run in one fresh interpreter: the Python blocks as written (later blocks use names of
earlier ones), each command through ``clutchsim.cli.main``, the function the ``clutchsim``
entry point calls (in-process, so that the compiled kernels load once per source), between
the blocks that precede and follow it.

Expected exit status: 0, unless the example's comment states another, as ``exit 1`` /
``exits 1`` / ``exit status 1`` in its trailing ``#`` comment or in the comment lines
directly above it in the same block.

Sizes: an example runs as written, except that ``--samples N`` is capped at
:data:`MAX_SAMPLES` and ``--cycles N`` at :data:`MAX_CYCLES` (the run is the same command with
fewer Monte-Carlo samples or duty cycles; the claim checks below still hold for it).

Claims: where an example's comment claims a behaviour, :data:`CLAIMS` checks it on what the
example wrote (e.g. "stick-slip": the rig's speed sticks near 0 and slips well above it).

Examples that read the shared data sets (``${CLUTCHSIM_SHARED}``) are skipped, each named,
when the shared directory is absent.

One run per command line: a command written the same in several sources (``clutchsim fmu
examples/launch.toml ... --out launch.fmu`` is in README.md, docs/fmu.md, ``clutchsim
--help`` and ``clutchsim fmu --help``) runs in its *home*, the first source that has it
(README.md, then docs/ in path order, then the epilogs, ``clutchsim --help`` last), and
the others name that run instead of repeating it (:func:`_cover`).  Only where that is the
same run: the same arguments, the same documented exit status, no claim to check, neither
run reading what an earlier example of its source wrote (no argument that an earlier
example names), and nothing later in the source that skips it reading what it writes (no
example naming its output) -- each source runs in a fresh directory of the same contents,
so such a command does the same thing in both.
"""

from __future__ import annotations

import argparse
import json
import re
import shlex
import shutil
import subprocess
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pytest

from clutchsim.cli import build_parser
from clutchsim.data import shared_dir

ROOT = Path(__file__).resolve().parents[2]
FILES = sorted([ROOT / "README.md", *(ROOT / "docs").rglob("*.md")])
FENCE = re.compile(r"^```(\w*)\s*$")
INLINE = re.compile(r"`(clutchsim [^`]*)`")
EXIT = re.compile(r"#.*?\bexit(?:s| status)? (\d+)\b")
#: size caps of the test run (see the module docstring)
MAX_SAMPLES = 40
MAX_CYCLES = 20
#: seconds one command may take before the test fails it as hanging
TIMEOUT_S = 600
#: seconds the examples of one source may take together
SOURCE_TIMEOUT_S = 1800


@dataclass
class Example:
    """One documented example: a command line (``argv``) or a Python block (``code``)."""

    where: str                   # file:line or "clutchsim CMD --help"
    text: str                    # as written (continuations joined)
    argv: list[str] | None = None
    code: str | None = None
    exit: int = 0
    comment: str = ""            # the comment next to it (claims and exit status)
    skip: str | None = None
    covered: Example | None = None   # the same run in an earlier source (see _cover)
    results: dict = field(default_factory=dict)

    @property
    def runs(self) -> bool:
        """Does it run in its own source (not skipped, not run in another)?"""
        return not self.skip and self.covered is None


def _command(where: str, text: str, comment: str) -> Example:
    code, _, trailing = text.partition(" #") if " #" in text else (text, "", "")
    comment = f"{comment} #{trailing}" if trailing else comment
    argv = shlex.split(code)
    exit_ = EXIT.search(comment)
    return Example(where, text, argv=argv, exit=int(exit_.group(1)) if exit_ else 0,
                   comment=comment)


def _commands_in_lines(lines, where) -> list[Example]:
    """Commands in the lines of a code block or an epilog (``where(i)`` names line i)."""
    out, above, i = [], "", 0
    while i < len(lines):
        line = lines[i].strip()
        line = line.removeprefix("$ ")
        if line.startswith("#"):
            above = f"{above} {line}"
        elif line.startswith("clutchsim"):
            start = i
            while line.endswith("\\") and i + 1 < len(lines):
                i += 1
                line = line[:-1].rstrip() + " " + lines[i].strip()
            out.append(_command(where(start), line, above))
            above = ""
        else:
            above = ""
        i += 1
    return out


def _markdown(path: Path) -> list[Example]:
    rel = path.relative_to(ROOT)
    lines = path.read_text(encoding="utf-8").splitlines()
    out, i = [], 0
    while i < len(lines):
        fence = FENCE.match(lines[i])
        if not fence:
            para = [i]      # inline spans of a paragraph (they may break over lines)
            while i + 1 < len(lines) and lines[i + 1].strip() and not FENCE.match(lines[i + 1]):
                i += 1
                para.append(i)
            text = " ".join(lines[j] for j in para)
            for span in INLINE.findall(text):
                if " -" in span:
                    out.append(_command(f"{rel}:{para[0] + 1}", span, text))
            i += 1
            continue
        start, body = i, []
        i += 1
        while i < len(lines) and not lines[i].startswith("```"):
            body.append(lines[i])
            i += 1
        if fence.group(1) == "python":
            out.append(Example(f"{rel}:{start + 1}", "\n".join(body), code="\n".join(body)))
        else:
            out += _commands_in_lines(body, lambda j, s=start: f"{rel}:{s + 2 + j}")
        i += 1
    return out


def _epilogs():
    parser = build_parser()
    subs = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    for name, p in [("", parser), *sorted(subs.choices.items())]:
        where = f"clutchsim {name} --help".replace("  ", " ")
        text = (p.epilog or "").split("examples:", 1)
        lines = text[1].split("\n\n", 1)[0].splitlines() if len(text) == 2 else []
        yield where, _commands_in_lines(lines, lambda j, w=where: w)


def _sources():
    for path in FILES:
        found = _markdown(path)
        if found:
            yield str(path.relative_to(ROOT)), found
    # the top-level epilog last: its examples are the commands' own (they run in theirs)
    yield from sorted(_epilogs(), key=lambda item: item[0] == "clutchsim --help")


def _words(ex: Example) -> set[str]:
    """The words of an example, to tell which files it may name."""
    return set(re.findall(r"[\w./-]+", ex.code if ex.code is not None else " ".join(ex.argv)))


def _outputs(ex: Example) -> set[str]:
    """What a command writes and a later example may read: its ``--out`` value."""
    argv = ex.argv or []
    return {argv[k + 1].rstrip("/") for k, a in enumerate(argv[:-1]) if a == "--out"}


def _files(words: set[str]) -> set[str]:
    """The words that may name a file or folder: with a ``/`` or an extension, not a
    number, not a file of ``examples/`` (never written: each source has its own copy)."""
    out = set()
    for w in words:
        if w.startswith(("-", "examples/")) or re.fullmatch(r"[\d.e+-]+", w):
            continue
        if "/" in w or re.search(r"\.[A-Za-z]\w*$", w):
            out.add(w.rstrip("/"))
    return out


def _overlap(a: set[str], b: set[str]) -> bool:
    """Does a path of ``a`` name one of ``b``, or a file in it, or the folder it is in?"""
    return any(x == y or x.startswith(y + "/") or y.startswith(x + "/") for x in a for y in b)


def _reads_earlier(examples: list[Example], i: int) -> bool:
    """May command ``i`` read what an earlier example of its source wrote (name a file or
    folder that an earlier example names)?"""
    own = _files(_words(examples[i]))
    return any(_overlap(own, _files(_words(e))) for e in examples[:i])


def _read_later(examples: list[Example], i: int) -> bool:
    """May a later example of its source read what command ``i`` writes (name its
    ``--out``)?"""
    outs = _outputs(examples[i])
    return any(_overlap(outs, _files(_words(e))) for e in examples[i + 1:])


def _same_run(a: Example, b: Example) -> bool:
    """Do two examples of the same arguments expect the same, with no claim to check?"""
    return a.exit == b.exit and not any(p in a.comment or p in b.comment for p in CLAIMS)


def _cover(sources: dict[str, list[Example]]) -> None:
    """Mark each command that runs, the same, in an earlier source (see the module
    docstring): its ``covered`` is that run's example."""
    homes: dict[tuple, tuple[Example, list[Example], int]] = {}
    for examples in sources.values():
        for i, ex in enumerate(examples):
            if ex.argv is None:
                continue
            home = homes.get(tuple(ex.argv))
            if home is None:
                homes[tuple(ex.argv)] = (ex, examples, i)
            elif (_same_run(home[0], ex) and not _reads_earlier(home[1], home[2])
                  and not _reads_earlier(examples, i) and not _read_later(examples, i)):
                ex.covered = home[0]


def _sized(argv: list[str]) -> list[str]:
    caps = {"--samples": MAX_SAMPLES, "--cycles": MAX_CYCLES}
    out = list(argv)
    for k, v in enumerate(out[:-1]):
        if v in caps and int(out[k + 1]) > caps[v]:
            out[k + 1] = str(caps[v])
    return out


def _needs_shared(ex: Example) -> bool:
    text = ex.code or ""
    for arg in ex.argv or []:
        f = ROOT / arg
        if arg.endswith(".toml") and f.is_file():
            text += f.read_text(encoding="utf-8")
    return "${CLUTCHSIM_SHARED}" in text or "shared_dir()" in text


# -- claims -------------------------------------------------------------------------------

def _out_path(ex: Example, cwd: Path) -> Path | None:
    if ex.argv and "--out" in ex.argv:
        return cwd / ex.argv[ex.argv.index("--out") + 1]
    names = re.findall(r"""["']([\w./-]+\.csv)["']""", ex.code or "")
    return cwd / names[0] if names else None


def _csv(path: Path) -> dict[str, np.ndarray]:
    import pandas as pd
    table = pd.read_csv(path)
    return {c.split(" [")[0].split("[")[0].strip(): table[c].to_numpy() for c in table}


def _stick_slip(ex: Example, cwd: Path):
    """The rig sticks (|v| below 1 % of its peak) and slips (above 30 % of it), each for at
    least 10 % of the time, in at least two separate slips (not one start-up creep)."""
    path = _out_path(ex, cwd)
    assert path is not None and path.is_file(), "a stick-slip example writes its traces"
    cols = _csv(path)
    t, v = cols["time"], np.abs(cols["v"] if "v" in cols else cols["omega"])
    dt = np.diff(t)
    vmax = v.max()
    assert vmax > 0, "the rig never moves"
    stuck, slipping = v[:-1] < 0.01 * vmax, v[:-1] > 0.3 * vmax
    phase = np.where(stuck, -1, np.where(slipping, 1, 0))
    phase = phase[phase != 0]
    slips = int(np.sum((phase[1:] == 1) & (phase[:-1] == -1)))
    frac = [dt[m].sum() / (t[-1] - t[0]) for m in (stuck, slipping)]
    assert frac[0] > 0.1 and frac[1] > 0.1 and slips >= 2, (
        f"no stick-slip: stuck {frac[0]:.0%} and slipping {frac[1]:.0%} of the time, "
        f"{slips} stick-to-slip transitions (peak |v| {vmax:.3g})")


def _locks_up(ex: Example, cwd: Path):
    """A sweep whose runs lock up: most rows (>= 90 %) completed with a lock-up time."""
    import pandas as pd
    table = pd.read_parquet(_out_path(ex, cwd) / "results.parquet")
    locked = (table["status"] == "completed") & table["lockup_time_s"].notna()
    assert locked.mean() >= 0.9, f"only {locked.sum()} of {len(table)} runs lock up"


def _naive_stopped(ex: Example, cwd: Path):
    """The naive model is stopped by chatter detection, the other models complete (the
    demo's point; also a run's with the naive model)."""
    out = _out_path(ex, cwd)
    demo = out / "demo.json"
    if demo.is_file():
        doc = json.loads(demo.read_text())
        launch = doc["launch"]
        # the demo report's Parameters section: the clutch of each compared model
        for name in launch:
            assert doc["parameters"][f"clutch ({name})"]["friction.model"]["value"] == name
        assert 'id="parameters"' in (out / "report.html").read_text(encoding="utf-8")
    else:
        launch = json.loads((out / "summary.json").read_text())["models"]
    assert launch["coulomb-naive"]["outcome"] == "chatter", launch["coulomb-naive"]
    assert all(m["completed"] for n, m in launch.items() if n != "coulomb-naive")


def _end_of_life(ex: Example, cwd: Path):
    """A durability study that reaches the end of life, reported with its criterion."""
    summary = json.loads((_out_path(ex, cwd) / "summary.json").read_text())
    assert summary["outcome"] == "end_of_life", summary["outcome"]
    eol = summary["end_of_life"]
    assert summary["life_cycles"] == eol["cycle"] and eol["criterion"], eol


#: phrase in an example's comment -> the check of what it wrote
CLAIMS = {
    "stick-slip": _stick_slip,
    "Monte Carlo": _locks_up,
    "chatter detection stops the naive": _naive_stopped,
    "end of life": _end_of_life,
}

SOURCES = dict(_sources())
_cover(SOURCES)


# -- running ------------------------------------------------------------------------------

DRIVER = """\
import contextlib, faulthandler, io, json, sys, time
from clutchsim.cli import main as __doc_main__
def __doc_cli__(i):
    argv = json.loads(sys.argv[1])[i]
    t0 = time.perf_counter()
    err = io.StringIO()
    faulthandler.dump_traceback_later({timeout}, exit=True)   # a hang: traceback, exit
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err):
        try:
            rc = __doc_main__(argv[1:])
        except SystemExit as exc:
            rc = 0 if exc.code is None else exc.code
    faulthandler.cancel_dump_traceback_later()
    with open("examples_done.jsonl", "a", encoding="utf-8") as f:
        f.write(json.dumps({{"i": i, "rc": rc, "wall_s": time.perf_counter() - t0,
                            "stderr": err.getvalue()[-2000:]}}) + "\\n")
"""


def _run_source(examples: list[Example], cwd: Path) -> tuple[subprocess.CompletedProcess, dict]:
    """Run in ``cwd``, a checkout's stand-in: ``examples/`` copied, ``../shared`` linked."""
    shutil.copytree(ROOT / "examples", cwd / "examples")
    if shared_dir().is_dir():
        (cwd.parent / "shared").symlink_to(shared_dir().resolve(), target_is_directory=True)
    script, cli = [DRIVER.format(timeout=TIMEOUT_S)], []
    for ex in examples:
        if not ex.runs:
            continue
        if ex.code is not None:
            script.append(ex.code)
        else:
            script.append(f"__doc_cli__({len(cli)})")
            cli.append(_sized(ex.argv))
    done = subprocess.run([sys.executable, "-c", "\n".join(script), json.dumps(cli)],
                          cwd=cwd, capture_output=True, text=True,
                          timeout=SOURCE_TIMEOUT_S, check=False)
    log = cwd / "examples_done.jsonl"
    rows = [json.loads(r) for r in log.read_text().splitlines()] if log.is_file() else []
    return done, {r["i"]: r for r in rows}


def run_and_check(source: str, tmp_path: Path):
    """Run the examples of ``source`` (a key of :data:`SOURCES`) and check each one's exit
    status and claims; skip, naming them, those that need the absent shared data."""
    examples = SOURCES[source]
    have_shared = shared_dir().is_dir()
    for ex in examples:
        if not have_shared and _needs_shared(ex):
            ex.skip = f"shared data not available ({shared_dir()}; set CLUTCHSIM_SHARED)"
    t0 = time.perf_counter()
    tmp_path = tmp_path / "repo"
    tmp_path.mkdir()
    done, rows = _run_source(examples, tmp_path)
    failures, k = [], 0
    for ex in examples:
        if not ex.runs or ex.code is not None:
            continue
        row = rows.get(k)
        k += 1
        if row is None:
            failures.append(f"{ex.where}: {ex.text}\n  not reached")
        elif row["rc"] != ex.exit:
            failures.append(f"{ex.where}: {ex.text}\n  exit {row['rc']} (documented: "
                            f"{ex.exit}) after {row['wall_s']:.1f} s\n  {row['stderr']}")
        else:
            for phrase, check in CLAIMS.items():
                if phrase in ex.comment:
                    try:
                        check(ex, tmp_path)
                    except AssertionError as exc:
                        failures.append(f"{ex.where}: {ex.text}\n  claims {phrase!r}: {exc}")
    if done.returncode != 0:
        failures.append(f"Python blocks of {source}: exit {done.returncode}\n"
                        f"{done.stderr[-3000:]}")
    else:
        for ex in examples:
            for phrase, check in CLAIMS.items():
                if ex.code is not None and not ex.skip and phrase in ex.code:
                    try:
                        check(ex, tmp_path)
                    except AssertionError as exc:
                        failures.append(f"{ex.where}: claims {phrase!r}: {exc}")
    print(f"\n{source}: {len(examples)} examples in {time.perf_counter() - t0:.1f} s")
    cli = [ex for ex in examples if ex.code is None and ex.runs]
    for k, ex in enumerate(cli):
        if k in rows:
            print(f"  exit {rows[k]['rc']} {rows[k]['wall_s']:6.1f} s  {ex.text[:110]}")
    for ex in examples:
        if ex.covered:
            print(f"  run in {ex.covered.where}: {ex.text[:100]}")
    assert not failures, "\n".join(failures)
    skipped = [f"{ex.where}: {ex.skip}" for ex in examples if ex.skip]
    if skipped:
        pytest.skip("; ".join(skipped))
