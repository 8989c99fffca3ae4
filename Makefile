# Two entry points for a new user: `make demo` and `make test`; `make docs` builds the documentation site.
# Each does all the set-up it needs on a fresh Debian machine with Python 3.
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.pdsgen-installed
TEST_STAMP := $(VENV)/.pdsgen-test-tools
DOCS_STAMP := $(VENV)/.pdsgen-docs-tools

.PHONY: demo test lint docs clean setup

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

test: $(TEST_STAMP)
	$(PY) -m pytest -q

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
