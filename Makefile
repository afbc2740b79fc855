# The two commands of the quick start; each sets up .venv itself.
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed

.PHONY: demo test bench clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e ".[plot,test,sweep]"
	touch $(STAMP)

demo: $(STAMP)
	$(PY) -m sim compare --scenario sudden-blockage --updates 1 --animate --out demo-output

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

clean:
	rm -rf $(VENV) demo-output benchmarks/results/*-quick.* benchmarks/results/sweeps/*-quick
