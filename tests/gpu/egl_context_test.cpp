// Tests for gpu::Context and gpu::Worker on whatever EGL offers (Mesa llvmpipe in CI).
// No EGL display is a failure, not a skip: CI installs llvmpipe (libegl-mesa0, libgl1-mesa-dri).
#include "gpu/egl_context.h"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <cstdlib>
#include <functional>
#include <future>
#include <stdexcept>
#include <thread>
#include <vector>

#include "gpu/gpu_worker.h"

namespace sweepd::gpu {
namespace {

TEST(EglContext, GivesAnOpenGl45CoreContextWithoutADisplay) {
  Context context;
  std::printf("renderer: %s (%s platform%s), GL %s\n", context.renderer().c_str(),
              context.platform().c_str(), context.software() ? ", software" : "",
              context.version().c_str());
  EXPECT_FALSE(context.renderer().empty());
  EXPECT_TRUE(context.platform() == "device" || context.platform() == "surfaceless");
  EXPECT_GE(context.major_version() * 10 + context.minor_version(), 45);
  EXPECT_TRUE(context.core_profile());
  EXPECT_EQ(context.gl().GetError(), static_cast<GLenum>(GL_NO_ERROR));
}

TEST(EglContext, TwoContextsLiveSideBySideOnTheSameDisplay) {
  // The display is shared; destroying the first context must not terminate it under the second.
  auto first = std::make_unique<Context>();
  Context second;
  first.reset();
  second.make_current();
  GLint max_texture_size = 0;
  second.gl().GetIntegerv(GL_MAX_TEXTURE_SIZE, &max_texture_size);
  EXPECT_GE(max_texture_size, 1024);  // GL 4.5 guarantees at least 16384
}

TEST(EglContext, DebugOutputReportsAGlErrorToTheSink) {
  std::vector<std::string> messages;
  ContextOptions options;
  options.debug_output = true;
  options.debug_sink = [&messages](const std::string& message) { messages.push_back(message); };
  Context context(options);
  ASSERT_TRUE(messages.empty());
  context.gl().BindTexture(GL_TEXTURE_2D, 987654);  // not a name from glGenTextures: an error
  EXPECT_EQ(context.gl().GetError(), static_cast<GLenum>(GL_INVALID_OPERATION));
  ASSERT_FALSE(messages.empty());  // synchronous output: the message arrived during the call
  EXPECT_NE(messages.front().find("GL error"), std::string::npos) << messages.front();
}

// Runs `construct` in a process whose EGL loader (libglvnd) finds no vendor library: exits 0
// after printing the ContextError it must throw, 1 if it does not throw.
[[noreturn]] void construct_without_egl_driver(const std::function<void()>& construct) {
  ::setenv("__EGL_VENDOR_LIBRARY_FILENAMES", "/nonexistent/sweepd_no_vendor.json", 1);
  ::unsetenv("__EGL_VENDOR_LIBRARY_DIRS");
  try {
    construct();
  } catch (const ContextError& error) {
    std::fprintf(stderr, "%s\n", error.what());
    std::exit(0);
  }
  std::exit(1);
}

// Death tests in fresh processes ("threadsafe" style re-runs the binary), as EGL caches its
// vendors once loaded: construction must throw a ContextError saying why — not crash, not hang.
TEST(EglContextDeathTest, NoEglDriverGivesAClearError) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(construct_without_egl_driver([] { Context context; }), ::testing::ExitedWithCode(0),
              "no headless OpenGL 4.5 core context through EGL.*needs an EGL driver");
}

TEST(GpuWorkerDeathTest, ReportsTheContextErrorFromItsConstructor) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(construct_without_egl_driver([] { Worker worker; }), ::testing::ExitedWithCode(0),
              "no headless OpenGL 4.5 core context through EGL");
}

TEST(GpuWorker, RunsJobsInOrderOnItsOwnThreadAndReturnsResults) {
  Worker worker;
  EXPECT_FALSE(worker.renderer().empty());
  const std::thread::id caller = std::this_thread::get_id();
  std::vector<int> order;
  std::vector<std::future<int>> results;
  for (int i = 0; i < 5; ++i) {
    results.push_back(worker.submit([i, &order, caller](Context& context) {
      EXPECT_NE(std::this_thread::get_id(), caller);
      GLint major = 0;
      context.gl().GetIntegerv(GL_MAJOR_VERSION, &major);  // the context is current here
      order.push_back(i);
      return major * 100 + i;
    }));
  }
  for (int i = 0; i < 5; ++i) EXPECT_EQ(results[i].get(), 400 + i);
  EXPECT_EQ(order, (std::vector<int>{0, 1, 2, 3, 4}));
}

TEST(GpuWorker, PassesAJobsExceptionThroughItsFuture) {
  Worker worker;
  auto failing = worker.submit([](Context&) -> int { throw std::runtime_error("job failed"); });
  EXPECT_THROW(failing.get(), std::runtime_error);
  // The worker keeps going after a failed job.
  EXPECT_EQ(worker.submit([](Context&) { return 7; }).get(), 7);
}

TEST(GpuWorker, RunsEveryQueuedJobBeforeShuttingDown) {
  std::future<int> last;
  {
    Worker worker;
    for (int i = 0; i < 3; ++i) {
      last = worker.submit([i](Context&) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
        return i;
      });
    }
  }  // destructor: drains the queue, then joins
  ASSERT_EQ(last.wait_for(std::chrono::seconds(0)), std::future_status::ready);
  EXPECT_EQ(last.get(), 2);
}

}  // namespace
}  // namespace sweepd::gpu
