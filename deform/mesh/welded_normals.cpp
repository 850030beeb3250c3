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

#if defined(__x86_64__)
// The same for two triangles in one AVX register (corner[0..2] in the low half, corner[3..5] in
// the high half): one rounding where the baseline's has two (FMA).
[[gnu::target("avx2,fma")]] inline __m256 area_normals_of_two(const glm::vec3* positions,
                                                              std::size_t count,
                                                              const std::uint32_t* corner) {
  __m256 c[3];
  for (int k = 0; k < 3; ++k)
    c[k] = _mm256_set_m128(load_position(positions, corner[3 + k], count),
                           load_position(positions, corner[k], count));
  const __m256 u = _mm256_sub_ps(c[1], c[0]);
  const __m256 v = _mm256_sub_ps(c[2], c[0]);
  constexpr int kYzx = _MM_SHUFFLE(3, 0, 2, 1);
  const __m256 c_zxy = _mm256_fmsub_ps(u, _mm256_permute_ps(v, kYzx),
                                       _mm256_mul_ps(_mm256_permute_ps(u, kYzx), v));
  return _mm256_permute_ps(c_zxy, kYzx);
}

// Area normals of the triangles with corners vertex[0, corners) added to their corners' welded
// sums welded[0, corners), two triangles at a time (an odd last one as the low half of a pair
// with itself, as store_area_normals_avx2 computes it).
[[gnu::target("avx2,fma")]] void scatter_area_normals_avx2(const glm::vec3* positions,
                                                           std::size_t count,
                                                           const std::uint32_t* vertex,
                                                           const std::uint32_t* welded,
                                                           std::size_t corners, FloatLanes* sums) {
  std::size_t c = 0;
  for (; c + 6 <= corners; c += 6) {
    const __m256 two = area_normals_of_two(positions, count, vertex + c);
    const FloatLanes first = _mm256_castps256_ps128(two);
    const FloatLanes second = _mm256_extractf128_ps(two, 1);
    sums[welded[c]] += first;
    sums[welded[c + 1]] += first;
    sums[welded[c + 2]] += first;
    sums[welded[c + 3]] += second;
    sums[welded[c + 4]] += second;
    sums[welded[c + 5]] += second;
  }
  if (c < corners) {
    const std::uint32_t twice[6] = {vertex[c], vertex[c + 1], vertex[c + 2],
                                    vertex[c], vertex[c + 1], vertex[c + 2]};
    const FloatLanes last = _mm256_castps256_ps128(area_normals_of_two(positions, count, twice));
    for (int k = 0; k < 3; ++k) sums[welded[c + k]] += last;
  }
}

// Area normals of triangles [begin, end) (begin even) stored at area_normals[t], two at a time.
[[gnu::target("avx2,fma")]] void store_area_normals_avx2(const glm::vec3* positions,
                                                         std::size_t count,
                                                         const std::uint32_t* vertex,
                                                         std::size_t begin, std::size_t end,
                                                         FloatLanes* area_normals) {
  std::size_t t = begin;
  for (; t + 2 <= end; t += 2)
    _mm256_storeu_ps(&area_normals[t][0], area_normals_of_two(positions, count, vertex + 3 * t));
  if (t < end) {
    const std::uint32_t* c = vertex + 3 * t;
    const std::uint32_t twice[6] = {c[0], c[1], c[2], c[0], c[1], c[2]};
    area_normals[t] = _mm256_castps256_ps128(area_normals_of_two(positions, count, twice));
  }
}
#endif

// The baseline's scatter, one triangle at a time.
void scatter_area_normals(const glm::vec3* positions, std::size_t count,
                          const std::uint32_t* vertex, const std::uint32_t* welded,
                          std::size_t corners, FloatLanes* sums) {
  for (std::size_t c = 0; c < corners; c += 3) {
    const FloatLanes n = area_normal(positions, count, vertex + c);
    sums[welded[c]] += n;
    sums[welded[c + 1]] += n;
    sums[welded[c + 2]] += n;
  }
}

}  // namespace

WeldedNormals::WeldedNormals(std::span<const glm::vec3> rest_positions,
                             std::span<const std::uint32_t> indices,
                             VertexLoopInstructions instructions)
    : instructions_(instructions) {
  if (indices.size() % 3 != 0)
    throw std::invalid_argument("welded normals: " + std::to_string(indices.size()) +
                                " triangle indices, not a multiple of 3");
  for (const std::uint32_t v : indices)
    if (v >= rest_positions.size())
      throw std::invalid_argument("welded normals: triangle corner " + std::to_string(v) +
                                  " past " + std::to_string(rest_positions.size()) + " vertices");
  if (instructions == VertexLoopInstructions::kAvx2Fma &&
      widest_vertex_loop_instructions() != VertexLoopInstructions::kAvx2Fma)
    throw std::invalid_argument("welded normals: this CPU has no AVX2 with FMA");
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
#if defined(__x86_64__)
  if (instructions_ == VertexLoopInstructions::kAvx2Fma) {
    scatter_area_normals_avx2(positions.data(), positions.size(), corner_vertex_.data(),
                              corner_welded_.data(), corner_vertex_.size(), sums);
  } else
#endif
  {
    scatter_area_normals(positions.data(), positions.size(), corner_vertex_.data(),
                         corner_welded_.data(), corner_vertex_.size(), sums);
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
  // Blocks of whole pairs: the AVX2 loop pairs triangles as the scatter does.
  run_in_vertex_blocks(
      triangles, threads,
      [&](std::size_t begin, std::size_t end) {
#if defined(__x86_64__)
        if (instructions_ == VertexLoopInstructions::kAvx2Fma) {
          store_area_normals_avx2(positions.data(), positions.size(), corner_vertex_.data(),
                                  begin, end, area_normals);
          return;
        }
#endif
        for (std::size_t t = begin; t < end; ++t)
          area_normals[t] =
              area_normal(positions.data(), positions.size(), corner_vertex_.data() + 3 * t);
      },
      2);
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
