// Collision + anatomical features per frame on the shared male, left elbow and knee flexed 150°
// (the angle between their links, tests/deform/shared_male.h):
// the CPU reference (grid broad phase) and gpu::CollisionDetector (llvmpipe here, a real GPU
// where one is lent), for pair detection over all 8 regions and for the whole feature pass
// (per region: detect, then fold/relax rounds each followed by a detection; protrusion). The
// sweep deformation itself is timed alongside, and the whole deformation job with folding,
// protrusion and volume preservation (deform/job/deform_job.h: a standalone frame, I_C from its
// fixed-point loop, and a stream frame, I_C from the previous frame).
#include <benchmark/benchmark.h>

#include <cstdio>
#include <filesystem>
#include <glm/gtc/quaternion.hpp>
#include <memory>

#include "deform/binding/bind.h"
#include "deform/features/collision_features.h"
#include "deform/job/deform_job.h"
#include "deform/rig/rig_map.h"
#include "gpu/collision.h"
#include "io/gltf_load.h"
#include "tests/deform/shared_male.h"

namespace {

using namespace sweepd;

struct Scene {
  deform::BoundModel bound;
  deform::Pose pose;
  std::unique_ptr<deform::ModelRuntime> runtime;
  deform::DeformContext context;
  std::vector<glm::vec3> posed;
};

Scene* scene() {
  static Scene* instance = []() -> Scene* {
    const auto file = std::filesystem::path(SWEEPD_SHARED_DATA) / "models/makehuman_male_cmu.glb";
    if (!std::filesystem::exists(file)) return nullptr;
    auto* s = new Scene;
    const deform::Model model = io::load_gltf(file);
    s->bound = deform::bind(model, deform::detect_rig_map(model.skeleton));
    s->pose = deform::test::left_elbow_and_knee_flexed(model, 150.0f);
    s->runtime = std::make_unique<deform::ModelRuntime>(s->bound);
    s->posed.resize(model.vertex_count());
    deform::DeformJob{.runtime = *s->runtime, .pose = s->pose, .positions = s->posed}.run(
        s->context);
    return s;
  }();
  return instance;
}

gpu::CollisionDetector* gpu_detector() {
  static std::unique_ptr<gpu::Context> context;
  static std::unique_ptr<gpu::CollisionDetector> detector = []() {
    try {
      context = std::make_unique<gpu::Context>();
      std::fprintf(stderr, "GL_RENDERER: %s\n", context->renderer().c_str());
      auto made = std::make_unique<gpu::CollisionDetector>(*context);
      // Warm up: the driver compiles the shader on its first dispatch.
      const std::vector<glm::vec3> corners = {{0, 0, 0},  {1, 0, 0},       {0, 1, 0},
                                              {0, 0, -1}, {0.2f, 0.2f, 1}, {0.3f, 0.2f, 1}};
      const std::vector<std::uint32_t> indices = {0, 1, 2, 3, 4, 5}, ids = {0, 1};
      std::vector<deform::TrianglePair> pairs;
      made->detect(corners, indices, ids, pairs);
      return made;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "no GPU collision: %s\n", e.what());
      return std::unique_ptr<gpu::CollisionDetector>();
    }
  }();
  return detector.get();
}

deform::DetectPairs gpu_hook(gpu::CollisionDetector& detector) {
  return [&detector](auto p, auto i, auto t, std::vector<deform::TrianglePair>& out) {
    detector.detect(p, i, t, out);
  };
}

void BM_SweepDeform(benchmark::State& state) {
  Scene* s = scene();
  if (s == nullptr) return state.SkipWithError("shared male absent");
  std::vector<glm::vec3> positions(s->posed.size());
  deform::DeformJob job{.runtime = *s->runtime, .pose = s->pose, .positions = positions};
  for (auto _ : state) {
    job.run(s->context);
    benchmark::DoNotOptimize(positions.data());
  }
}

// The deformation job with folding, protrusion and volume on the CPU: a frame standing alone
// (0: I_C from up to 3 fixed-point rounds) or a stream's frame (1: I_C from the previous frame).
void BM_VolumeAndFeatures(benchmark::State& state) {
  Scene* s = scene();
  if (s == nullptr) return state.SkipWithError("shared male absent");
  std::vector<glm::vec3> positions(s->posed.size()), normals(s->posed.size());
  deform::DeformJob job{
      .runtime = *s->runtime,
      .pose = s->pose,
      .features = {.folding = true, .protrusion = true, .volume = true},
      .options = {.volume_change = state.range(0) ? deform::VolumeChangeSource::kPreviousFrame
                                                  : deform::VolumeChangeSource::kFixedPoint},
      .positions = positions,
      .normals = normals};
  deform::DeformContext context;
  deform::DeformReport report = job.run(context);
  for (auto _ : state) report = job.run(context);
  state.counters["rounds"] = report.rounds;
  state.counters["pairs_after"] = report.features.pairs_after;
}

// Pairs over all 8 collision regions, CPU (0) or GPU (1).
void BM_DetectAllRegions(benchmark::State& state) {
  Scene* s = scene();
  if (s == nullptr) return state.SkipWithError("shared male absent");
  const deform::CollisionModel& features = s->runtime->collision();
  gpu::CollisionDetector* detector = state.range(0) ? gpu_detector() : nullptr;
  if (state.range(0) && detector == nullptr) return state.SkipWithError("no GL context");
  deform::SelfIntersectionDetector cpu;
  std::vector<deform::TrianglePair> pairs;
  std::size_t found = 0, triangles = 0;
  for (auto _ : state) {
    found = triangles = 0;
    for (const deform::CollisionRegion& region : features.regions.regions) {
      if (detector) {
        detector->detect(s->posed, features.regions.welded_indices, region.triangles, pairs);
      } else {
        cpu.detect(s->posed, features.regions.welded_indices, region.triangles, pairs);
      }
      found += pairs.size();
      triangles += region.triangles.size();
    }
  }
  state.counters["pairs"] = static_cast<double>(found);
  state.counters["triangles"] = static_cast<double>(triangles);
}

// The whole feature pass per frame (detect, fold/relax rounds, protrusion), CPU or GPU pairs.
void BM_CollisionFeatures(benchmark::State& state) {
  Scene* s = scene();
  if (s == nullptr) return state.SkipWithError("shared male absent");
  gpu::CollisionDetector* detector = state.range(0) ? gpu_detector() : nullptr;
  if (state.range(0) && detector == nullptr) return state.SkipWithError("no GL context");
  deform::CollisionFeatures features(s->runtime->collision());
  const deform::DetectPairs hook = detector ? gpu_hook(*detector) : deform::DetectPairs{};
  std::vector<glm::vec3> positions = s->posed;
  deform::FeatureReport report;
  for (auto _ : state) {
    state.PauseTiming();
    positions = s->posed;
    state.ResumeTiming();
    report = features.apply(s->context.skinning(), positions, hook);
  }
  state.counters["pairs_before"] = report.pairs_before;
  state.counters["pairs_after"] = report.pairs_after;
  state.counters["folded"] = report.folded;
}

BENCHMARK(BM_SweepDeform)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_VolumeAndFeatures)->ArgName("stream")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DetectAllRegions)->ArgName("gpu")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CollisionFeatures)->ArgName("gpu")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
