# Two commands do everything on a fresh machine with Python >= 3.11 and pip:
#   make demo   creates .venv, installs corneasim, runs the default scenario
#   make test   creates .venv, installs the test extras, runs pytest (one worker per core)
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin

.PHONY: demo test clean

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)

$(VENV)/.installed: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e .
	touch $@

$(VENV)/.installed-test: pyproject.toml $(VENV)/.installed
	$(BIN)/python -m pip install --quiet -e '.[test]'
	touch $@

demo: $(VENV)/.installed
	$(BIN)/corneasim run needle

test: $(VENV)/.installed-test
	$(BIN)/python -m pytest -n auto --dist loadfile

clean:
	rm -rf $(VENV) build src/*.egg-info
