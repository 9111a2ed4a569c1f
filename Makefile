# The README's two commands. Both create .venv when it is missing.
PY ?= python3
VENV := .venv
BIN := $(VENV)/bin
HASH := $(shell cat pyproject.toml | cksum | cut -d' ' -f1)
# what the demo needs (clutchsim and matplotlib), and everything (the test and dev extras):
# the demo does not wait for the test tools; an install of everything serves both
STAMP_RUN := $(VENV)/.installed-run-$(HASH)
STAMP_ALL := $(VENV)/.installed-all-$(HASH)

.PHONY: demo test bench clean

# pip byte-compiles every module of every package it installs, one file at a time (11 of
# the 18 s of the demo's install, measured): both installs skip it and compile after, the
# full install on every core, the demo beside its run.
$(BIN)/python:
	$(PY) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet "pip>=21.3"

$(STAMP_RUN): $(BIN)/python pyproject.toml
	if [ ! -f $(STAMP_ALL) ]; then $(BIN)/python -m pip install --quiet --no-compile -e ".[plot]"; fi
	rm -f $(VENV)/.installed-run-* && touch $(STAMP_RUN)

# (as with pip, a file no Python reads, a package's template, is not an error)
$(STAMP_ALL): $(BIN)/python pyproject.toml
	$(BIN)/python -m pip install --quiet --no-compile -e ".[dev]"
	$(BIN)/python -m compileall -q -j 0 $(VENV)/lib > /dev/null || true
	rm -f $(VENV)/.installed-* && touch $(STAMP_ALL) $(STAMP_RUN)

# the bytecode the demo's install skipped is compiled beside the demo, on the core that
# waits while the other compiles the integrator (numba, ~25 s from an empty cache)
demo: $(STAMP_RUN)
	nice -n 19 $(BIN)/python -m compileall -q $(VENV)/lib > /dev/null 2>&1 & \
	$(BIN)/clutchsim demo --out clutchsim-out/demo; rc=$$?; wait; exit $$rc

test: $(STAMP_ALL)
	$(BIN)/python -m pytest -n 2 --dist loadfile --durations=15

bench: $(STAMP_ALL)
	$(BIN)/python benchmarks/core_speed.py

clean:
	rm -rf $(VENV) clutchsim-out .pytest_cache
