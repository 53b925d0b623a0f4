# Armature: `make run` serves, `make test` tests. Both install what is missing first.
BUILD ?= build
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?=
# ozz-animation and ACL (../shared/third_party) as the benchmarks' baselines: only `make bench` turns them on.
BENCH_OZZ ?= OFF
BENCH_ACL ?= OFF
# Compiler warnings fail the build (-Werror): WERROR=OFF to build with a compiler that warns more.
WERROR ?= ON
DATA_DIR ?= armature-data
ARGS ?=

SOAK_CLIENTS ?= 50
SOAK_SECONDS ?= 600

FUZZ_BUILD ?= build-fuzz
FUZZ_SECONDS ?= 300
FUZZ_SMOKE_SECONDS ?= 20
FUZZ_RUNS ?=
FUZZ_MAX_LEN ?= 4096
CLANG ?= /usr/bin/clang++-14

.PHONY: all deps test-deps configure build run test bench image-test soak clean fuzz fuzz-build fuzz-smoke format

all: build

deps:
	./scripts/setup.sh

test-deps:
	./scripts/setup.sh test

configure:
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release -DARMATURE_BENCH_OZZ=$(BENCH_OZZ) -DARMATURE_BENCH_ACL=$(BENCH_ACL) -DARMATURE_WERROR=$(WERROR) $(CMAKE_FLAGS)

build: deps configure
	cmake --build $(BUILD) -j $(JOBS)

run: build
	$(BUILD)/bin/armature-server --data-dir $(DATA_DIR) $(ARGS)

test: test-deps configure
	cmake --build $(BUILD) -j $(JOBS)
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS) --timeout 600
	$(MAKE) fuzz-smoke

# The C++ sources as .clang-format has them (ctest architecture.format checks it).
format:
	python3 tests/architecture/check_format.py . >/dev/null || \
	  find base engine server clients/cpp bench tests \( -name '*.cc' -o -name '*.h' \) -not -path '*/node_modules/*' \
	    -not -path '*/corpus/*' -not -path '*/regressions/*' -not -path '*/seeds/*' | xargs clang-format-14 -i --style=file

# libFuzzer targets (tests/fuzz) in their own clang build with ASan+UBSan.
fuzz-build:
	CC=$(subst clang++,clang,$(CLANG)) CXX=$(CLANG) cmake -S . -B $(FUZZ_BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo \
	  -DARMATURE_FUZZ=ON -DARMATURE_FUZZ_SECONDS=$(FUZZ_SMOKE_SECONDS)
	cmake --build $(FUZZ_BUILD) -j $(JOBS)

# Part of `make test` when clang-14 is installed: every target replays its
# regressions and seeds, then fuzzes FUZZ_SMOKE_SECONDS, one at a time.
fuzz-smoke:
	@if [ -x $(CLANG) ]; then $(MAKE) fuzz-build && cd $(FUZZ_BUILD) && ctest --output-on-failure -R '^fuzz\.'; \
	else echo "fuzz-smoke: $(CLANG) not found; fuzz targets skipped"; fi

# Each target for FUZZ_SECONDS (default 300), or FUZZ_RUNS inputs if sooner,
# corpus kept in $(FUZZ_BUILD)/fuzz-work.
fuzz: fuzz-build
	@set -e; for t in $(FUZZ_BUILD)/bin/*_fuzz; do \
	  FUZZ_RUNS=$(FUZZ_RUNS) FUZZ_MAX_LEN=$(FUZZ_MAX_LEN) tests/fuzz/run_fuzz.sh $$t $(FUZZ_SECONDS) $(FUZZ_BUILD)/fuzz-work; done

# Builds deploy/Dockerfile with podman, runs the image and checks it from the
# host, then validates deploy/k8s offline (deploy/image-test.sh).
image-test: configure
	cmake --build $(BUILD) -j $(JOBS) --target armature
	./deploy/image-test.sh --cli $(BUILD)/bin/armature

# A real server soaked by SOAK_CLIENTS clients for SOAK_SECONDS on the full mix
# (bench/soak); fails on any error or if the server does not exit 0 on SIGTERM.
soak: build
	sh bench/soak/run_soak.sh $(BUILD)/bin/armature-server $(BUILD)/bin/armature-soak $(SOAK_CLIENTS) $(SOAK_SECONDS)

# Builds ozz-animation beside the benchmarks (bench/CMakeLists.txt) and ACL's
# armature-bench-acl (bench/acl/), and ends with the Armature/ozz ratio of each
# BM_VsOzz_* pair, the Armature/ACL ratio of each BM_VsAcl_* pair and the
# compressed clips' sizes and errors against ACL (scripts/bench_ratios.py),
# then armature-load against a real server (bench/load/run_load_bench.sh:
# closed loop at concurrency 1-128, 100-1000 streams).
bench: BENCH_OZZ = ON
bench: BENCH_ACL = ON
bench: build
	./scripts/setup.sh bench
	$(MAKE) configure BENCH_OZZ=ON BENCH_ACL=ON
	cmake --build $(BUILD) -j $(JOBS)
	$(BUILD)/bin/armature-bench --benchmark_counters_tabular=true \
	  --benchmark_out=$(BUILD)/bench.json --benchmark_out_format=json $(ARGS)
	@if [ -x $(BUILD)/bin/armature-bench-acl ]; then $(BUILD)/bin/armature-bench-acl --benchmark_counters_tabular=true \
	  --benchmark_out=$(BUILD)/bench_acl.json --benchmark_out_format=json $(ARGS); \
	else echo "armature-bench-acl not built (ACL or RTM tarball absent): compressed clips not compared with ACL"; fi
	@if [ -x $(BUILD)/bin/armature-bench-assimp ]; then $(BUILD)/bin/armature-bench-assimp --benchmark_repetitions=3; \
	else echo "armature-bench-assimp not built (no libassimp-dev): BVH parse not compared with assimp"; fi
	@if command -v python3 >/dev/null; then python3 scripts/bench_ratios.py $(BUILD)/bench.json $$(ls $(BUILD)/bench_acl.json 2>/dev/null); \
	else echo "python3 not found: Armature/ozz ratios not printed (see $(BUILD)/bench.json)"; fi
	sh bench/load/run_load_bench.sh $(BUILD)/bin/armature-server $(BUILD)/bin/armature-load

clean:
	rm -rf $(BUILD)
