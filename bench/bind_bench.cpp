// Binding benchmark (paper §3): bind() on the procedural mannequin at about 72k vertices (the
// paper's scale) and on the shared male, one thread. The target: at most 1 s for 72k.
// Run a Release build: build/<dir>/bench/bind_bench
#include <benchmark/benchmark.h>

#include <filesystem>

#include "deform/binding/bind.h"
#include "deform/rig/rig_map.h"
#include "io/gltf_load.h"
#include "mannequin/mannequin.h"

namespace {

using namespace sweepd;

void run_bind(benchmark::State& state, const deform::Model* model) {
  const deform::RigMap rig = deform::detect_rig_map(model->skeleton);
  for (auto _ : state) benchmark::DoNotOptimize(deform::bind(*model, rig));
  state.counters["vertices"] = static_cast<double>(model->vertex_count());
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  static const deform::Model mannequin = mannequin::make_mannequin({.target_vertices = 72000});
  benchmark::RegisterBenchmark("bind/mannequin_72k", run_bind, &mannequin)
      ->Unit(benchmark::kMillisecond);
  const std::filesystem::path male =
      std::filesystem::path(SWEEPD_SHARED_DATA) / "models" / "makehuman_male_cmu.glb";
  static deform::Model male_model;
  if (std::filesystem::exists(male)) {
    male_model = io::load_gltf(male);
    benchmark::RegisterBenchmark("bind/male", run_bind, &male_model)->Unit(benchmark::kMillisecond);
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
