# The two commands of the README. Both work on a fresh machine with python3 and make.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
DOCS_STAMP := $(VENV)/.installed-docs
BENCH_STAMP := $(VENV)/.installed-bench
# one BLAS thread: the machines are 2-core and shared; threaded BLAS only adds contention
export OPENBLAS_NUM_THREADS := 1
export OMP_NUM_THREADS := 1
# pytest workers (pytest-xdist), one per core of the 2-core machines; whole files per worker
TEST_WORKERS ?= 2

.PHONY: run test chromium lint format bench reference docs clean

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

$(STAMP): pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet -e ".[test,sweep,app]"
	touch $(STAMP)

$(DOCS_STAMP): pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet -e ".[docs]"
	touch $(DOCS_STAMP)

run: $(STAMP)
	$(BIN)/python -m hairbed demo
	$(BIN)/python -m hairbed figures --out figures

test: $(STAMP) chromium
	$(BIN)/ruff check src tests benchmarks
	$(BIN)/ruff format --check src tests benchmarks
	$(BIN)/mypy
	$(BIN)/python -m pytest -q -n $(TEST_WORKERS) --dist loadfile --durations=15
	# the kernels once more as plain Python (coverage of the compiled code's source)
	NUMBA_DISABLE_JIT=1 $(BIN)/python -m pytest -q -p no:cacheprovider \
		tests/test_kernels_elliptic.py tests/test_kernels_weak.py tests/test_jit.py \
		tests/test_kernels_python.py tests/test_kernels_spectral.py tests/test_kernels_dynamics.py

# Debian's Chromium for the browser tests of the explorer (tests/test_explorer_browser.py),
# installed when missing and possible (root with apt-get); otherwise those tests skip, saying so.
chromium:
	@if [ -x /usr/bin/chromium ] || [ -n "$$HAIRBED_CHROMIUM" ]; then :; \
	elif [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then \
		echo "installing Debian's chromium for the browser tests (apt-get install chromium)"; \
		apt-get install -y -q chromium >/dev/null 2>&1 \
		|| (apt-get update -q >/dev/null 2>&1 && apt-get install -y -q chromium >/dev/null 2>&1) \
		|| echo "could not install chromium: the browser tests will skip"; \
	else \
		echo "no /usr/bin/chromium (apt-get install chromium): the browser tests will skip"; \
	fi

lint: $(STAMP)
	$(BIN)/ruff check src tests benchmarks

format: $(STAMP)
	$(BIN)/ruff format src tests benchmarks
	$(BIN)/ruff check --fix src tests benchmarks

# the bench extra (PyElastica); offline it is skipped, and so is bench_pyelastica.py
$(BENCH_STAMP): pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet -e ".[bench]" \
		|| echo "could not install the bench extra (pyelastica): bench_pyelastica.py will skip"
	touch $(BENCH_STAMP)

bench: $(STAMP) $(BENCH_STAMP)
	$(BIN)/python benchmarks/bench_solve.py
	$(BIN)/python benchmarks/bench_pyelastica.py

# Regenerate the mpmath reference data of the tests (slow: tens of minutes; run on demand).
reference: $(STAMP)
	$(BIN)/python tests/reference/generate_reference.py
	$(BIN)/python tests/reference/generate_corners.py
	$(BIN)/python tests/reference/generate_cases.py
	$(BIN)/python tests/reference/generate_derivatives.py
	$(BIN)/python tests/reference/generate_folds.py
	$(BIN)/python tests/reference/generate_loaded.py
	$(BIN)/python tests/reference/generate_pillar.py
	$(BIN)/python tests/reference/generate_porous.py
	$(BIN)/python tests/reference/generate_wall_law.py

# The documentation site (docs/_build/html), warnings as errors. The figure gallery is drawn
# during the build into docs/_generated (redrawn when a source file is newer).
docs: $(DOCS_STAMP)
	$(BIN)/sphinx-build -W --keep-going -b html docs docs/_build/html

clean:
	rm -rf $(VENV) build *.egg-info src/*.egg-info .pytest_cache .ruff_cache docs/_build docs/_generated
