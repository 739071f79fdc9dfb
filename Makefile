# Two commands for a fresh machine: `make demo` and `make test` (each sets up .venv first).
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
export OPENBLAS_NUM_THREADS ?= 1
export MPLBACKEND ?= Agg
# Keep compiled bytecode (and pytest's rewritten test modules) between runs: some machines set
# PYTHONDONTWRITEBYTECODE, which makes every pytest worker and every subprocess compile vibss and the tests afresh
# (about 4 s of each worker's 8 s collection).
unexport PYTHONDONTWRITEBYTECODE

.PHONY: demo test test-quick bench bench-quick fuzz venv chromium clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -e ".[all,test]"
	touch $(STAMP)

venv: $(STAMP) chromium

# The browser test (tests/report/test_browser.py) opens the HTML report in headless Chromium: installed with
# apt-get where that exists and we are root (CI: .ci/run); elsewhere that test is skipped with its reason.
chromium:
	@if command -v chromium >/dev/null || command -v chromium-browser >/dev/null; then :; \
	elif [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null; then \
		apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium; \
	else echo "note: no chromium (apt-get install chromium as root): the browser test will be skipped"; fi

demo: $(STAMP)
	$(BIN)/vibss report --example powertrain --out demo-report
	@echo "Figures and the HTML report: demo-report/index.html"

test: $(STAMP) chromium
	$(BIN)/python -m mypy -n 2
	$(BIN)/python -m pytest -n 2 --dist worksteal -q vibss tests

# Everything but the tests marked slow (over about 4 s each); one room: pytest tests/frequency -m "not slow"
test-quick: $(STAMP) chromium
	$(BIN)/python -m pytest -n 2 --dist worksteal -q -m "not slow" vibss tests

# The adversarial suite of tests/robustness/test_random_models.py, long (1,000 random models per property, 10,000
# mutated model files; VIBSS_FUZZ_MODELS / VIBSS_FUZZ_FILES override), and the contract campaign of
# tests/robustness/test_contract_campaign.py at full size (40 models per family, up to 4 bodies;
# VIBSS_CAMPAIGN_MODELS overrides; its figures per method in campaign.jsonl); figures in docs/robustness.md
fuzz: $(STAMP)
	VIBSS_FUZZ=1 $(BIN)/python -m pytest -q -s -p no:cacheprovider --durations=0 tests/robustness/test_random_models.py
	rm -f campaign.jsonl
	VIBSS_FUZZ=1 VIBSS_CAMPAIGN_OUT=campaign.jsonl $(BIN)/python -m pytest -q -s -p no:cacheprovider --durations=0 \
		tests/robustness/test_contract_campaign.py

# `make bench QUICK=1` (or `make bench-quick`): small sizes, a few minutes; seeded like the full run
bench: $(STAMP)
	$(BIN)/python benchmarks/run_all.py $(if $(QUICK),--quick)

bench-quick: $(STAMP)
	$(BIN)/python benchmarks/run_all.py --quick

clean:
	rm -rf $(VENV) build *.egg-info .pytest_cache
