#include "deform/mesh/welded_normals.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include "deform/mesh/mesh_topology.h"

namespace sweepd::deform {

namespace {

FloatLanes lanes_of(const glm::vec3& p) { return FloatLanes{p.x, p.y, p.z, 0.0f}; }

FloatLanes cross(FloatLanes u, FloatLanes v) {
  const FloatLanes u_yzx = __builtin_shufflevector(u, u, 1, 2, 0, 3);
  const FloatLanes v_yzx = __builtin_shufflevector(v, v, 1, 2, 0, 3);
  const FloatLanes c_zxy = u * v_yzx - u_yzx * v;
  return __builtin_shufflevector(c_zxy, c_zxy, 1, 2, 0, 3);
}

// 1 / √x lane by lane (x86-64: one sqrtps, one divps).
FloatLanes inverse_square_roots(FloatLanes x) {
#if defined(__SSE2__)
  return _mm_div_ps(_mm_set1_ps(1.0f), _mm_sqrt_ps(x));
#else
  return FloatLanes{1.0f / std::sqrt(x[0]), 1.0f / std::sqrt(x[1]), 1.0f / std::sqrt(x[2]),
                    1.0f / std::sqrt(x[3])};
#endif
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
  sum_count_ = (welded_count + 3) / 4 * 4;
  corner_welded_.reserve(corner_vertex_.size());
  for (const std::uint32_t v : corner_vertex_) corner_welded_.push_back(welded_[v]);
}

void WeldedNormals::compute(std::span<const glm::vec3> positions, std::span<glm::vec3> normals,
                            std::vector<FloatLanes>& frame_sums) const {
  if (positions.size() != welded_.size() || normals.size() != positions.size())
    throw std::invalid_argument("welded normals: " + std::to_string(positions.size()) +
                                " positions and " + std::to_string(normals.size()) +
                                " normals for " + std::to_string(welded_.size()) + " vertices");
  frame_sums.resize(sum_count());
  std::fill(frame_sums.begin(), frame_sums.end(), FloatLanes{0.0f, 0.0f, 0.0f, 0.0f});
  const std::uint32_t* vertex = corner_vertex_.data();
  const std::uint32_t* welded = corner_welded_.data();
  FloatLanes* sums = frame_sums.data();
  for (std::size_t corner = 0; corner < corner_vertex_.size(); corner += 3) {
    const FloatLanes a = lanes_of(positions[vertex[corner]]);
    const FloatLanes area_normal = cross(lanes_of(positions[vertex[corner + 1]]) - a,
                                         lanes_of(positions[vertex[corner + 2]]) - a);
    sums[welded[corner]] += area_normal;
    sums[welded[corner + 1]] += area_normal;
    sums[welded[corner + 2]] += area_normal;
  }
  // Unit sums, four at a time (one square root and one division for four on x86-64); frame_sums
  // holds a multiple of four (the padding stays zero).
  for (std::size_t w = 0; w < frame_sums.size(); w += 4) {
    FloatLanes* n = sums + w;
    const FloatLanes x0y0x1y1 = __builtin_shufflevector(n[0] * n[0], n[1] * n[1], 0, 4, 1, 5);
    const FloatLanes x2y2x3y3 = __builtin_shufflevector(n[2] * n[2], n[3] * n[3], 0, 4, 1, 5);
    const FloatLanes z0z1 = __builtin_shufflevector(n[0] * n[0], n[1] * n[1], 2, 6, 3, 7);
    const FloatLanes z2z3 = __builtin_shufflevector(n[2] * n[2], n[3] * n[3], 2, 6, 3, 7);
    const FloatLanes length_squared = (__builtin_shufflevector(x0y0x1y1, x2y2x3y3, 0, 1, 4, 5) +
                                       __builtin_shufflevector(x0y0x1y1, x2y2x3y3, 2, 3, 6, 7)) +
                                      __builtin_shufflevector(z0z1, z2z3, 0, 1, 4, 5);
    const FloatLanes inverse_length = inverse_square_roots(length_squared);
    for (int k = 0; k < 4; ++k)
      n[k] =
          length_squared[k] > 0.0f ? n[k] * inverse_length[k] : FloatLanes{0.0f, 1.0f, 0.0f, 0.0f};
  }
  for (std::size_t v = 0; v < normals.size(); ++v) {
    const FloatLanes& n = sums[welded_[v]];
    normals[v] = glm::vec3(n[0], n[1], n[2]);
  }
}

}  // namespace sweepd::deform
