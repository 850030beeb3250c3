// StretchHeat: a heat map of edge stretch on the skin (contact sheets' --heat stretch) — per
// vertex the largest |l / l_rest − 1| over the mesh edges at it (the per-edge figure whose
// largest value is metrics::QualityMetrics::largest_edge_stretch), coloured from blue (0)
// through yellow to red (full_scale and above).
//
// StretchHeat(rest positions V, indices 3F): the mesh's edges, each once, and their rest lengths.
// colour(positions V, full_scale > 0, colours V): per-vertex colours in [0, 1] into the
//   caller's buffer (gpu::PreviewMesh::vertex_colours); no allocation.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

namespace sweepd::sheet {

class StretchHeat {
 public:
  StretchHeat(std::span<const glm::vec3> rest_positions, std::span<const std::uint32_t> indices);

  void colour(std::span<const glm::vec3> positions, float full_scale,
              std::span<glm::vec3> colours) const;

 private:
  std::vector<std::uint32_t> edges_;  // 2 per edge
  std::vector<float> rest_length_;
};

}  // namespace sweepd::sheet
