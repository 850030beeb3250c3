#include "deform/binding/mesh_parts_joined.h"

#include <algorithm>
#include <numeric>

#include "deform/mesh/mesh_topology.h"

namespace sweepd::deform {

namespace {

int root_of(std::vector<int>& parent, int k) {
  while (parent[k] != k) k = parent[k] = parent[parent[k]];
  return k;
}

}  // namespace

std::vector<std::uint8_t> mesh_parts_joined(const Model& model) {
  const std::size_t parts = model.parts.size();
  std::vector<std::uint8_t> joined(parts, 0);
  int largest = -1;
  for (std::size_t k = 0; k < parts; ++k)
    if (model.parts[k].rigid_joint < 0 &&
        (largest < 0 || model.parts[k].vertex_count > model.parts[largest].vertex_count))
      largest = static_cast<int>(k);
  if (largest < 0) return joined;
  // Skinned parts that share a welded position fall into one set.
  std::size_t welded_count = 0;
  const std::vector<std::uint32_t> welded =
      weld_coincident_positions(model.positions, &welded_count);
  std::vector<int> first_part(welded_count, -1);
  std::vector<int> parent(parts);
  std::iota(parent.begin(), parent.end(), 0);
  for (std::size_t k = 0; k < parts; ++k) {
    const MeshPart& part = model.parts[k];
    if (part.rigid_joint >= 0) continue;
    for (std::uint32_t v = part.first_vertex; v < part.first_vertex + part.vertex_count; ++v) {
      int& seen = first_part[welded[v]];
      if (seen < 0)
        seen = static_cast<int>(k);
      else
        parent[root_of(parent, static_cast<int>(k))] = root_of(parent, seen);
    }
  }
  const int body = root_of(parent, largest);
  for (std::size_t k = 0; k < parts; ++k)
    joined[k] = model.parts[k].rigid_joint < 0 && root_of(parent, static_cast<int>(k)) == body;
  return joined;
}

std::vector<std::uint8_t> vertices_joined(const Model& model) {
  std::vector<std::uint8_t> joined(model.vertex_count(), 1);
  const std::vector<std::uint8_t> parts = mesh_parts_joined(model);
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const MeshPart& part = model.parts[k];
    std::fill_n(joined.begin() + part.first_vertex, part.vertex_count, parts[k]);
  }
  return joined;
}

}  // namespace sweepd::deform
