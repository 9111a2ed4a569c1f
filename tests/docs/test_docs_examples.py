"""Every example of README.md and docs/ runs as documented (the rules: _doc_examples.py)."""

import pytest
from _doc_examples import SOURCES, run_and_check


@pytest.mark.parametrize("source", [s for s in SOURCES if s.endswith(".md")])
def test_documented_examples_run_as_documented(source, tmp_path):
    run_and_check(source, tmp_path)
