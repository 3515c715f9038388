# rangekit front door. `make demo` and `make test` install what is missing
# (Debian packages), configure, build and run; see README.md.
BUILD ?= build
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
FUZZ_SECONDS ?= 30
FUZZ_RUNS ?= 10000000
CMAKE_FLAGS ?=

# `make build` and `make demo` need only the build dependencies and build no
# tests; the targets below also install the test tools and build the tests.
WITH_TESTS ?= OFF
test bench bench-web hardware tidy lint consumer package format-check: WITH_TESTS = ON
DEPS_KIND = $(if $(filter ON,$(WITH_TESTS)),test,build)

SOURCES := $(shell git ls-files '*.cpp' '*.hpp' 2>/dev/null)

.PHONY: all deps configure build test demo asan tsan hardware fuzz fuzz-long fuzz-build bench bench-web lint format format-check tidy \
  consumer package clean

all: build

deps:
	@bash scripts/install-deps.sh $(DEPS_KIND)

configure: deps
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRANGEKIT_TESTS=$(WITH_TESTS) \
	  -DRANGEKIT_BENCH=$(WITH_TESTS) $(CMAKE_FLAGS) >/dev/null

build: configure
	@cmake --build $(BUILD) -j$(JOBS)

test: build
	@ctest --test-dir $(BUILD) --output-on-failure -j$(JOBS)

# The sensor service on a site of emulators (an LS5, a ULS, a bus of four ULS units) for a
# minute (DEMO_SECONDS=0: until Ctrl-C); it prints the dashboard's address to open in a browser.
DEMO_SECONDS ?= 60
demo: build
	@./$(BUILD)/rangekit serve --demo --duration $(DEMO_SECONDS)

# Sanitizer builds keep line tables only (-g1): reports still name file and line, and the
# build takes about a quarter less time (server.cpp under TSan: 79-103 s against 110-143 s
# with -g), which keeps CI well inside its 90 minutes.
SANITIZER_DEBUG_INFO = -g1

# Same tests with AddressSanitizer + UndefinedBehaviorSanitizer (CI runs this too).
asan:
	@bash scripts/install-deps.sh test
	@cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="$(SANITIZER_DEBUG_INFO)" \
	  -DRANGEKIT_SANITIZE=ON -DRANGEKIT_BENCH=OFF >/dev/null
	@cmake --build build-asan -j$(JOBS)
	@ctest --test-dir build-asan --output-on-failure -j$(JOBS)

# Same tests with ThreadSanitizer: the drivers' reader threads, capture writer and emulator runtimes.
tsan:
	@bash scripts/install-deps.sh test
	@cmake -S . -B build-tsan -DCMAKE_BUILD_TYPE=RelWithDebInfo \
	  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 $(SANITIZER_DEBUG_INFO) -DNDEBUG" -DRANGEKIT_TSAN=ON -DRANGEKIT_BENCH=OFF >/dev/null
	@cmake --build build-tsan -j$(JOBS)
	@ctest --test-dir build-tsan --output-on-failure -j$(JOBS)

# The opt-in hardware tier against real sensors: RANGEKIT_ULS_PORT, RANGEKIT_LS5_PORT, ...
# (tests/hardware/hardware_env.hpp); every test skips when its variable is unset.
hardware: build
	@./$(BUILD)/rangekit_hardware_tests

# libFuzzer targets (clang 14). `make fuzz`: each runs FUZZ_SECONDS on its seed corpus
# (the short run). `make fuzz-long`: each to FUZZ_RUNS (10^7) executions, hours in all
# (docs/reliability.md has the rates). FUZZ_TARGETS="a b" runs only those.
fuzz-build:
	@bash scripts/install-deps.sh test
	@cmake -S . -B build-fuzz -DCMAKE_CXX_COMPILER=clang++-14 -DRANGEKIT_FUZZ=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
	@cmake --build build-fuzz -j$(JOBS)

fuzz: fuzz-build
	@bash scripts/run-fuzz.sh build-fuzz/fuzzers $(FUZZ_SECONDS)

fuzz-long: fuzz-build
	@bash scripts/run-fuzz.sh build-fuzz/fuzzers 0 $(FUZZ_RUNS)

bench: build
	@./$(BUILD)/rangekit_bench

# The dashboard's frame-rate and heap figures: an LS5 at 1 kHz on its live plot for 60 s in
# headless chromium (web/tests/fps.bench.mjs; docs/dashboard.md, "Benchmark"). Needs only the CLI.
bench-web: configure
	@cmake --build $(BUILD) --target rangekit -j$(JOBS)
	@cd $(BUILD)/web && RANGEKIT_CLI=$(abspath $(BUILD))/rangekit RANGEKIT_SCREENSHOTS=$(abspath $(BUILD))/screenshots \
	  node tests/fps.bench.mjs

# tests/consumer built against `cmake --install` of this build (find_package and
# pkg-config) and against the source tree (add_subdirectory), then run.
consumer: build
	@bash scripts/check-consumer.sh $(BUILD)

# The .deb (CPack) of this build; installed with dpkg, run, checked and removed.
package: build
	@bash scripts/check-package.sh $(BUILD)

lint: format-check tidy

format:
	@clang-format -i $(SOURCES)

format-check: deps
	@clang-format --dry-run --Werror $(SOURCES) && echo "clang-format: clean"

# clang-tidy over the library and CLI sources, in parallel (run-clang-tidy ships with clang-tidy).
tidy: configure
	@run-clang-tidy -p $(BUILD) -quiet -j $(JOBS) '$(CURDIR)/src/.*\.cpp$$' > $(BUILD)/clang-tidy.log 2>&1 \
	  && echo "clang-tidy: clean" || { grep -E 'error:|warning:' $(BUILD)/clang-tidy.log | sort -u; exit 1; }

clean:
	@rm -rf $(BUILD) build-asan build-tsan build-fuzz
