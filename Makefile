# leopod: two commands.
#   make run   set up .venv, install leopod, run the default campaign end to end (offline);
#              the report is results/<campaign>/report.html
#   make test  set up .venv, install leopod, run the test suite
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
CORES  ?= 2
CONFIG ?= config/config.yaml

.PHONY: run test setup lint bench clean

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)

$(VENV)/.installed: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e ".[test]"
	$(BIN)/python -m leopod.dynamics.compiled    # compile and cache the force model once
	# bytecode of the editable sources (pip compiles only installed packages): every job
	# process imports leopod to hand its job to the warm worker (~10 ms less per job)
	$(BIN)/python -m compileall -q src/leopod
	touch $@

setup: $(VENV)/.installed

run: setup
	$(BIN)/snakemake --cores $(CORES) --configfile $(CONFIG)
	@report=$$($(BIN)/python -c "from leopod.workflow.config import load_campaign; \
	from leopod.workflow.layout import Layout; \
	print(Layout.of(load_campaign(*'$(CONFIG)'.split())).report)") && \
	$(BIN)/snakemake --cores $(CORES) --configfile $(CONFIG) --report $$report && \
	echo "report: $$report"

test: setup
	$(BIN)/python -m pytest

lint: setup
	$(BIN)/snakemake --lint --configfile $(CONFIG)

bench: setup
	$(BIN)/python benchmarks/ingest_quality.py

clean:
	rm -rf results resources logs .snakemake
