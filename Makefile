# Entry points. Each target installs what it needs from Debian's packages first (idempotent).
PRESET ?= default
BUILD := build/$(PRESET)
JOBS ?= $(shell nproc)
FUZZ_SECONDS ?= 20

.PHONY: deps deps-browser deps-test build demo test test-asan bench fuzz format install-check clean

deps:
	@bash scripts/install-deps.sh

deps-browser:
	@bash scripts/install-deps.sh --browser

deps-test:
	@bash scripts/install-deps.sh --browser --linuxcnc

build: deps
	@cmake --preset $(PRESET) >/dev/null
	@cmake --build --preset $(PRESET) -j $(JOBS)

demo: build
	./$(BUILD)/lathectl demo --out demo-out
	@echo "open demo-out/index.html"

# The fuzz smoke runs first so that ctest's summary line closes the output.
test: deps-test
	@bash scripts/fuzz-smoke.sh $(FUZZ_SECONDS)
	@cmake --preset default -DLATHECTL_HAL=ON >/dev/null
	@cmake --build --preset default -j $(JOBS)
	ctest --preset default -j $(JOBS)

test-asan: deps
	@cmake --preset asan >/dev/null
	@cmake --build --preset asan -j $(JOBS)
	ctest --preset asan -j $(JOBS)

bench: build
	./$(BUILD)/bench/lathectl_bench --benchmark_counters_tabular=true

fuzz: deps
	@bash scripts/fuzz-smoke.sh 600

format:
	clang-format -i $$(git ls-files '*.cpp' '*.hpp')

clean:
	rm -rf build demo-out
