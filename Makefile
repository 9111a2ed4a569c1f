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

# The venv is made without pip and filled by scripts/venv-install.sh (uv, else pip): the
# demo's install took ~11 s where venv, ensurepip and pip took ~29 s (session 31).
$(BIN)/python:
	$(PY) -m venv --without-pip $(VENV)

$(STAMP_RUN): $(BIN)/python pyproject.toml
	if [ ! -f $(STAMP_ALL) ]; then sh scripts/venv-install.sh $(PY) $(VENV) plot; fi
	rm -f $(VENV)/.installed-run-* && touch $(STAMP_RUN)

$(STAMP_ALL): $(BIN)/python pyproject.toml
	sh scripts/venv-install.sh $(PY) $(VENV) dev compile
	rm -f $(VENV)/.installed-* && touch $(STAMP_ALL) $(STAMP_RUN)

# the demo's install writes no bytecode: the interpreter writes each module's on its first
# import.  (Compiled beside the demo at the lowest priority it cost the demo 10 s, session
# 31: both cores are busy, one with the drift test, one compiling the launch metrics.  Where
# PYTHONDONTWRITEBYTECODE is set, later processes compile their imports, ~2.5 s, until
# `make test` installs everything compiled.)
demo: $(STAMP_RUN)
	$(BIN)/clutchsim demo --out clutchsim-out/demo

test: $(STAMP_ALL)
	$(BIN)/python -m pytest -n 2 --dist loadfile --durations=15

bench: $(STAMP_ALL)
	$(BIN)/python benchmarks/core_speed.py

clean:
	rm -rf $(VENV) clutchsim-out .pytest_cache
