#include "deform/mesh/welded_mesh.h"

#include "deform/mesh/mesh_topology.h"

namespace sweepd::deform {

WeldedMesh weld_mesh(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices) {
  WeldedMesh mesh;
  std::size_t welded_count = 0;
  mesh.welded_id = weld_coincident_positions(positions, &welded_count);
  mesh.positions.resize(welded_count);
  for (std::size_t v = 0; v < positions.size(); ++v)
    mesh.positions[mesh.welded_id[v]] = positions[v];
  mesh.indices.resize(indices.size());
  for (std::size_t i = 0; i < indices.size(); ++i) mesh.indices[i] = mesh.welded_id[indices[i]];
  mesh.adjacency = vertex_adjacency(mesh.positions, mesh.indices);
  return mesh;
}

}  // namespace sweepd::deform
