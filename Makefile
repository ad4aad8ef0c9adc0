# Two commands do everything on a fresh machine: `make run` and `make test`.
# VENV picks the virtual environment (CI builds the docs in a fresh one: VENV=.venv-docs make docs).
PYTHON ?= python3
VENV ?= .venv
BIN := $(VENV)/bin

.PHONY: run test lint typecheck bench docs package clean

$(BIN)/activate:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

# The stamps re-install when pyproject.toml changes.
$(VENV)/.installed: pyproject.toml | $(BIN)/activate
	$(BIN)/python -m pip install --quiet -e .
	touch $@

# Tests cover the optional backends too: numba and JAX (the engines; the core under jit/grad),
# Gymnasium, Dask, the docs extension that renders the registries (Sphinx), the web explorer
# (FastAPI, driven in tests by Playwright with the system's Chromium), Stone Soup (tracking) and
# tifffile (GeoTIFF elevation models).
$(VENV)/.installed-test: pyproject.toml | $(BIN)/activate
	$(BIN)/python -m pip install --quiet -e '.[test,fast,jax,rl,sweep,docs,web,tracking,terrain]'
	touch $@

# The numba engine's kernels compiled once, here, into numba's cache on disk (the __pycache__ folder
# next to their sources): importing targetacq.core.engines.numba_engine compiles each kernel's one
# signature, or loads it from the cache. The tests, their subprocesses and the first numba run then
# load the kernels instead of compiling them (some 25 s of CPU each). Remade when an engine source
# changes, the old cache cleared first: numba checks a kernel's own file, not the files of the
# functions it inlines (_simd.py).
ENGINE_SOURCES := $(wildcard src/targetacq/core/engines/*.py)
$(VENV)/.numba-cache: $(VENV)/.installed-test $(ENGINE_SOURCES)
	rm -f src/targetacq/core/engines/__pycache__/*.nbi src/targetacq/core/engines/__pycache__/*.nbc
	$(BIN)/python -c 'import targetacq.core.engines.numba_engine'
	touch $@

# The docs import every module they document (the API pages of targetacq.envs and targetacq.web
# too) and run the gallery: the extras those modules need come with the docs' own.
$(VENV)/.installed-docs: pyproject.toml | $(BIN)/activate
	$(BIN)/python -m pip install --quiet -e '.[docs,sweep,rl,web]'
	touch $@

run: $(VENV)/.installed
	$(BIN)/targetacq dri --example
	$(BIN)/targetacq evaluate

lint: $(VENV)/.installed-test
	$(BIN)/ruff check src tests benchmarks
	$(BIN)/ruff format --check src tests benchmarks

typecheck: $(VENV)/.installed-test
	$(BIN)/mypy

test: $(VENV)/.installed-test $(VENV)/.numba-cache lint typecheck
	$(BIN)/python -m pytest

# The documentation site, warnings as errors: build/docs/index.html.
docs: $(VENV)/.installed-docs
	$(BIN)/sphinx-build -E -W --keep-going -q -b html docs build/docs

# The sdist and the wheel, installed into a fresh venv and run from outside the repository.
package: $(VENV)/.installed-test
	bash .ci/package

bench: $(VENV)/.installed-test $(VENV)/.numba-cache
	for b in benchmarks/bench_*.py; do $(BIN)/python $$b || exit 1; done

clean:
	rm -rf $(VENV) .venv-docs build *.egg-info src/*.egg-info .pytest_cache .mypy_cache .ruff_cache .hypothesis
