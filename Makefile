# Two commands do everything on a fresh machine with Python >= 3.11 and pip:
#   make demo   creates .venv, installs corneasim, runs the default scenario
#   make test   creates .venv, installs the test extras, runs pytest (one worker per core)
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin

.PHONY: demo test bytecode clean

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)

$(VENV)/.installed: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e .
	touch $@

$(VENV)/.installed-test: pyproject.toml $(VENV)/.installed
	$(BIN)/python -m pip install --quiet -e '.[test]'
	touch $@

# The bytecode of corneasim's own modules, refreshed for those edited since: an editable
# install writes none, and where PYTHONDONTWRITEBYTECODE is set (as in many containers) every
# start would compile all of them from source, about 0.2 s of each run's start-up.
bytecode: $(VENV)/.installed
	$(BIN)/python -m compileall -q src

demo: $(VENV)/.installed bytecode
	$(BIN)/corneasim run needle

test: $(VENV)/.installed-test bytecode
	$(BIN)/python -m pytest -n auto --dist loadfile

clean:
	rm -rf $(VENV) build src/*.egg-info
