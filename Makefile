# Two commands on a fresh clone: `make demo` and `make test`. Each creates .venv itself.
# `make bench` runs every benchmark, `make bench NAME=ffbp` one (benchmarks/<name>.py).
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed

.PHONY: demo test bench clean venv docs-figures

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet -e ".[test]"
	touch $(STAMP)

venv: $(STAMP)

demo: $(STAMP)
	$(PY) -m salkit.cli.demo --out results

test: $(STAMP)
	$(VENV)/bin/lint-imports --no-cache
	$(PY) -m pytest -q -n auto --dist loadfile --doctest-modules src/salkit tests

docs-figures: $(STAMP)
	$(PY) docs/make_figures.py

bench: $(STAMP)
	$(PY) -m pip install --quiet -e ".[bench]"
	$(PY) benchmarks/run_all.py $(NAME)

clean:
	rm -rf $(VENV) results
