# Two entry points for a fresh machine (see README):
#   make demo   create .venv, install everything, run the main job on the built-in default
#   make test   create .venv, install everything, lint (ruff, mypy baseline), run the whole test suite
PYTHON ?= python3
VENV   ?= .venv
BIN     = $(VENV)/bin
STAMP   = $(VENV)/.installed

.PHONY: demo test lint install clean bench

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[test,test-gpl]'
	touch $(STAMP)

install: $(STAMP)

demo: $(STAMP)
	$(BIN)/imil demo --out demo-output

lint: $(STAMP)
	$(BIN)/ruff check impedance_mil tests benchmarks examples scripts
	$(BIN)/ruff format --check impedance_mil tests benchmarks examples scripts
	$(BIN)/python scripts/mypy_baseline.py

test: lint
	bash scripts/install-browser.sh || echo "make: chromium not installed; browser tests skip (and fail under CI=true)"
	$(BIN)/python -m pytest -q -n 2 tests

bench: $(STAMP)
	for f in benchmarks/*.py; do $(BIN)/python $$f || exit 1; done

clean:
	rm -rf $(VENV) demo-output
