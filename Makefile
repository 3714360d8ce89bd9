# Two commands on a fresh clone: `make demo` and `make test`. Each creates .venv itself.
# `make bench` runs every benchmark, `make bench NAME=ffbp` one (benchmarks/<name>.py).
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed

.PHONY: demo test bench clean venv docs-figures api dist

# uv installs the same releases as pip (from PyPI) in about 25 s where pip takes 1.5 min of a
# fresh machine's `make test`; pip does it if uv cannot be had. Bytecode is compiled at install:
# with PYTHONDONTWRITEBYTECODE set (as on CI machines) every process would compile what it imports.
INSTALL = ( $(PY) -m pip install --quiet uv && UV_LINK_MODE=copy $(VENV)/bin/uv pip install --quiet --compile-bytecode --python $(PY) $(1) ) \
          || $(PY) -m pip install --quiet $(1)

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(call INSTALL,-e ".[test]")
	touch $(STAMP)

venv: $(STAMP)

demo: $(STAMP)
	$(PY) -m salkit.cli.demo --out results

# Headless Chromium (Debian's package) renders the demo's pages in one test, and gdalinfo (gdal-bin)
# reads the GeoTIFF export in another; installed here where apt-get can (as root), else the first is
# skipped saying so and the second reads the file through rasterio's GDAL only.
CHROMIUM = command -v chromium >/dev/null 2>&1 || { [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1 && \
	( timeout 300 apt-get update -qq && DEBIAN_FRONTEND=noninteractive timeout 300 apt-get install -y -qq chromium gdal-bin ) \
	>/dev/null 2>&1; } || echo "note: no Chromium (apt-get install chromium): the rendered-page test will be skipped"

test: $(STAMP)
	@$(CHROMIUM)
	$(VENV)/bin/lint-imports --no-cache
	$(PY) -m pytest -q -n auto --dist loadfile --doctest-modules src/salkit tests

# The API reference from the docstrings (Sphinx, numpydoc read by napoleon), warnings as errors:
# docs/api/_build/html/index.html. CI builds it after the tests.
api: $(STAMP)
	$(call INSTALL,-e ".[docs]")
	rm -rf docs/api/generated docs/api/_build
	$(PY) -m sphinx -b html -W --keep-going -q docs/api docs/api/_build/html
	@echo "API reference: docs/api/_build/html/index.html"

# The sdist and wheel as PyPI would take them: built in isolation, checked by twine (CI runs it).
dist: $(STAMP)
	$(call INSTALL,-e ".[dist]")
	rm -rf dist
	$(PY) -m build --outdir dist . > /dev/null
	$(VENV)/bin/twine check --strict dist/*

docs-figures: $(STAMP)
	$(PY) docs/make_figures.py

bench: $(STAMP)
	$(call INSTALL,-e ".[bench]")
	$(PY) benchmarks/run_all.py $(NAME)

clean:
	rm -rf $(VENV) results dist build docs/api/_build docs/api/generated
