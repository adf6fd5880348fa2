# The two commands of the README. Both work on a fresh machine with python3 and make.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
DOCS_STAMP := $(VENV)/.installed-docs
# one BLAS thread: the machines are 2-core and shared; threaded BLAS only adds contention
export OPENBLAS_NUM_THREADS := 1
export OMP_NUM_THREADS := 1

.PHONY: run test lint format bench reference docs clean

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

$(STAMP): pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet -e ".[test,sweep]"
	touch $(STAMP)

$(DOCS_STAMP): pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet -e ".[docs]"
	touch $(DOCS_STAMP)

run: $(STAMP)
	$(BIN)/python -m hairbed demo
	$(BIN)/python -m hairbed figures --out figures

test: $(STAMP)
	$(BIN)/ruff check src tests benchmarks
	$(BIN)/ruff format --check src tests benchmarks
	$(BIN)/python -m pytest -q
	# the kernels once more as plain Python (coverage of the compiled code's source)
	NUMBA_DISABLE_JIT=1 $(BIN)/python -m pytest -q -p no:cacheprovider \
		tests/test_kernels_elliptic.py tests/test_kernels_weak.py tests/test_jit.py \
		tests/test_kernels_python.py

lint: $(STAMP)
	$(BIN)/ruff check src tests benchmarks

format: $(STAMP)
	$(BIN)/ruff format src tests benchmarks
	$(BIN)/ruff check --fix src tests benchmarks

bench: $(STAMP)
	$(BIN)/python benchmarks/bench_solve.py

# Regenerate the mpmath reference data of the tests (slow; run on demand).
reference: $(STAMP)
	$(BIN)/python tests/reference/generate_reference.py

# The documentation site (docs/_build/html), warnings as errors. The figure gallery is drawn
# during the build into docs/_generated (redrawn when a source file is newer).
docs: $(DOCS_STAMP)
	$(BIN)/sphinx-build -W --keep-going -b html docs docs/_build/html

clean:
	rm -rf $(VENV) build *.egg-info src/*.egg-info .pytest_cache .ruff_cache docs/_build docs/_generated
