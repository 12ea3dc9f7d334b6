# Quick start: `make demo` (venv, install, a real run on the embedded default) and `make test`.
PYTHON ?= python3
VENV ?= .venv
PY := $(VENV)/bin/python
EXTRAS ?= test,planners,plots,rl,tensorboard,gui,cluster,fast,jax
comma := ,
STAMP := $(VENV)/.installed-$(subst $(comma),-,$(EXTRAS))

.PHONY: install demo test bench lint clean

$(STAMP): pyproject.toml
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[$(EXTRAS)]'
	touch $(STAMP)

install: $(STAMP)

demo: install
	$(VENV)/bin/ocplus demo

test: install
	$(PY) -m pytest

bench: install
	$(PY) experiments/bench_sim.py

clean:
	rm -rf $(VENV) build *.egg-info
