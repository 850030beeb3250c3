// Where the tests find the shared data, the source tree and the programs they start. The paths
// are absolute and differ between clones, so they are compiled into one file (test_paths.cpp)
// instead of every test's command line: the compiler cache (CMakePresets.json) then serves a
// fresh clone in another folder every test object the developer's own build made.
// tests/CMakeLists.txt defines SWEEPD_SHARED_DATA, SWEEPD_SOURCE_DIR, ... as these names.
// Constant-initialized, so they can be read during any file's static initialization.
#pragma once

namespace sweepd::test_paths {

extern const char shared_data[];   // ../shared/data beside the checkout
extern const char source_dir[];    // the checkout
extern const char build_dir[];     // this build tree
extern const char sweepctl[];      // the programs of this build tree
extern const char daemon[];
extern const char stream_poses[];
extern const char render_frames[];
extern const char server_bench[];  // empty where the benchmarks are not built
extern const char flatc[];
extern const char cxx_compiler[];  // this build's compiler and flags (the installed-client test)
extern const char cxx_flags[];

}  // namespace sweepd::test_paths
