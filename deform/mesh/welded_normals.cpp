#include "deform/mesh/welded_normals.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include "deform/mesh/mesh_topology.h"
#include "deform/simd/vertex_blocks.h"

namespace sweepd::deform {

namespace {

// Position v in lanes 0-2: one 16-byte load where another vertex follows it in the array (lane 3
// then holds that vertex's x, which no caller reads), else three floats.
FloatLanes load_position(const glm::vec3* positions, std::uint32_t v, std::size_t count) {
  if (v + 1 < count) return load_lanes(&positions[v].x);
  return FloatLanes{positions[v].x, positions[v].y, positions[v].z, 0.0f};
}

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

// Four sums made unit vectors in place ((0, 1, 0) for a zero sum): one square root and one
// division for four on x86-64, each lane computed alone, so the grouping changes no bit.
void normalise_four(FloatLanes* n) {
  const FloatLanes x0y0x1y1 = __builtin_shufflevector(n[0] * n[0], n[1] * n[1], 0, 4, 1, 5);
  const FloatLanes x2y2x3y3 = __builtin_shufflevector(n[2] * n[2], n[3] * n[3], 0, 4, 1, 5);
  const FloatLanes z0z1 = __builtin_shufflevector(n[0] * n[0], n[1] * n[1], 2, 6, 3, 7);
  const FloatLanes z2z3 = __builtin_shufflevector(n[2] * n[2], n[3] * n[3], 2, 6, 3, 7);
  const FloatLanes length_squared = (__builtin_shufflevector(x0y0x1y1, x2y2x3y3, 0, 1, 4, 5) +
                                     __builtin_shufflevector(x0y0x1y1, x2y2x3y3, 2, 3, 6, 7)) +
                                    __builtin_shufflevector(z0z1, z2z3, 0, 1, 4, 5);
  const FloatLanes inverse_length = inverse_square_roots(length_squared);
  for (int k = 0; k < 4; ++k)
    n[k] = length_squared[k] > 0.0f ? n[k] * inverse_length[k] : FloatLanes{0.0f, 1.0f, 0.0f, 0.0f};
}

// Area normal (cross product of two edges) of the triangle with corners corner[0..2]; lane 3
// holds no meaning.
FloatLanes area_normal(const glm::vec3* positions, std::size_t count, const std::uint32_t* corner) {
  const FloatLanes a = load_position(positions, corner[0], count);
  return cross(load_position(positions, corner[1], count) - a,
               load_position(positions, corner[2], count) - a);
}

}  // namespace

WeldedNormals::WeldedNormals(std::span<const glm::vec3> rest_positions,
                             std::span<const std::uint32_t> indices) {
  if (indices.size() % 3 != 0)
    throw std::invalid_argument("welded normals: " + std::to_string(indices.size()) +
                                " triangle indices, not a multiple of 3");
  for (const std::uint32_t v : indices)
    if (v >= rest_positions.size())
      throw std::invalid_argument("welded normals: triangle corner " + std::to_string(v) +
                                  " past " + std::to_string(rest_positions.size()) + " vertices");
  std::size_t welded_count = 0;
  welded_ = weld_coincident_positions(rest_positions, &welded_count);
  // Triangles ordered by their first welded vertex, so that the triangles a vertex gathers lie
  // near those of the vertices before it (the gather reads them from memory, not the cache, when
  // a mesh lists its triangles in another order than its vertices).
  const std::size_t triangles = indices.size() / 3;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> order(triangles);
  for (std::size_t t = 0; t < triangles; ++t)
    order[t] = {std::min({welded_[indices[3 * t]], welded_[indices[3 * t + 1]],
                          welded_[indices[3 * t + 2]]}),
                static_cast<std::uint32_t>(t)};
  std::sort(order.begin(), order.end());
  corner_vertex_.reserve(indices.size());
  for (const auto& [first, t] : order)
    corner_vertex_.insert(corner_vertex_.end(), indices.begin() + 3 * t,
                          indices.begin() + 3 * t + 3);
  corner_welded_.reserve(corner_vertex_.size());
  for (const std::uint32_t v : corner_vertex_) corner_welded_.push_back(welded_[v]);
  // Each welded vertex's triangles in ascending order (a triangle with two corners on one
  // welded vertex counts twice, as a scatter would add it twice): the first kSlots in its slots,
  // unused slots naming the zero entry past the last triangle, the rest (poles) in `more_`.
  std::vector<std::vector<std::uint32_t>> around(welded_count);
  for (std::size_t corner = 0; corner < corner_vertex_.size(); ++corner)
    around[welded_[corner_vertex_[corner]]].push_back(static_cast<std::uint32_t>(corner / 3));
  slots_.assign(welded_count * kSlots, static_cast<std::uint32_t>(triangles));
  first_more_.assign(welded_count + 1, 0);
  for (std::size_t w = 0; w < welded_count; ++w) {
    for (std::size_t i = 0; i < around[w].size(); ++i)
      (i < kSlots ? slots_[w * kSlots + i] : more_.emplace_back()) = around[w][i];
    first_more_[w + 1] = static_cast<std::uint32_t>(more_.size());
  }
}

void WeldedNormals::compute(std::span<const glm::vec3> positions, std::span<glm::vec3> normals,
                            std::vector<FloatLanes>& scratch, int threads) const {
  if (positions.size() != welded_.size() || normals.size() != positions.size())
    throw std::invalid_argument("welded normals: " + std::to_string(positions.size()) +
                                " positions and " + std::to_string(normals.size()) +
                                " normals for " + std::to_string(welded_.size()) + " vertices");
  scratch.resize(scratch_count());
  if (threads <= 1) {
    scatter(positions, normals, scratch.data());
  } else {
    gather(positions, normals, scratch.data(), threads);
  }
}

void WeldedNormals::scatter(std::span<const glm::vec3> positions, std::span<glm::vec3> normals,
                            FloatLanes* sums) const {
  const std::size_t welded_count = first_more_.size() - 1;
  std::fill(sums, sums + (welded_count + 3) / 4 * 4, FloatLanes{0.0f, 0.0f, 0.0f, 0.0f});
  const std::uint32_t* welded = corner_welded_.data();
  for (std::size_t corner = 0; corner < corner_vertex_.size(); corner += 3) {
    const FloatLanes n = area_normal(positions.data(), positions.size(), &corner_vertex_[corner]);
    sums[welded[corner]] += n;
    sums[welded[corner + 1]] += n;
    sums[welded[corner + 2]] += n;
  }
  for (std::size_t w = 0; w < welded_count; w += 4) normalise_four(sums + w);
  for (std::size_t v = 0; v < normals.size(); ++v) {
    const FloatLanes& n = sums[welded_[v]];
    normals[v] = glm::vec3(n[0], n[1], n[2]);
  }
}

void WeldedNormals::gather(std::span<const glm::vec3> positions, std::span<glm::vec3> normals,
                           FloatLanes* area_normals, int threads) const {
  const std::size_t triangles = corner_vertex_.size() / 3;
  // Unused slots' entry: adding −0 leaves every float as it is (−0 included), so a vertex's sum
  // is the scatter's to the bit.
  area_normals[triangles] = FloatLanes{-0.0f, -0.0f, -0.0f, -0.0f};
  run_in_vertex_blocks(triangles, threads, [&](std::size_t begin, std::size_t end) {
    for (std::size_t t = begin; t < end; ++t)
      area_normals[t] =
          area_normal(positions.data(), positions.size(), corner_vertex_.data() + 3 * t);
  });
  run_in_vertex_blocks(
      normals.size(), threads,
      [&](std::size_t begin, std::size_t end) {
        for (std::size_t v0 = begin; v0 < end; v0 += 4) {
          const std::size_t count = std::min<std::size_t>(4, end - v0);
          FloatLanes n[4] = {};
          for (std::size_t k = 0; k < count; ++k) {
            const std::uint32_t w = welded_[v0 + k];
            const std::uint32_t* slot = &slots_[std::size_t{w} * kSlots];
            // Summed in a local, which stays in a register (adding into n[k] kept the sum on
            // the stack: each add waited for the last one's store).
            FloatLanes sum = {};
            for (std::size_t i = 0; i < kSlots; ++i) sum += area_normals[slot[i]];
            for (std::uint32_t i = first_more_[w]; i < first_more_[w + 1]; ++i)
              sum += area_normals[more_[i]];
            n[k] = sum;
          }
          normalise_four(n);
          for (std::size_t k = 0; k < count; ++k)
            normals[v0 + k] = glm::vec3(n[k][0], n[k][1], n[k][2]);
        }
      },
      4);
}

}  // namespace sweepd::deform
