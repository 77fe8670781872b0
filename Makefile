# Quick start: `make demo` (set up + run the vault example), `make test` (set up + lint + tests).
PYTHON ?= python3
VENV   ?= .venv
BIN    := $(VENV)/bin
OUT    ?= out

.PHONY: setup demo test lint bench clean

$(BIN)/ccu: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e ".[dev]"
	@touch $(BIN)/ccu

setup: $(BIN)/ccu

demo: setup
	$(BIN)/ccu info examples/vault.toml
	$(BIN)/ccu deploy examples/vault.toml --out $(OUT)/vault
	$(BIN)/ccu path examples/vault.toml --steps 12 --out $(OUT)/vault-path
	@echo ""
	@echo "Demo finished. Files written:"
	@echo "  $(OUT)/vault/structure.json        (the deployed vault, SPEC section 4 contract)"
	@echo "  $(OUT)/vault/structure.obj         (deployed plates, OBJ)"
	@echo "  $(OUT)/vault/structure.compas.json (COMPAS meshes)"
	@echo "  $(OUT)/vault-path/path.csv         (alpha, span, rise, crease planarity per state)"
	@echo "  $(OUT)/vault-path/states/          (one structure file per state)"

lint: setup
	$(BIN)/ruff check src tests benchmarks
	$(BIN)/ruff format --check src tests benchmarks

test: setup lint
	$(BIN)/python -m pytest -q

bench: setup
	$(BIN)/python benchmarks/bench_deploy.py

clean:
	rm -rf $(VENV) $(OUT) .pytest_cache .ruff_cache .hypothesis build src/*.egg-info
