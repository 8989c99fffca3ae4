# Two entry points for a new user: `make demo` and `make test` (`make check`, its quick subset); `make docs`
# builds the documentation site.
# Each does all the set-up it needs on a fresh Debian machine with Python 3.
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.pdsgen-installed
TEST_STAMP := $(VENV)/.pdsgen-test-tools
DOCS_STAMP := $(VENV)/.pdsgen-docs-tools

.PHONY: demo test check lint docs clean setup

setup: $(STAMP)

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[test,pds4,s3]'
	@$(PY) -c "import glymur, sys; sys.exit(0 if glymur.lib.openjp2.OPENJP2 else 1)" 2>/dev/null \
	  || sh tools/install-openjpeg.sh
	touch $@

# The tests also compare with GDAL's command-line tools and render pages in Chromium.
$(TEST_STAMP): $(STAMP) tools/install-test-tools.sh
	sh tools/install-test-tools.sh
	touch $@

demo: $(STAMP)
	$(VENV)/bin/pdsgen demo out/demo

# The whole suite, on both cores of a 2-core machine (pytest-xdist: each worker takes a test file
# at a time, so a file's shared fixtures are made once): about 2,000 tests, about 6 minutes on 2
# quiet cores, longer on a busy machine. `make check` runs a representative subset in under 2.
TEST_RUN := $(PY) -m pytest -q -n 2 --dist loadfile
test: $(TEST_STAMP)
	@echo "make test: the whole suite, about 2,000 tests, about 6 minutes on 2 quiet cores (make check: under 2 minutes)"
	$(TEST_RUN)

# The quick check: the README walk-through, every kind of product byte for byte, the same bytes on
# another day, the validator on its genuine corpus and NASA's PDS4 suite, the architecture, lint.
QUICK := tests/test_docs_walkthrough.py tests/test_products_unchanged.py tests/test_reproducible.py \
	tests/test_validate_corpus.py tests/test_validate_genuine.py tests/test_pds4_parity.py \
	tests/test_architecture.py tests/test_lint.py
check: $(TEST_STAMP)
	@echo "make check: a representative subset of the suite, under 2 minutes on 2 cores (make test: all of it)"
	$(TEST_RUN) $(QUICK)

# The documentation site from docs/ into build/site/ (mkdocs.yml). Strict: a warning - a
# link to a page or anchor that does not exist, a page left out of the navigation - fails.
$(DOCS_STAMP): $(STAMP)
	$(PY) -m pip install --quiet -e '.[docs]'
	touch $@

docs: $(DOCS_STAMP)
	$(VENV)/bin/mkdocs build --strict --clean

lint: $(STAMP)
	$(VENV)/bin/ruff check src tests bench

clean:
	rm -rf out build dist .pytest_cache
