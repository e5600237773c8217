# Two commands on a fresh machine: `make demo` and `make test`.
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed

.PHONY: demo test slow fuzz corpus lint format bench docs clean

$(STAMP): pyproject.toml
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e ".[test,viz]"
	touch $(STAMP)

demo: $(STAMP)
	$(VENV)/bin/origami-cad demo -o out

test: $(STAMP)
	$(VENV)/bin/ruff check .
	$(VENV)/bin/ruff format --check .
	$(PY) -m pytest -q -n auto --dist loadfile

# the tests marked slow (make test leaves them out; each keeps a fast check there): the
# paper task's ten recorded runs and its whole search at 180 deg, the commands' slow
# baseline cases (tests/test_commands_baseline.py)
slow: $(STAMP)
	$(PY) -m pytest -q -n auto --dist loadfile -m slow

# a longer, random fuzz of the readers (the suite runs a small fixed budget of each test):
# FUZZ_EXAMPLES inputs per test; `make fuzz FUZZ_EXAMPLES=5000` for a night
FUZZ_EXAMPLES ?= 1000
fuzz: $(STAMP)
	ORIGAMI_FUZZ_EXAMPLES=$(FUZZ_EXAMPLES) $(PY) -m pytest -q -n 0 \
		tests/test_fuzz_readers.py tests/test_hostile_readers.py tests/test_api_hostile_all.py \
		tests/test_api_probe.py

# the whole chain (check, fold, fabricate, plan-route, simulate) on every public pattern of
# tests/data/corpus.toml, as a table (docs/patterns.md shows the last one)
corpus: $(STAMP)
	mkdir -p out
	$(PY) tests/corpus.py --markdown out/corpus.md --docs docs/patterns.md

format: $(STAMP)
	$(VENV)/bin/ruff format .
	$(VENV)/bin/ruff check --fix .

bench: $(STAMP)
	$(PY) -m pip install --quiet -e ".[mkl]"
	$(PY) benchmarks/run.py

# the user guide, its gallery (pictures drawn from examples/ by the build, docs/hooks) and an
# API reference generated from the docstrings, into out/site; .ci/run builds it after the tests
MKDOCS_FLAGS ?=
docs: $(STAMP)
	$(PY) -m pip install --quiet -e ".[docs]"
	$(VENV)/bin/mkdocs build --strict $(MKDOCS_FLAGS) -f docs/mkdocs.yml -d ../out/site

clean:
	rm -rf out .pytest_cache .ruff_cache
