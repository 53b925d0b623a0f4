# Armature: `make run` serves, `make test` tests. Both install what is missing first.
BUILD ?= build
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?=
DATA_DIR ?= armature-data
ARGS ?=

.PHONY: all deps test-deps configure build run test bench image-test clean

all: build

deps:
	./scripts/setup.sh

test-deps:
	./scripts/setup.sh test

configure:
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS)

build: deps configure
	cmake --build $(BUILD) -j $(JOBS)

run: build
	$(BUILD)/bin/armature-server --data-dir $(DATA_DIR) $(ARGS)

test: test-deps configure
	cmake --build $(BUILD) -j $(JOBS)
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS) --timeout 600

# Builds deploy/Dockerfile with podman, runs the image and checks it from the
# host, then validates deploy/k8s offline (deploy/image-test.sh).
image-test: configure
	cmake --build $(BUILD) -j $(JOBS) --target armature
	./deploy/image-test.sh --cli $(BUILD)/bin/armature

bench: build
	$(BUILD)/bin/armature-bench --benchmark_counters_tabular=true $(ARGS)

clean:
	rm -rf $(BUILD)
