# Entry points. Each target installs what it needs from Debian's packages first (idempotent).
PRESET ?= default
BUILD := build/$(PRESET)
JOBS ?= $(shell nproc)
FUZZ_SECONDS ?= 600

.PHONY: deps deps-browser deps-test build demo stability-map gauge-series test test-asan bench fuzz format install-check package clean

deps:
	@bash scripts/install-deps.sh

deps-browser:
	@bash scripts/install-deps.sh --browser

deps-test:
	@bash scripts/install-deps.sh --browser --linuxcnc --package --python

build: deps
	@cmake --preset $(PRESET) >/dev/null
	@cmake --build --preset $(PRESET) -j $(JOBS)

# Only what the demo runs: the program (the tests and benchmarks are make test's and make bench's).
# It says how long each phase took, so a fresh machine's time is not one opaque number.
demo:
	@t0=$$(date +%s); bash scripts/install-deps.sh; \
	t1=$$(date +%s); cmake --preset $(PRESET) >/dev/null && \
	  cmake --build --preset $(PRESET) -j $(JOBS) --target lathectl || exit $$?; \
	t2=$$(date +%s); ./$(BUILD)/lathectl demo --out demo-out; rc=$$?; t3=$$(date +%s); \
	echo "demo: dependencies $$((t1 - t0)) s, build $$((t2 - t1)) s, run $$((t3 - t2)) s"; \
	[ $$rc -eq 0 ] && echo "open demo-out/index.html (the stability map, 150 runs: make stability-map)"; exit $$rc

# The showcase of `lathectl sweep` (docs/sweep.md, "The stability map"): system B's time-domain
# chatter over feed × speed, 150 runs (19 s of CPU: about 10 s on 2 free cores), with the
# stability lobes of the same structure drawn over it. WORKERS=N to use N cores (default: all);
# a rerun finishes an interrupted map.
WORKERS ?= 0
stability-map:
	@cmake --preset $(PRESET) >/dev/null && cmake --build --preset $(PRESET) -j $(JOBS) --target lathectl
	./$(BUILD)/lathectl sweep examples/sweeps/b_single_tool_map.toml --out map-out --workers $(WORKERS)
	@echo "open map-out/report.html"

# System D's long series on LinuxCNC against lathectl run (docs/system-d-gauging.md, "Size bias
# on LinuxCNC"): PARTS parts in one session, about 4.5 s each (200: 15 minutes), not in make test.
PARTS ?= 200
gauge-series: deps-test
	@cmake --preset default -DLATHECTL_HAL=ON >/dev/null
	@cmake --build --preset default -j $(JOBS) --target lathectl lathectl_gauge lathectl_gauge_plant
	scripts/linuxcnc-gauge-series --parts $(PARTS) --install build/default \
	  --lathectl build/default/lathectl --out gauge-series-out

# The fuzz step runs first so that ctest's summary line closes the output: the committed
# regression corpus and the seed corpus replayed, then a fixed seed for a fixed number of runs
# per target (scripts/fuzz-smoke.sh); open-ended fuzzing is make fuzz.
test: deps-test
	@LATHECTL_WERROR=ON bash scripts/fuzz-smoke.sh
	@cmake --preset default -DLATHECTL_HAL=ON -DLATHECTL_PYTHON=ON -DLATHECTL_WERROR=ON >/dev/null
	@cmake --build --preset default -j $(JOBS)
	ctest --preset default -j $(JOBS)

test-asan: deps
	@cmake --preset asan >/dev/null
	@cmake --build --preset asan -j $(JOBS)
	ctest --preset asan -j $(JOBS)

bench: build
	./$(BUILD)/bench/lathectl_bench --benchmark_counters_tabular=true

# Random seeds, FUZZ_SECONDS per target, the corpus kept in build/fuzz/explore/ between runs.
fuzz: deps
	@bash scripts/fuzz-smoke.sh --explore $(FUZZ_SECONDS)

# The Debian packages lathectl, lathectl-linuxcnc and python3-lathectl → build/package/*.deb: a
# Release build with the HAL components and the Python module, Debian's hardening flags
# (dpkg-buildflags), installed under /usr; then lintian
# (fails on errors; warnings are listed in README.md).
PKG_FLAGS = -DCMAKE_CXX_FLAGS="$$(dpkg-buildflags --get CXXFLAGS) $$(dpkg-buildflags --get CPPFLAGS)" \
            -DCMAKE_EXE_LINKER_FLAGS="$$(dpkg-buildflags --get LDFLAGS)" \
            -DCMAKE_MODULE_LINKER_FLAGS="$$(dpkg-buildflags --get LDFLAGS)"
package:
	@bash scripts/install-deps.sh --linuxcnc --package
	@cmake --preset package $(PKG_FLAGS) >/dev/null
	@cmake --build --preset package -j $(JOBS)
	rm -f build/package/*.deb
	cd build/package && cpack
	lintian --fail-on error build/package/*.deb
	@ls -l build/package/*.deb

format:
	clang-format -i $$(git ls-files '*.cpp' '*.hpp')

clean:
	rm -rf build demo-out map-out
