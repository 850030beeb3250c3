// Deformation benchmark: control sweeps (the paper) against the LBS and DQS baselines (4
// influences), one thread, in ns per vertex on the procedural mannequin at about 15k, 72k and
// 250k vertices and on the shared MakeHuman male, positions only and positions + normals.
// Sweep includes its per-frame work (posing the key ellipses, rebuilding C(t) and Q(t), refreshing
// the sample table); its normals are recomputed from the posed triangles (area-weighted), the
// baselines' are turned. "sweep" runs the widest vertex loops the CPU has; where that is AVX2,
// "sweep_sse2" rows time the x86-64 baseline's loops too.
// bench/run_benchmarks.sh prints the table (with the sweep/LBS ratio) for docs/performance.md.
//
// Run a Release build: build/<dir>/bench/deform_bench [--benchmark_filter=...]
// The "per_vertex" counter is the time per vertex (Google Benchmark prints it in seconds with
// an SI prefix: "2.1n" = 2.1 ns). The pose bends every joint; its cost is outside the timing
// except for the per-frame matrix conversion DQS does itself. The "sweep_stage" rows time a sweep
// pose's stages apart (posing: per frame; vertices and normals: per vertex). The "split" rows
// time one 250k pose split over 1, 2, 4, … threads (up to the cores) in wall time: one client's
// latency.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "deform/baselines/dual_quaternion_skinning.h"
#include "deform/baselines/linear_blend_skinning.h"
#include "deform/binding/bind.h"
#include "deform/mesh/welded_normals.h"
#include "deform/model/forward_kinematics.h"
#include "deform/posing/sweep_poser.h"
#include "deform/rig/rig_map.h"
#include "io/gltf/gltf_load.h"
#include "mannequin/mannequin.h"
#include "tests/test_paths.h"

namespace {

using namespace sweepd;

struct BenchModel {
  std::string name;
  deform::Model model;
  std::vector<glm::mat4> world, skinning;
  std::unique_ptr<deform::BoundModel> bound;
  std::vector<std::unique_ptr<deform::SkinningTable>> tables;  // per instruction set
};

// Every joint turned 0.3 rad about one oblique axis (the cost does not depend on the angles).
void bend(BenchModel& subject) {
  const deform::Skeleton& skeleton = subject.model.skeleton;
  deform::Pose pose = deform::rest_pose(skeleton);
  const glm::quat bend = glm::angleAxis(0.3f, glm::normalize(glm::vec3(1, 2, 3)));
  for (glm::quat& rotation : pose.local_rotations) rotation = rotation * bend;
  subject.world.resize(skeleton.joints.size());
  subject.skinning.resize(skeleton.joints.size());
  deform::forward_kinematics(skeleton, pose, subject.world);
  deform::skinning_matrices(subject.world, deform::world_rest_inverse_matrices(skeleton),
                            subject.skinning);
}

// The "per_vertex" counter: seconds per vertex of one frame.
void report_per_vertex(benchmark::State& state, std::size_t n) {
  state.counters["vertices"] = static_cast<double>(n);
  state.counters["per_vertex"] =
      benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate |
                                                     benchmark::Counter::kInvert);
}

using Skin = void (*)(const deform::SkinningTable&, std::span<const glm::mat4>,
                      std::span<glm::vec3>, std::span<glm::vec3>, int);

void run(benchmark::State& state, const BenchModel* subject, const deform::SkinningTable* table,
         Skin skin, bool with_normals) {
  const std::size_t n = subject->model.vertex_count();
  std::vector<glm::vec3> positions(n), normals(with_normals ? n : 0);
  for (auto _ : state) {
    skin(*table, subject->skinning, positions, normals, 1);
    benchmark::DoNotOptimize(positions.data());
    benchmark::DoNotOptimize(normals.data());
    benchmark::ClobberMemory();
  }
  report_per_vertex(state, n);
}

void run_sweep(benchmark::State& state, const BenchModel* subject,
               deform::VertexLoopInstructions instructions, bool with_normals, int threads) {
  const std::size_t n = subject->model.vertex_count();
  std::vector<glm::vec3> positions(n), normals(with_normals ? n : 0);
  deform::SweepPoser poser(*subject->bound, instructions);
  for (auto _ : state) {
    poser.set_pose(subject->world);
    poser.deform(subject->skinning, positions, normals, threads);
    benchmark::DoNotOptimize(positions.data());
    benchmark::DoNotOptimize(normals.data());
    benchmark::ClobberMemory();
  }
  report_per_vertex(state, n);
}

enum class SweepStage { kPosing, kVertices, kNormals };

// One stage of a sweep pose (widest loops): "posing" is set_pose alone (the keys, the curves,
// the sample table: per frame, whatever the vertex count), "vertices" deform alone (positions),
// "normals" the normals recomputed from the posed positions alone (WeldedNormals, one thread).
void run_sweep_stage(benchmark::State& state, const BenchModel* subject, SweepStage stage) {
  const std::size_t n = subject->model.vertex_count();
  std::vector<glm::vec3> positions(n), normals(n);
  std::vector<deform::FloatLanes> normal_scratch;
  deform::SweepPoser poser(*subject->bound);
  const deform::WeldedNormals welded(subject->model.positions, subject->model.indices);
  poser.set_pose(subject->world);
  poser.deform(subject->skinning, positions, {}, 1);
  for (auto _ : state) {
    if (stage == SweepStage::kPosing)
      poser.set_pose(subject->world);
    else if (stage == SweepStage::kVertices)
      poser.deform(subject->skinning, positions, {}, 1);
    else
      welded.compute(positions, normals, normal_scratch);
    benchmark::DoNotOptimize(positions.data());
    benchmark::DoNotOptimize(normals.data());
    benchmark::ClobberMemory();
  }
  report_per_vertex(state, n);
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  std::vector<std::unique_ptr<BenchModel>> models;
  for (int target : {15000, 72000, 250000}) {
    deform::Model model = mannequin::make_mannequin({.target_vertices = target});
    const std::string name = "mannequin_" + std::to_string(target / 1000) + "k";
    models.push_back(
        std::make_unique<BenchModel>(BenchModel{name, std::move(model), {}, {}, {}, {}}));
  }
  const std::filesystem::path male =
      std::filesystem::path(SWEEPD_SHARED_DATA) / "models" / "makehuman_male_cmu.glb";
  if (std::filesystem::exists(male)) {
    models.push_back(
        std::make_unique<BenchModel>(BenchModel{"male", io::load_gltf(male), {}, {}, {}, {}}));
  } else {
    std::fprintf(stderr, "shared male absent (%s): benchmarking the mannequins only\n",
                 male.string().c_str());
  }
  for (const auto& subject : models) {
    bend(*subject);
    subject->bound = std::make_unique<deform::BoundModel>(
        deform::bind(subject->model, deform::detect_rig_map(subject->model.skeleton)));
    // "sweep", "lbs", "dqs": the widest vertex loops this CPU has; "…_sse2": the x86-64
    // baseline's.
    std::vector<std::pair<std::string, deform::VertexLoopInstructions>> sets = {
        {"", deform::widest_vertex_loop_instructions()}};
    if (sets[0].second != deform::VertexLoopInstructions::kBaseline)
      sets.emplace_back("_sse2", deform::VertexLoopInstructions::kBaseline);
    const auto row = [&](const std::string& method, const std::string& suffix, bool normals) {
      return method + suffix + "/" + subject->name + "/" +
             (normals ? "positions+normals" : "positions");
    };
    for (const auto& [suffix, instructions] : sets) {
      subject->tables.push_back(
          std::make_unique<deform::SkinningTable>(subject->model, instructions));
      for (const bool with_normals : {false, true}) {
        benchmark::RegisterBenchmark(row("sweep", suffix, with_normals).c_str(), run_sweep,
                                     subject.get(), instructions, with_normals, 1)
            ->Unit(benchmark::kMicrosecond);
        for (const auto& [method, skin] :
             {std::pair<const char*, Skin>{"lbs", deform::linear_blend_skinning},
              std::pair<const char*, Skin>{"dqs", deform::dual_quaternion_skinning}})
          benchmark::RegisterBenchmark(row(method, suffix, with_normals).c_str(), run,
                                       subject.get(), subject->tables.back().get(), skin,
                                       with_normals)
              ->Unit(benchmark::kMicrosecond);
      }
    }
  }
  // Where a sweep pose's time goes (issue 50 item 2).
  for (const auto& subject : models)
    for (const auto& [stage, name] : {std::pair{SweepStage::kPosing, "posing"},
                                      std::pair{SweepStage::kVertices, "vertices"},
                                      std::pair{SweepStage::kNormals, "normals"}})
      benchmark::RegisterBenchmark(("sweep_stage/" + subject->name + "/" + name).c_str(),
                                   run_sweep_stage, subject.get(), stage)
          ->Unit(benchmark::kMicrosecond);
  // One pose split over threads (issue 50 item 3): wall time, the latency a client sees.
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  for (const auto& subject : models) {
    if (subject->name != "mannequin_250k") continue;
    for (const bool with_normals : {false, true})
      for (int threads = 1; threads <= cores; threads *= 2)
        benchmark::RegisterBenchmark(("split/" + subject->name + "/" +
                                      (with_normals ? "positions+normals" : "positions") +
                                      "/threads:" + std::to_string(threads))
                                         .c_str(),
                                     run_sweep, subject.get(),
                                     deform::widest_vertex_loop_instructions(), with_normals,
                                     threads)
            ->Unit(benchmark::kMicrosecond)
            ->UseRealTime();
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
