"""Every example of README.md and docs/ runs as documented (the rules: _doc_examples.py)."""

import pytest
from _doc_examples import SOURCES, Example, _command, _cover, run_and_check


@pytest.mark.parametrize("source", [s for s in SOURCES if s.endswith(".md")])
def test_documented_examples_run_as_documented(source, tmp_path):
    run_and_check(source, tmp_path)


def test_a_command_documented_twice_runs_where_it_is_the_same_run():
    """A command line in several sources runs once, in its first source, and only where
    the two runs are the same: what it reads and writes stays inside it."""
    run = "clutchsim run examples/launch.toml --out launch/"
    read = Example("b.md:9", "import pandas", code="pandas.read_csv('launch/summary.csv')")
    sources = {
        "a.md": [_command("a.md:1", run, "")],
        "b.md": [_command("b.md:1", run, ""), read],           # read afterwards: runs
        "c.md": [_command("c.md:1", "clutchsim run x.toml --out y/", ""),
                 _command("c.md:2", run, "")],                  # nothing of it read: covered
        "g.md": [_command("g.md:1", "clutchsim sweep x.toml --out launch/runs/", ""),
                 _command("g.md:2", run, "")],                  # its folder written before
        "d.md": [_command("d.md:1", run, "# exits 1")],         # another documented exit
        "e.md": [_command("e.md:1", "clutchsim fmu launch/ --out f.fmu", ""),
                 _command("e.md:2", "clutchsim run examples/launch.toml --out g/", "")],
        "f.md": [_command("f.md:1", "clutchsim sweep --out launch/", ""),
                 _command("f.md:2", "clutchsim fmu launch/ --out f.fmu", "")],  # reads launch/
    }
    _cover(sources)
    covered = {ex.where: ex.covered.where for exs in sources.values() for ex in exs
               if ex.covered}
    assert covered == {"c.md:2": "a.md:1"}


def test_every_covered_example_names_the_same_run():
    """The documents' own coverage: each covered command has its home's arguments and
    exit status, and the home itself runs."""
    covered = [ex for exs in SOURCES.values() for ex in exs if ex.covered]
    assert covered, "no command is documented twice any more: drop the coverage rule?"
    for ex in covered:
        home = ex.covered
        assert home.argv == ex.argv and home.exit == ex.exit and home.covered is None, ex.where
