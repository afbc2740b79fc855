# The two commands of the quick start; each sets up .venv itself.
# Python: the first of python3, python3.13 ... python3.10 whose version Taichi 1.7 ships wheels for (3.10-3.13 here).
SUPPORTED := import sys; sys.exit(not (3, 10) <= sys.version_info[:2] <= (3, 13))
PYTHON ?= $(shell for p in python3 python3.13 python3.12 python3.11 python3.10; do \
	command -v $$p >/dev/null 2>&1 && $$p -c '$(SUPPORTED)' 2>/dev/null && { echo $$p; break; }; done)
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed

.PHONY: demo test bench clean

$(STAMP): pyproject.toml
	@test -n "$(PYTHON)" || { echo "tdp needs Python 3.10-3.13 (Taichi 1.7 ships wheels for those); none of python3, python3.13, python3.12, python3.11, python3.10 is one" >&2; exit 1; }
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e ".[plot,test,sweep]"
	touch $(STAMP)

demo: $(STAMP)
	$(PY) -m sim compare --scenario sudden-blockage --updates 1 --cost-scaling-factor 3 --inflation-radius 0.8 --animate \
		--out demo-output

test: $(STAMP)
	$(PY) -m pytest -q

bench: $(STAMP)
	$(PY) -m benchmarks.kernel
	$(PY) -m benchmarks.convergence
	$(PY) -m benchmarks.blockage
	$(PY) -m benchmarks.paper
	$(PY) -m benchmarks.worlds
	$(PY) -m benchmarks.budget
	$(PY) -m benchmarks.sweep
	$(PY) -m benchmarks.predict
	$(PY) -m benchmarks.warehouse
	$(PY) -m benchmarks.equal_time
	$(PY) -m benchmarks.costs
	$(PY) -m benchmarks.startup

clean:
	rm -rf $(VENV) demo-output benchmarks/results/*-quick.* benchmarks/results/sweeps/*-quick benchmarks/results/smoke-quick
