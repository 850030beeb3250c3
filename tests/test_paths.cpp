#include "tests/test_paths.h"

namespace sweepd::test_paths {

const char shared_data[] = SWEEPD_TEST_SHARED_DATA;
const char source_dir[] = SWEEPD_TEST_SOURCE_DIR;
const char build_dir[] = SWEEPD_TEST_BUILD_DIR;
const char sweepctl[] = SWEEPD_TEST_SWEEPCTL;
const char daemon[] = SWEEPD_TEST_DAEMON;
const char stream_poses[] = SWEEPD_TEST_STREAM_POSES;
const char render_frames[] = SWEEPD_TEST_RENDER_FRAMES;
const char server_bench[] = SWEEPD_TEST_SERVER_BENCH;
const char flatc[] = SWEEPD_TEST_FLATC;
const char cxx_compiler[] = SWEEPD_TEST_CXX_COMPILER;
const char cxx_flags[] = SWEEPD_TEST_CXX_FLAGS;

}  // namespace sweepd::test_paths
