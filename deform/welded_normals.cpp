#include "deform/welded_normals.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "deform/mesh_topology.h"

namespace sweepd::deform {

namespace {

FloatLanes lanes_of(const glm::vec3& p) { return FloatLanes{p.x, p.y, p.z, 0.0f}; }

FloatLanes cross(FloatLanes u, FloatLanes v) {
  const FloatLanes u_yzx = __builtin_shufflevector(u, u, 1, 2, 0, 3);
  const FloatLanes v_yzx = __builtin_shufflevector(v, v, 1, 2, 0, 3);
  const FloatLanes c_zxy = u * v_yzx - u_yzx * v;
  return __builtin_shufflevector(c_zxy, c_zxy, 1, 2, 0, 3);
}

}  // namespace

WeldedNormals::WeldedNormals(std::span<const glm::vec3> rest_positions,
                             std::span<const std::uint32_t> indices)
    : corner_vertex_(indices.begin(), indices.end()) {
  if (indices.size() % 3 != 0)
    throw std::invalid_argument("welded normals: " + std::to_string(indices.size()) +
                                " triangle indices, not a multiple of 3");
  for (const std::uint32_t v : corner_vertex_)
    if (v >= rest_positions.size())
      throw std::invalid_argument("welded normals: triangle corner " + std::to_string(v) +
                                  " past " + std::to_string(rest_positions.size()) + " vertices");
  std::size_t welded_count = 0;
  welded_ = weld_coincident_positions(rest_positions, &welded_count);
  sums_.resize(welded_count);
  corner_welded_.reserve(corner_vertex_.size());
  for (const std::uint32_t v : corner_vertex_) corner_welded_.push_back(welded_[v]);
}

void WeldedNormals::compute(std::span<const glm::vec3> positions, std::span<glm::vec3> normals) {
  std::fill(sums_.begin(), sums_.end(), FloatLanes{0.0f, 0.0f, 0.0f, 0.0f});
  const std::uint32_t* vertex = corner_vertex_.data();
  const std::uint32_t* welded = corner_welded_.data();
  FloatLanes* sums = sums_.data();
  for (std::size_t corner = 0; corner < corner_vertex_.size(); corner += 3) {
    const FloatLanes a = lanes_of(positions[vertex[corner]]);
    const FloatLanes area_normal = cross(lanes_of(positions[vertex[corner + 1]]) - a,
                                         lanes_of(positions[vertex[corner + 2]]) - a);
    sums[welded[corner]] += area_normal;
    sums[welded[corner + 1]] += area_normal;
    sums[welded[corner + 2]] += area_normal;
  }
  for (std::size_t v = 0; v < normals.size(); ++v) {
    const FloatLanes n = sums[welded_[v]];
    const float length_squared = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
    if (length_squared > 0.0f) {
      const FloatLanes unit = n * (1.0f / std::sqrt(length_squared));
      normals[v] = glm::vec3(unit[0], unit[1], unit[2]);
    } else {
      normals[v] = glm::vec3(0.0f, 1.0f, 0.0f);
    }
  }
}

}  // namespace sweepd::deform
