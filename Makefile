# The two commands of the README: `make demo` (the main job) and `make test`.
# Each installs what is missing, configures a tree once (ninja reconfigures it when a CMakeLists
# changes) and builds as needed; the compiler cache (ccache, CMakePresets.json) serves any clone.
# `make check`: only the unit tests (label "unit", not "slow"), built without sweepd, sweepctl
# and the clients: the loop while editing.
# `make sanitize`: the whole suite under AddressSanitizer + UndefinedBehaviorSanitizer (build/asan);
# `make sanitize-untrusted`: the tests that feed bytes a client or a file controls (label
# "untrusted") under the same sanitizers, only their targets: what CI runs;
# `make tsan`: the tests of sweepd's own threads under ThreadSanitizer (label "threads", build/tsan,
# only their targets).
# All three fail on any sanitizer report of any process a test ran (.ci/sanitized_ctest).
BUILD := build/release
JOBS ?= $(shell nproc)

.PHONY: deps build check test sanitize sanitize-untrusted tsan demo bench fuzz docs docs-sheet docs-quality clean

deps:
	bash deploy/install-deps.sh

# configure-PRESET: configures build/PRESET when it has no build.ninja yet.
configure-%:
	@test -f build/$*/build.ninja || cmake --preset $* >/dev/null

build: deps configure-release
	cmake --build $(BUILD) -j $(JOBS)

check: deps configure-release
	cmake --build $(BUILD) -j $(JOBS) --target unit_tests
	ctest --test-dir $(BUILD) --output-on-failure -j $(JOBS) -L unit -LE slow

test: build
	ctest --test-dir $(BUILD) --output-on-failure -j $(JOBS)

sanitize: deps configure-asan
	cmake --build --preset asan -j $(JOBS)
	.ci/sanitized_ctest asan -j $(JOBS)

sanitize-untrusted: deps configure-asan
	cmake --build --preset asan -j $(JOBS) --target untrusted_input_tests
	.ci/sanitized_ctest asan -j $(JOBS) -L untrusted

tsan: deps configure-tsan
	cmake --build --preset tsan -j $(JOBS)
	.ci/sanitized_ctest tsan -j $(JOBS)

demo: build
	bash deploy/demo.sh $(BUILD)

bench: build
	cmake --build $(BUILD) -j $(JOBS) --target benchmarks
	bash bench/run_benchmarks.sh $(BUILD)

# libFuzzer over every untrusted input (fuzz/run_fuzzers.sh): FUZZ_SECONDS per target.
FUZZ_SECONDS ?= 60
fuzz: deps
	bash fuzz/run_fuzzers.sh $(FUZZ_SECONDS)

# The docs site (mkdocs.yml: docs/, with protocol/README.md, deploy/README.md and README's test
# table drawn in) into build/docs-site/; any warning fails it, as in tests/docs/docs_site_test.py.
docs: deps
	mkdocs build --strict --site-dir build/docs-site

# README's contact sheet: sweep, LBS and DQS on the shared male at three frames of CMU 01_01
# (197: a deep crouch, 600: standing, arms down, 1257: both elbows bent furthest), from the
# shared data beside this checkout, as deploy/demo.sh finds it.
SHARED := ../shared/data
docs-sheet: deps configure-release
	@test -f $(SHARED)/models/makehuman_male_cmu.glb || { echo "docs-sheet: no $(SHARED)/models/makehuman_male_cmu.glb: ../shared/data is not beside this checkout"; exit 1; }
	cmake --build $(BUILD) -j $(JOBS) --target sweepctl
	$(BUILD)/cli/sweepctl sheet $(SHARED)/models/makehuman_male_cmu.glb \
	  --bvh $(SHARED)/motion/cmu_01_01.bvh --frames 197,600,1257 --methods sweep,lbs,dqs \
	  --cell 200x300 -o docs/contact_sheet.png

# docs/quality/: per shared body, sweepctl check's tables (range of motion, CMU 01_01 and 01_03)
# and the contact sheet of its worst frames, and their index (a few minutes).
docs-quality: deps configure-release
	@test -d $(SHARED)/models/corpus || { echo "docs-quality: no $(SHARED)/models/corpus: ../shared/data is not beside this checkout"; exit 1; }
	cmake --build $(BUILD) -j $(JOBS) --target sweepctl
	bash docs/quality/make_pages.sh $(BUILD)/cli/sweepctl $(SHARED)

clean:
	rm -rf build
