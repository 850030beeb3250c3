# The two commands of the README: `make demo` (the main job) and `make test`.
# Each installs what is missing, configures and builds as needed.
# `make sanitize`: the whole suite under AddressSanitizer + UndefinedBehaviorSanitizer (build/asan);
# `make tsan`: the tests labelled "threads" under ThreadSanitizer (build/tsan, only their targets).
# Both fail on any sanitizer report of any process a test ran (.ci/sanitized_ctest).
BUILD := build/release
JOBS ?= $(shell nproc)

.PHONY: deps build test sanitize tsan demo bench fuzz clean

deps:
	bash deploy/install-deps.sh

build: deps
	cmake --preset release >/dev/null
	cmake --build $(BUILD) -j $(JOBS)

test: build
	ctest --test-dir $(BUILD) --output-on-failure -j $(JOBS)

sanitize: deps
	cmake --preset asan >/dev/null
	cmake --build --preset asan -j $(JOBS)
	.ci/sanitized_ctest asan -j $(JOBS)

tsan: deps
	cmake --preset tsan >/dev/null
	cmake --build --preset tsan -j $(JOBS)
	.ci/sanitized_ctest tsan -j $(JOBS)

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
