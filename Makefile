# The two commands of the README: `make demo` (the main job) and `make test`.
# Each installs what is missing, configures and builds as needed.
BUILD := build/release
JOBS ?= $(shell nproc)

.PHONY: deps build test demo bench fuzz clean

deps:
	bash deploy/install-deps.sh

build: deps
	cmake --preset release >/dev/null
	cmake --build $(BUILD) -j $(JOBS)

test: build
	ctest --test-dir $(BUILD) --output-on-failure -j $(JOBS)

demo: build
	bash deploy/demo.sh $(BUILD)

bench: build
	bash bench/run_benchmarks.sh $(BUILD)

# libFuzzer over every untrusted input (fuzz/run_fuzzers.sh): FUZZ_SECONDS per target.
FUZZ_SECONDS ?= 60
fuzz: deps
	bash fuzz/run_fuzzers.sh $(FUZZ_SECONDS)

clean:
	rm -rf build
