// Enclosed volume of triangles: the divergence-theorem sum Σ dot(p, cross(q, r)) / 6 over the
// listed triangles of a closed, outward-oriented mesh — the mesh's volume when all triangles
// are listed; over a subset, the difference between two calls is the volume change caused by
// moving only vertices whose triangles are all in the subset (used by skin folding and bone
// protrusion to report their effect on I_C, paper §4.4).
//
// Inputs: positions #V, indices 3 per triangle, triangles: ids to sum over. Output: m³ (double).
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <span>

namespace sweepd::deform {

double enclosed_volume(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
                       std::span<const std::uint32_t> triangles);

}  // namespace sweepd::deform
