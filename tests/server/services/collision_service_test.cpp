// CollisionService on the GPU backend with a GPU job that throws (an injected pair finder on
// the real GPU thread, llvmpipe here): the pose is still deformed, with the CPU reference's
// pairs, so its vertices equal the CPU backend's bit for bit; every such pose is counted as a
// fallback in Stats (build_stats) and /metrics (format_metrics), and the reason is logged once.
// Then the real gpu::CollisionDetector behind the same service gives the CPU's vertices too.
#include "server/services/collision_service.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "protocol/messages.h"
#include "server/http/metrics_text.h"
#include "server/replies/stats_reply.h"
#include "tests/deform/shared_male.h"
#include "tests/server/http_probe.h"

namespace sweepd::test {
namespace {

namespace pb = sweepd::protocol;

struct Featured {
  std::vector<glm::vec3> positions;
  deform::FeatureReport report;
};

// The male's left elbow and knee at 150° with folding and protrusion, pairs from `detect`.
Featured deform_bent_male(const deform::BoundModel& male, const deform::DetectPairs& detect) {
  deform::test::Posing posing(male);
  posing.features = {.folding = true, .protrusion = true};
  posing.options.detect = detect;
  deform::Pose pose = deform::test::left_elbow_and_knee_flexed(male.model, 150.0f);
  Featured out;
  out.positions.resize(male.model.vertex_count());
  posing.deform(pose, deform::DeformMethod::kSweep, out.positions);
  out.report = posing.report.features;
  return out;
}

TEST(CollisionService, AThrowingGpuJobIsAnsweredFromTheCpuAndCounted) {
  REQUIRE_SHARED_MALE();
  server::GpuThread gpu;
  if (gpu.start() == nullptr) GTEST_SKIP() << "no EGL context: " << gpu.failure();
  int gpu_jobs = 0;
  server::CollisionService service(
      gpu, {gpu::CollisionBackend::kGpu, "test: an injected failure"},
      [&gpu_jobs](gpu::Context&, std::span<const glm::vec3>, std::span<const std::uint32_t>,
                  std::span<const std::uint32_t>,
                  std::vector<deform::TrianglePair>&) -> gpu::CollisionTimings {
        ++gpu_jobs;
        throw std::runtime_error("injected: GL_OUT_OF_MEMORY in the collision dispatch");
      });
  server::CollisionPairFinder finder(service);
  const Featured cpu = deform_bent_male(male, {});
  ASSERT_GT(cpu.report.pairs_before, 0) << "the 150° pose must give folding pairs to find";

  ::testing::internal::CaptureStderr();
  for (int pose = 0; pose < 2; ++pose) {
    const Featured fallen_back = deform_bent_male(male, finder.begin());
    finder.finish(fallen_back.report);
    // The CPU reference's pairs: the same vertices, bit for bit.
    EXPECT_EQ(fallen_back.positions, cpu.positions) << "pose " << pose;
    EXPECT_EQ(fallen_back.report.pairs_after, cpu.report.pairs_after);
  }
  const std::string log = ::testing::internal::GetCapturedStderr();
  // One GPU job per pose: after it threw, that pose's later detections went to the CPU.
  EXPECT_EQ(gpu_jobs, 2);
  const server::CollisionSnapshot snapshot = service.snapshot();
  EXPECT_EQ(snapshot.requests, 2u);
  EXPECT_EQ(snapshot.gpu_fallbacks, 2u);
  EXPECT_GT(snapshot.detect_ns, 0u);
  // Logged once for the one reason, with the reason.
  const std::string event = "\"event\":\"collision_gpu_fallback\"";
  const std::size_t first = log.find(event);
  ASSERT_NE(first, std::string::npos) << log;
  EXPECT_EQ(log.find(event, first + 1), std::string::npos) << log;
  EXPECT_NE(log.find("GL_OUT_OF_MEMORY"), std::string::npos) << log;

  // Stats carries the count ...
  flatbuffers::FlatBufferBuilder builder;
  server::build_stats(builder, 1, {}, {}, {}, snapshot, 5);
  const pb::Stats& stats = *pb::GetSizePrefixedMessage(builder.GetBufferPointer())->body_as_Stats();
  ASSERT_NE(stats.collision(), nullptr);
  EXPECT_EQ(stats.collision()->backend()->str(), "gpu");
  EXPECT_EQ(stats.collision()->gpu_fallbacks(), 2u);
  EXPECT_EQ(stats.collision()->requests(), 2u);
  // ... and so does /metrics.
  server::ServerSnapshot server_snapshot;
  server_snapshot.collision = snapshot;
  const std::string page =
      server::format_metrics(&server_snapshot, {}, server::Readiness::Stage::kAccepting);
  EXPECT_EQ(metric(page, "sweepd_collision_gpu_fallbacks_total"), 2.0) << page;
  EXPECT_EQ(metric(page, R"(sweepd_collision_backend{backend="gpu"})"), 1.0) << page;
  EXPECT_EQ(metric(page, R"(sweepd_collision_backend{backend="cpu"})"), 0.0) << page;
}

TEST(CollisionService, TheGpuDetectorGivesTheCpuVertices) {
  REQUIRE_SHARED_MALE();
  server::GpuThread gpu;
  if (gpu.start() == nullptr) GTEST_SKIP() << "no EGL context: " << gpu.failure();
  server::CollisionService service(gpu, {gpu::CollisionBackend::kGpu, "test"});
  server::CollisionPairFinder finder(service);
  const Featured on_gpu = deform_bent_male(male, finder.begin());
  finder.finish(on_gpu.report);
  EXPECT_EQ(on_gpu.positions, deform_bent_male(male, {}).positions);
  const server::CollisionSnapshot snapshot = service.snapshot();
  EXPECT_EQ(snapshot.gpu_fallbacks, 0u);
  EXPECT_GT(snapshot.upload_ns, 0u);
  EXPECT_GT(snapshot.readback_ns, 0u);
  EXPECT_EQ(snapshot.device, gpu.start()->renderer());
}

}  // namespace
}  // namespace sweepd::test
