# Two entry points for a new user: `make demo` and `make test`.
# Each does all the set-up it needs on a fresh Debian machine with Python 3.
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.pdsgen-installed
TEST_STAMP := $(VENV)/.pdsgen-test-tools

.PHONY: demo test lint clean setup

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

lint: $(STAMP)
	$(VENV)/bin/ruff check src tests bench

clean:
	rm -rf out build dist .pytest_cache
