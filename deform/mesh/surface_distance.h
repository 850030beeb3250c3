// Surface distance: for every vertex of a triangle mesh, the length of the shortest path along
// the mesh's edges (Dijkstra) to the nearest vertex of a source set. Binding uses it for the
// neck's hand-over to the head, which grows with the distance from where the head's skin
// weight starts (deform/blending/sweep_blending.h).
// Inputs:  positions  n vertex positions (weld UV-seam copies first: seams cut paths);
//          indices    triangle corners, 3 per triangle, each < n;
//          is_source  n flags.
// Output:  n distances in the positions' unit: 0 at sources, +infinity where none is reachable.
// Throws std::invalid_argument for mismatched sizes or an index out of range.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

namespace sweepd::deform {

std::vector<float> distance_along_edges(std::span<const glm::vec3> positions,
                                        std::span<const std::uint32_t> indices,
                                        const std::vector<bool>& is_source);

}  // namespace sweepd::deform
