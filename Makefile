# planar-sym: read this as the table of contents of the project's chores.
PYTHON ?= python3
VENV   ?= .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed

.PHONY: help venv derive derive-check build browser test test-fast demo bench mutate docs lint clean

help:  ## this list
	@grep -E '^[a-z-]+:.*## ' $(MAKEFILE_LIST) | sed -E 's/:.*## /\t/'

venv: $(STAMP)  ## virtual environment with the package (editable) and every extra

# the install compiles the C helpers and the built-in robots (setup.py): again when they change
$(STAMP): pyproject.toml constraints.txt setup.py planar_sym/model/_fastcall.c \
		planar_sym/dynamics/_integrate.c planar_sym/motion/_newton.c \
		$(wildcard generated/*/manifest.json)
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q -c constraints.txt -e '.[derive,test,bench,cluster,docs,notebook,mutate]'
	touch $@

derive: $(STAMP)  ## re-derive every built-in robot into generated/ (deterministic, atomic)
	$(PY) -m derive

derive-check: $(STAMP)  ## re-derive only robots whose generated/ is stale
	$(PY) -m derive --if-stale

build: $(STAMP)  ## compile the generated C of every robot into the cache
	$(PY) -m planar_sym build

browser:  ## Debian's Chromium, for the page test (does nothing when it is there; needs root)
	.ci/install-browser

# two worker processes (pytest-xdist): CI has two cores, and the suite takes 8 minutes on them
# instead of 11 on one
test: $(STAMP) browser  ## the whole test suite (the browser test must run, not skip)
	PLANAR_SYM_REQUIRE_BROWSER=1 $(PY) -m pytest -q -n 2

test-fast: $(STAMP)  ## tests without the slow re-derivation checks
	$(PY) -m pytest -q -n 2 -m "not slow"

demo: derive-check build  ## every scenario, animation and robot drawing into results/ (index: results/README.md)
	$(PY) -m planar_sym demo --out results

bench: $(STAMP)  ## benchmarks vs Pinocchio, MuJoCo, lambdify and a C floor -> BENCHMARKS.md (~20 min; its first line says how long the last run took)
	$(PY) -m benchmarks

# TARGET: a module or folder under planar_sym/ listed in mutation/targets.toml (several: spaces)
mutate: $(STAMP)  ## mutation testing: make mutate TARGET=planar_sym/dynamics -> MUTATION.md (not in test)
	@test -n "$(TARGET)" || { $(PY) -m mutation --list; echo "usage: make mutate TARGET=..."; exit 2; }
	$(PY) -m mutation $(TARGET)

# tests/test_docs_examples.py runs every example of the pages; docs/hooks.py fills in the generated
# parts (BENCHMARKS.md's tables, every command's --help, the file formats' fields)
docs: $(STAMP)  ## the documentation site (tutorials, how-to, reference, API, background) into site/ (mkdocs --strict; open site/index.html)
	$(PY) -m mkdocs build --strict --site-dir site

lint: $(STAMP)  ## ruff on the sources (generated/ excluded)
	$(PY) -m pip install -q ruff && $(PY) -m ruff check planar_sym derive tests benchmarks examples mutation

clean:  ## remove build outputs (not the committed generated/)
	rm -rf build dist *.egg-info results .pytest_cache site .mutation
	$(MAKE) -s -C examples/c clean
