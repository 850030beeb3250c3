// Collision + anatomical features per frame, left elbow and knee flexed 150° (the angle between
// their links, tests/deform/shared_male.h), frames alternating with 149° so that every frame
// brings new positions (the GPU detector answers unchanged positions from its last submission):
// the CPU reference (grid broad phase, one core) and gpu::CollisionDetector (llvmpipe here, a
// real GPU where one is lent), for pair detection over all 8 regions per frame — on the shared
// male (14.5k vertices) and the 72k procedural mannequin; on the GPU as CollisionFeatures calls
// it (region by region: the first call sends every stale region in one submission) and through
// detect_all — and for the whole feature pass on the male (per region: detect, then fold/relax
// rounds each followed by a detection; protrusion). The sweep deformation itself is timed
// alongside, and the whole deformation job with folding, protrusion and volume preservation
// (deform/job/deform_job.h: a standalone frame, I_C from its fixed-point loop, and a stream
// frame, I_C from the previous frame).
// Whole body (the `contact` feature, deform/features/skin_contact.h): detection over the whole
// skin on the shared male and the 72k mannequin, at 150° elbow and knee flexion and at the
// worst contact frame of cmu_01_03 (frame 4250: the most whole-body pairs among its every 50th
// frame on the male; frame 1100 was, with 483, until the hip links kept their rest angle to the
// pelvis, motion/retarget.h: 3 there now), CPU one core, CPU all cores, GPU; and the contact
// pass per frame.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <filesystem>
#include <glm/gtc/quaternion.hpp>
#include <memory>
#include <thread>

#include "bench/bench_models.h"
#include "deform/binding/bind.h"
#include "deform/features/collision_features.h"
#include "deform/features/whole_body_detector.h"
#include "deform/job/deform_job.h"
#include "deform/rig/rig_map.h"
#include "gpu/collision.h"
#include "io/bvh/bvh_load.h"
#include "io/gltf/gltf_load.h"
#include "mannequin/mannequin.h"
#include "motion/retarget.h"
#include "tests/deform/shared_male.h"
#include "tests/test_paths.h"

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
      auto made = std::make_unique<gpu::CollisionDetector>(*context);  // compiles, warms up
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

// A model bound once and posed twice (elbow and knee flexed 150° and 149°): the frames the
// detection benchmarks alternate between.
struct PosedFrames {
  deform::BoundModel bound;
  std::unique_ptr<deform::ModelRuntime> runtime;
  deform::DeformContext contexts[2];
  std::vector<glm::vec3> posed[2];
};

// 0: the shared male (nullptr without ../shared/data), 1: the 72k mannequin.
PosedFrames* posed_frames(int model) {
  static std::unique_ptr<PosedFrames> made[2];
  if (made[model]) return made[model].get();
  const deform::Model* source = model == 0 ? bench::shared_male() : &bench::mannequin_72k();
  if (source == nullptr) return nullptr;
  made[model] = std::make_unique<PosedFrames>();
  PosedFrames& f = *made[model];
  f.bound = deform::bind(*source, deform::detect_rig_map(source->skeleton));
  f.runtime = std::make_unique<deform::ModelRuntime>(f.bound);
  for (int frame = 0; frame < 2; ++frame) {
    f.posed[frame].resize(source->vertex_count());
    deform::Pose pose = deform::test::left_elbow_and_knee_flexed(*source, 150.0f - frame);
    // The second frame also moves the whole body 1 mm, so that every region changes.
    pose.root_translation += glm::vec3(0.0f, 1e-3f * frame, 0.0f);
    deform::DeformJob{.runtime = *f.runtime, .pose = pose, .positions = f.posed[frame]}.run(
        f.contexts[frame]);
  }
  return made[model].get();
}

// The frame a model's next benchmark starts from: the alternation goes on from its last run, so
// a run's first frame is never the positions the GPU detector saw last (those it would answer
// with no GPU work).
std::size_t& next_frame(int model) {
  static std::size_t next[2] = {0, 0};
  return next[model];
}

// Pairs over every collision region per frame. Arguments: model (0 male, 1 mannequin 72k),
// detector (0 CPU reference on one core, 1 GPU called region by region, 2 GPU detect_all).
void BM_RegionsPerFrame(benchmark::State& state) {
  PosedFrames* f = posed_frames(static_cast<int>(state.range(0)));
  if (f == nullptr) return state.SkipWithError("shared male absent");
  const deform::CollisionRegions& regions = f->runtime->collision().regions;
  gpu::CollisionDetector* detector = state.range(1) ? gpu_detector() : nullptr;
  if (state.range(1) && detector == nullptr) return state.SkipWithError("no GL context");
  deform::SelfIntersectionDetector cpu;
  std::vector<std::span<const std::uint32_t>> lists;
  for (const deform::CollisionRegion& region : regions.regions) lists.push_back(region.triangles);
  std::vector<std::vector<deform::TrianglePair>> pairs(lists.size());
  std::size_t found = 0, triangles = 0, frames = 0, submissions = 0, undecided = 0;
  std::size_t entries = 0, candidates = 0;
  std::size_t& frame_index = next_frame(static_cast<int>(state.range(0)));
  gpu::CollisionTimings spent;  // the GPU calls' stages, summed
  auto count = [&] {
    submissions += static_cast<std::size_t>(detector->last_stats().submissions);
    undecided += detector->last_stats().undecided;
    entries += detector->last_stats().entries;
    candidates += detector->last_stats().candidates;
    spent.upload += detector->last_timings().upload;
    spent.dispatch += detector->last_timings().dispatch;
    spent.readback += detector->last_timings().readback;
  };
  // One buffer the frames are copied into (as a deformation job writes its output), for both.
  std::vector<glm::vec3> positions(f->posed[0].size());
  for (auto _ : state) {
    const std::vector<glm::vec3>& frame = f->posed[frame_index++ % 2];
    ++frames;
    std::copy(frame.begin(), frame.end(), positions.begin());
    if (state.range(1) == 2) {
      detector->detect_all(positions, regions.welded_indices, lists, pairs);
      count();
    } else {
      for (std::size_t l = 0; l < lists.size(); ++l) {
        if (detector) {
          detector->detect(positions, regions.welded_indices, lists[l], pairs[l]);
          count();
        } else {
          cpu.detect(positions, regions.welded_indices, lists[l], pairs[l]);
        }
      }
    }
    found = triangles = 0;
    for (std::size_t l = 0; l < lists.size(); ++l) {
      found += pairs[l].size();
      triangles += lists[l].size();
    }
  }
  state.counters["pairs"] = static_cast<double>(found);
  state.counters["triangles"] = static_cast<double>(triangles);
  state.counters["submissions"] = static_cast<double>(submissions) / static_cast<double>(frames);
  state.counters["undecided"] = static_cast<double>(undecided) / static_cast<double>(frames);
  auto per_frame_ms = [&](std::chrono::nanoseconds t) {
    return std::chrono::duration<double, std::milli>(t).count() / static_cast<double>(frames);
  };
  if (detector) {
    state.counters["entries"] = static_cast<double>(entries) / static_cast<double>(frames);
    state.counters["candidates"] = static_cast<double>(candidates) / static_cast<double>(frames);
    state.counters["upload_ms"] = per_frame_ms(spent.upload);
    state.counters["dispatch_ms"] = per_frame_ms(spent.dispatch);
    state.counters["readback_ms"] = per_frame_ms(spent.readback);
  }
}

// The whole feature pass per frame on the male (detect, fold/relax rounds, protrusion), CPU or
// GPU pairs, frames alternating between 150° and 149°.
void BM_CollisionFeatures(benchmark::State& state) {
  PosedFrames* f = posed_frames(0);
  if (f == nullptr) return state.SkipWithError("shared male absent");
  gpu::CollisionDetector* detector = state.range(0) ? gpu_detector() : nullptr;
  if (state.range(0) && detector == nullptr) return state.SkipWithError("no GL context");
  deform::CollisionFeatures features(f->runtime->collision());
  const deform::DetectPairs hook = detector ? gpu_hook(*detector) : deform::DetectPairs{};
  std::vector<glm::vec3> positions = f->posed[0];
  deform::FeatureReport report;
  for (auto _ : state) {
    const int frame = static_cast<int>(next_frame(0)++ % 2);
    state.PauseTiming();
    positions = f->posed[frame];
    state.ResumeTiming();
    report = features.apply(f->contexts[frame].skinning(), positions, hook);
  }
  state.counters["pairs_before"] = report.pairs_before;
  state.counters["pairs_after"] = report.pairs_after;
  state.counters["folded"] = report.folded;
}

// ---- Whole body (contact) ----

constexpr int kWorstContactFrame = 4250;  // of cmu_01_03, see the header comment

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
  // Frames alternate with a copy moved 1 mm sideways (the same pairs): the GPU detector answers
  // unchanged positions from its last submission, which would time nothing.
  const std::vector<glm::vec3>& posed = s->posed[state.range(1)];
  std::vector<glm::vec3> moved = posed;
  for (glm::vec3& p : moved) p.x += 1e-3f;
  const deform::CollisionModel& model = s->runtime->collision();
  const int backend = static_cast<int>(state.range(2));
  int frame = 0;
  gpu::CollisionDetector* detector = backend == 2 ? gpu_detector() : nullptr;
  if (backend == 2 && detector == nullptr) return state.SkipWithError("no GL context");
  const int threads = backend == 0 ? 1 : static_cast<int>(std::thread::hardware_concurrency());
  deform::WholeBodyDetector cpu;
  deform::SelfIntersectionDetector grid;
  std::vector<deform::TrianglePair> pairs;
  for (auto _ : state) {
    const std::vector<glm::vec3>& positions = ++frame % 2 ? moved : posed;
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
BENCHMARK(BM_RegionsPerFrame)
    ->ArgNames({"model", "gpu"})
    ->ArgsProduct({{0, 1}, {0, 1, 2}})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CollisionFeatures)->ArgName("gpu")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
