// Binding benchmark (paper §3): bind() on the procedural mannequin at about 72k vertices (the
// paper's scale) and on the shared male, one thread. The target: at most 1 s for 72k.
// Run a Release build: build/<dir>/bench/bind_bench
#include <benchmark/benchmark.h>

#include "bench/bench_models.h"
#include "deform/binding/bind.h"
#include "deform/rig/rig_map.h"

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
  benchmark::RegisterBenchmark("bind/mannequin_72k", run_bind, &bench::mannequin_72k())
      ->Unit(benchmark::kMillisecond);
  if (const deform::Model* male = bench::shared_male())
    benchmark::RegisterBenchmark("bind/male", run_bind, male)->Unit(benchmark::kMillisecond);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
