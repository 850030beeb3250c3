// Collision + anatomical features per frame on the shared male, left elbow and knee flexed 150°
// (the angle between their links, tests/deform/shared_male.h):
// the CPU reference (grid broad phase) and gpu::CollisionDetector (llvmpipe here, a real GPU
// where one is lent), for pair detection over all 8 regions and for the whole feature pass
// (per region: detect, then fold/relax rounds each followed by a detection; protrusion). The
// sweep deformation itself is timed alongside, and the whole deformation job with folding,
// protrusion and volume preservation (deform/job/deform_job.h: a standalone frame, I_C from its
// fixed-point loop, and a stream frame, I_C from the previous frame).
// Whole body (the `contact` feature, deform/features/skin_contact.h): detection over the whole
// skin on the shared male and the 72k mannequin, at 150° elbow and knee flexion and at the
// worst contact frame of cmu_01_03 (frame 1100: the most whole-body pairs among its every 50th
// frame on the male), CPU one core, CPU all cores, GPU; and the contact pass per frame.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <filesystem>
#include <glm/gtc/quaternion.hpp>
#include <memory>
#include <thread>

#include "deform/binding/bind.h"
#include "deform/features/collision_features.h"
#include "deform/features/whole_body_detector.h"
#include "deform/job/deform_job.h"
#include "deform/rig/rig_map.h"
#include "gpu/collision.h"
#include "io/bvh_load.h"
#include "io/gltf_load.h"
#include "mannequin/mannequin.h"
#include "motion/retarget.h"
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

// ---- Whole body (contact) ----

constexpr int kWorstContactFrame = 1100;  // of cmu_01_03, see the header comment

// A model posed for whole-body detection: 0 the shared male, 1 the 72k mannequin; pose 0 the
// left elbow and knee at 150°, 1 cmu_01_03's worst contact frame.
struct BodyScene {
  std::unique_ptr<deform::BoundModel> bound;
  std::unique_ptr<deform::ModelRuntime> runtime;
  deform::DeformContext context;
  std::vector<glm::vec3> posed[2];
};

BodyScene* body_scene(int model) {
  static BodyScene* scenes[2] = {nullptr, nullptr};
  if (scenes[model] != nullptr) return scenes[model];
  const std::filesystem::path data(SWEEPD_SHARED_DATA);
  const auto male = data / "models/makehuman_male_cmu.glb";
  const auto clip = data / "motion/cmu_01_03.bvh";
  if (!std::filesystem::exists(clip) || (model == 0 && !std::filesystem::exists(male)))
    return nullptr;
  auto* s = new BodyScene;
  const deform::Model mesh =
      model == 0 ? io::load_gltf(male) : mannequin::make_mannequin({.target_vertices = 72000});
  s->bound = std::make_unique<deform::BoundModel>(
      deform::bind(mesh, deform::detect_rig_map(mesh.skeleton)));
  s->runtime = std::make_unique<deform::ModelRuntime>(*s->bound);
  const motion::Retargeter retargeter(io::load_bvh(clip), s->bound->model);
  deform::Pose poses[2] = {deform::test::left_elbow_and_knee_flexed(mesh, 150.0f),
                           retargeter.pose_at_frame(kWorstContactFrame)};
  for (int p = 0; p < 2; ++p) {
    s->posed[p].resize(mesh.vertex_count());
    deform::DeformJob{.runtime = *s->runtime, .pose = poses[p], .positions = s->posed[p]}.run(
        s->context);
  }
  std::fprintf(stderr, "%s: %zu vertices, %zu skin triangles\n",
               model == 0 ? "shared male" : "mannequin 72k", mesh.vertex_count(),
               s->runtime->collision().contact.skin_triangles.size());
  return scenes[model] = s;
}

// Whole-skin pairs: args model, pose, backend (0 CPU one core, 1 CPU all cores, 2 GPU, 3 the
// region detector's grid on one core, SelfIntersectionDetector: the broad phase not chosen).
void BM_DetectWholeBody(benchmark::State& state) {
  BodyScene* s = body_scene(static_cast<int>(state.range(0)));
  if (s == nullptr) return state.SkipWithError("shared data absent");
  const std::vector<glm::vec3>& positions = s->posed[state.range(1)];
  const deform::CollisionModel& model = s->runtime->collision();
  const int backend = static_cast<int>(state.range(2));
  gpu::CollisionDetector* detector = backend == 2 ? gpu_detector() : nullptr;
  if (backend == 2 && detector == nullptr) return state.SkipWithError("no GL context");
  const int threads = backend == 0 ? 1 : static_cast<int>(std::thread::hardware_concurrency());
  deform::WholeBodyDetector cpu;
  deform::SelfIntersectionDetector grid;
  std::vector<deform::TrianglePair> pairs;
  for (auto _ : state) {
    if (backend == 3) {
      grid.detect(positions, model.regions.welded_indices, model.contact.skin_triangles, pairs);
    } else if (detector) {
      detector->detect(positions, model.regions.welded_indices, model.contact.skin_triangles,
                       pairs);
    } else {
      cpu.detect(positions, model.regions.welded_indices, model.contact.skin_triangles, pairs,
                 threads);
    }
  }
  deform::remove_rest_pairs(model.contact.rest_pairs, pairs);
  state.counters["contact_pairs"] = static_cast<double>(pairs.size());
  state.counters["threads"] = detector ? 0 : backend == 3 ? 1 : threads;
}

// The contact pass alone (CPU all cores): args model, pose.
void BM_ContactFeature(benchmark::State& state) {
  BodyScene* s = body_scene(static_cast<int>(state.range(0)));
  if (s == nullptr) return state.SkipWithError("shared data absent");
  const std::vector<glm::vec3>& posed = s->posed[state.range(1)];
  deform::CollisionFeatures features(s->runtime->collision(),
                                     {.folding = false, .protrusion = false, .contact = true});
  std::vector<glm::vec3> positions = posed;
  deform::FeatureReport report;
  for (auto _ : state) {
    state.PauseTiming();
    positions = posed;
    state.ResumeTiming();
    report = features.apply(s->context.skinning(), positions);
  }
  state.counters["pairs_before"] = report.contact_pairs_before;
  state.counters["pairs_after"] = report.contact_pairs_after;
}

BENCHMARK(BM_DetectWholeBody)
    ->ArgNames({"mannequin", "worst_frame", "backend"})
    ->ArgsProduct({{0, 1}, {0, 1}, {0, 1, 2, 3}})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ContactFeature)
    ->ArgNames({"mannequin", "worst_frame"})
    ->ArgsProduct({{0, 1}, {0, 1}})
    ->Unit(benchmark::kMillisecond);

BENCHMARK(BM_SweepDeform)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_VolumeAndFeatures)->ArgName("stream")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DetectAllRegions)->ArgName("gpu")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CollisionFeatures)->ArgName("gpu")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
