# rangekit front door. `make demo` and `make test` install what is missing
# (Debian packages), configure, build and run; see README.md.
BUILD ?= build
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
FUZZ_SECONDS ?= 30
FUZZ_RUNS ?= 10000000
FUZZ_LONG_SECONDS ?= 3600
CMAKE_FLAGS ?=

# `make build` and `make demo` need only the build dependencies and build no
# tests; the targets below also install the test tools and build the tests.
WITH_TESTS ?= OFF
test bench bench-scale bench-web hardware tidy lint consumer package format-check clone-check: WITH_TESTS = ON
DEPS_KIND = $(if $(filter ON,$(WITH_TESTS)),test,build)

SOURCES := $(shell git ls-files '*.cpp' '*.hpp' 2>/dev/null)

.PHONY: all deps configure build test test-quick demo asan asan-build tsan tsan-build hardware fuzz fuzz-long fuzz-build bench bench-scale bench-web lint format format-check tidy \
  consumer package clone-check clean

all: build

deps:
	@bash scripts/install-deps.sh $(DEPS_KIND)

# Debug info is line tables only (-g1): backtraces, sanitizer reports and gdb's breakpoints
# name file and line, and the build takes about a quarter less time than with -g.
# DEBUG_INFO=-g gives gdb the variables too (docs/development.md).
DEBUG_INFO ?= -g1

configure: deps
	@bash scripts/configure.sh $(BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo \
	  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 $(DEBUG_INFO) -DNDEBUG" -DRANGEKIT_TESTS=$(WITH_TESTS) \
	  -DRANGEKIT_BENCH=$(WITH_TESTS) $(CMAKE_FLAGS)

build: configure
	@cmake --build $(BUILD) -j$(JOBS)

# Tests spend most of their time waiting on emulated serial lines and timers (a -j2 run
# used 94 s of CPU in 318 s), but the emulators must answer within the drivers' deadlines:
# at three and four per core, with the service's hostile-client tests added, loaded runs
# missed them (a bus scan heard a unit twice, a bus unit did not answer in 1 s). So ctest
# runs two per core, as the sanitizer runs do; a browser test runs alone.
TEST_JOBS ?= $(shell echo $$(( $(JOBS) * 2 )))
# A test that hangs fails after this many seconds, named, instead of holding the run to
# CI's limit. The slowest test takes under 140 s under a sanitizer on a loaded machine.
TEST_TIMEOUT ?= 600
CTEST = ctest --output-on-failure --timeout $(TEST_TIMEOUT)

test: build
	@$(CTEST) --test-dir $(BUILD) -j$(TEST_JOBS)

# The tests labelled quick (CMakeLists.txt): no broker, browser or Python, and not the web
# tests that load the CPU on purpose or the full bus scan; 30 s on two cores, for use while
# working. Without those, four per core keep their deadlines: a run used 21 s of CPU in 30 s,
# and passed beside two busy loops.
QUICK_TEST_JOBS ?= $(shell echo $$(( $(JOBS) * 4 )))
test-quick: build
	@$(CTEST) --test-dir $(BUILD) -j$(QUICK_TEST_JOBS) -L quick

# The sensor service on a site of emulators (an LS5, a ULS, a bus of four ULS units) for a
# minute (DEMO_SECONDS=0: until Ctrl-C); it prints the dashboard's address to open in a browser.
DEMO_SECONDS ?= 60
demo: build
	@./$(BUILD)/rangekit serve --demo --duration $(DEMO_SECONDS)

test-quick: WITH_TESTS = ON

# Under the sanitizers the tests use the CPU more (a -j4 ASan run: 263 s, where -j8 took
# longer), so they run two per core.
SANITIZER_TEST_JOBS ?= $(shell echo $$(( $(JOBS) * 2 )))

# Same tests with AddressSanitizer + UndefinedBehaviorSanitizer (CI runs this too). The
# sanitizer builds compile the libraries in unity batches as well: 28 % less compiler time
# for the ASan libraries (291 s of CPU instead of 404 s).
# asan-build and tsan-build only build: CI compiles them while the default build's tests run.
asan: asan-build
	@$(CTEST) --test-dir build-asan -j$(SANITIZER_TEST_JOBS)
asan-build:
	@bash scripts/install-deps.sh test
	@bash scripts/configure.sh build-asan -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="$(DEBUG_INFO)" \
	  -DRANGEKIT_SANITIZE=ON -DRANGEKIT_BENCH=OFF -DRANGEKIT_UNITY_SOURCES=ON $(CMAKE_FLAGS)
	@cmake --build build-asan -j$(JOBS)

# Same tests with ThreadSanitizer: the drivers' reader threads, capture writer, hub, faces and
# emulator runtimes. Only the test binaries whose code runs threads are built and run; these
# test single-threaded code (codecs, firmware models run by hand, file checks), where TSan
# has nothing to look at: uls, ls5, ls5_emulator, docs, architecture, alloc, hardware.
# -O1, the least ThreadSanitizer's manual asks for: g++ compiled src/hub/hub.cpp in 24 %
# less time than at -O2.
TSAN_TESTS = cli core hub ls5_driver modbus mqtt record sim sinks uls_driver uls_emulator web
empty :=
TSAN_LABELS = $(subst $(empty) $(empty),|,$(strip $(TSAN_TESTS)))
tsan: tsan-build
	@$(CTEST) --test-dir build-tsan -j$(SANITIZER_TEST_JOBS) -L '^binary\.($(TSAN_LABELS))$$'
tsan-build:
	@bash scripts/install-deps.sh test
	@bash scripts/configure.sh build-tsan -DCMAKE_BUILD_TYPE=RelWithDebInfo \
	  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 $(DEBUG_INFO) -DNDEBUG" -DRANGEKIT_TSAN=ON -DRANGEKIT_BENCH=OFF \
	  -DRANGEKIT_UNITY_SOURCES=ON $(CMAKE_FLAGS)
	@cmake --build build-tsan -j$(JOBS) --target rangekit $(TSAN_TESTS:%=rangekit_%_tests)

# The opt-in hardware tier against real sensors: RANGEKIT_ULS_PORT, RANGEKIT_LS5_PORT, ...
# (tests/hardware/hardware_env.hpp); every test skips when its variable is unset.
hardware: build
	@./$(BUILD)/rangekit_hardware_tests

# libFuzzer targets (clang 14). `make fuzz`: each runs FUZZ_SECONDS on its seed corpus
# (the short run). `make fuzz-long`: each to FUZZ_RUNS (10^7) executions or for
# FUZZ_LONG_SECONDS (an hour), whichever ends first: hours in all (docs/reliability.md has
# the rates). FUZZ_TARGETS="a b" runs only those.
fuzz-build:
	@bash scripts/install-deps.sh test
	@cmake -S . -B build-fuzz -DCMAKE_CXX_COMPILER=clang++-14 -DRANGEKIT_FUZZ=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
	@cmake --build build-fuzz -j$(JOBS)

fuzz: fuzz-build
	@bash scripts/run-fuzz.sh build-fuzz/fuzzers $(FUZZ_SECONDS)

fuzz-long: fuzz-build
	@bash scripts/run-fuzz.sh build-fuzz/fuzzers $(FUZZ_LONG_SECONDS) $(FUZZ_RUNS)

bench: build
	@./$(BUILD)/rangekit_bench

# A site on one box (bench/site_scale_bench.cpp; docs/performance.md, "A site on one box"): the
# service with N = 1, 8, 32, 64 UDP LS5 and past them, about five minutes. SCALE_N="..." picks N.
SCALE_N ?= 1,8,32,64,128,256
bench-scale: build
	@RANGEKIT_BENCH_SCALE=$(SCALE_N) ./$(BUILD)/rangekit_bench --benchmark_filter=SiteScale

# The dashboard's frame-rate and heap figures in headless chromium (docs/dashboard.md,
# "Benchmark"): an LS5 at 1 kHz on its live plot for 60 s (web/tests/fps.bench.mjs), then the
# overview of 100 sensors fed by the UDP pacer for 10 minutes and its keystroke response
# (web/tests/site.bench.mjs; RANGEKIT_SITE_BENCH_SECONDS=60 for a shorter run).
BENCH_WEB_ENV = RANGEKIT_CLI=$(abspath $(BUILD))/rangekit RANGEKIT_SCREENSHOTS=$(abspath $(BUILD))/screenshots \
  RANGEKIT_UDP_PACER=$(abspath $(BUILD))/rangekit_udp_pacer
bench-web: configure
	@cmake --build $(BUILD) --target rangekit rangekit_udp_pacer -j$(JOBS)
	@cd $(BUILD)/web && $(BENCH_WEB_ENV) node tests/fps.bench.mjs
	@cd $(BUILD)/web && $(BENCH_WEB_ENV) node tests/site.bench.mjs

# tests/consumer built against `cmake --install` of this build (find_package and
# pkg-config) and against the source tree (add_subdirectory), then run.
consumer: build
	@bash scripts/check-consumer.sh $(BUILD)

# The .deb (CPack) of this build; installed with dpkg, run, checked and removed.
package: build
	@bash scripts/check-package.sh $(BUILD)

# A family is its folders and one line of families.cmake: the LS5 cloned as ls6 in a temporary
# copy of the tree, built (through ccache, with $(BUILD)'s dashboard toolchain) and found in
# every face (docs/architecture.md, "Add a family"). The tree is not touched.
clone-check: deps
	@JOBS=$(JOBS) BUILD=$(BUILD) DEBUG_INFO="$(DEBUG_INFO)" bash scripts/clone-family.sh

lint: format-check tidy

format:
	@clang-format -i $(SOURCES)

format-check: deps
	@clang-format --dry-run --Werror $(SOURCES) && echo "clang-format: clean"

# clang-tidy over the library and CLI sources, in parallel, with the compile database of
# $(BUILD) (scripts/tidy.py: files already found clean and unchanged are not checked again).
tidy: configure
	@python3 scripts/tidy.py $(BUILD) $(JOBS)

clean:
	@rm -rf $(BUILD) build-asan build-tsan build-fuzz
