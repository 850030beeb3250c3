// Bind-time mesh adjacency, two ways (deform/README.md, "Mesh topology at bind time"): the
// welded mesh's flat compressed rows (weld_mesh: weld, then vertex_adjacency), against
// OpenMesh's halfedge mesh (to_tri_mesh: weld, then add_face) walked ring by ring into the same
// rows, each ring sorted ascending as the bind's float sums need. On the procedural mannequin at
// about 72k vertices and on the shared male, one thread.
// Run a Release build: build/<dir>/bench/mesh_adjacency_bench
#include <benchmark/benchmark.h>

#include <algorithm>
#include <utility>

#include "bench/bench_models.h"
#include "deform/mesh/mesh_topology.h"
#include "deform/mesh/welded_mesh.h"

namespace {

using namespace sweepd;

void flat_arrays(benchmark::State& state, const deform::Model* model) {
  for (auto _ : state)
    benchmark::DoNotOptimize(deform::weld_mesh(model->positions, model->indices));
  state.counters["vertices"] = static_cast<double>(model->vertex_count());
}

void openmesh_halfedges(benchmark::State& state, const deform::Model* model) {
  std::vector<std::pair<std::uint32_t, float>> ring;
  for (auto _ : state) {
    const deform::TriMesh mesh = deform::to_tri_mesh(model->positions, model->indices);
    deform::VertexAdjacency adjacency;
    adjacency.row_start.assign(1, 0);
    for (const deform::TriMesh::VertexHandle v : mesh.vertices()) {
      ring.clear();
      for (const deform::TriMesh::VertexHandle u : mesh.vv_range(v))
        ring.emplace_back(static_cast<std::uint32_t>(u.idx()),
                          (mesh.point(u) - mesh.point(v)).norm());
      std::sort(ring.begin(), ring.end());
      for (const auto& [u, length] : ring) {
        adjacency.neighbour.push_back(u);
        adjacency.edge_length.push_back(length);
      }
      adjacency.row_start.push_back(static_cast<std::uint32_t>(adjacency.neighbour.size()));
    }
    benchmark::DoNotOptimize(adjacency);
  }
  state.counters["vertices"] = static_cast<double>(model->vertex_count());
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  const deform::Model& mannequin = bench::mannequin_72k();
  benchmark::RegisterBenchmark("adjacency/flat/mannequin_72k", flat_arrays, &mannequin)
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("adjacency/openmesh/mannequin_72k", openmesh_halfedges, &mannequin)
      ->Unit(benchmark::kMillisecond);
  if (const deform::Model* male = bench::shared_male()) {
    benchmark::RegisterBenchmark("adjacency/flat/male", flat_arrays, male)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark("adjacency/openmesh/male", openmesh_halfedges, male)
        ->Unit(benchmark::kMillisecond);
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
