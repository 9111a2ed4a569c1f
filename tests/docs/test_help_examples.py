"""Every example of the commands' --help runs as documented (the rules: _doc_examples.py).

A file of its own, so that ``pytest -n 2 --dist loadfile`` can run it beside the docs'.
"""

import pytest
from _doc_examples import SOURCES, run_and_check


@pytest.mark.parametrize("source", [s for s in SOURCES if s.endswith("--help")])
def test_help_examples_run_as_documented(source, tmp_path):
    run_and_check(source, tmp_path)
