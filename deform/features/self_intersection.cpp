#include "deform/features/self_intersection.h"

#include <algorithm>
#include <cmath>

#include "deform/features/triangle_intersection.h"

namespace sweepd::deform {

TriangleBox triangle_box(std::span<const glm::vec3> positions,
                         std::span<const std::uint32_t> indices, std::uint32_t triangle) {
  const glm::vec3& p = positions[indices[3 * triangle]];
  const glm::vec3& q = positions[indices[3 * triangle + 1]];
  const glm::vec3& r = positions[indices[3 * triangle + 2]];
  return {glm::min(p, glm::min(q, r)), glm::max(p, glm::max(q, r))};
}

bool finite_triangle(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
                     std::uint32_t triangle) {
  for (int k = 0; k < 3; ++k) {
    const glm::vec3& p = positions[indices[3 * triangle + k]];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return false;
  }
  return true;
}

bool mesh_triangles_intersect(std::span<const glm::vec3> positions,
                              std::span<const std::uint32_t> indices, std::uint32_t a,
                              std::uint32_t b) {
  const glm::vec3 ta[3] = {positions[indices[3 * a]], positions[indices[3 * a + 1]],
                           positions[indices[3 * a + 2]]};
  const glm::vec3 tb[3] = {positions[indices[3 * b]], positions[indices[3 * b + 1]],
                           positions[indices[3 * b + 2]]};
  return triangles_intersect(ta, tb);
}

void SelfIntersectionDetector::detect(std::span<const glm::vec3> positions,
                                      std::span<const std::uint32_t> indices,
                                      std::span<const std::uint32_t> triangles,
                                      std::vector<TrianglePair>& pairs) {
  pairs.clear();
  if (triangles.size() < 2) return;
  boxes_.resize(triangles.size());
  finite_slots_.clear();
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  double extent_sum = 0.0;
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    // A triangle with a non-finite corner has no place in space and meets nothing; kept, it
    // would make the grid's extent infinite or NaN and its float-to-int cell casts undefined.
    if (!finite_triangle(positions, indices, triangles[i])) continue;
    finite_slots_.push_back(static_cast<std::uint32_t>(i));
    boxes_[i] = triangle_box(positions, indices, triangles[i]);
    lo = glm::min(lo, boxes_[i].lo);
    hi = glm::max(hi, boxes_[i].hi);
    const glm::vec3 size = boxes_[i].hi - boxes_[i].lo;
    extent_sum += std::max(size.x, std::max(size.y, size.z));
  }
  if (finite_slots_.size() < 2) return;
  // Cells about one triangle wide, at most 1024 per axis (keys stay well inside 64 bits).
  const glm::vec3 span = hi - lo;
  float cell = static_cast<float>(extent_sum / static_cast<double>(finite_slots_.size()));
  cell = std::max({cell, span.x / 1024.0f, span.y / 1024.0f, span.z / 1024.0f, 1e-30f});
  const glm::ivec3 dims = glm::ivec3(span / cell) + 1;
  auto cell_of = [&](const glm::vec3& p) {
    return glm::clamp(glm::ivec3((p - lo) / cell), glm::ivec3(0), dims - 1);
  };
  auto key_of = [&](const glm::ivec3& c) {
    return (static_cast<std::uint64_t>(c.x) * static_cast<std::uint64_t>(dims.y) +
            static_cast<std::uint64_t>(c.y)) *
               static_cast<std::uint64_t>(dims.z) +
           static_cast<std::uint64_t>(c.z);
  };

  entries_.clear();
  for (const std::uint32_t i : finite_slots_) {
    const glm::ivec3 c0 = cell_of(boxes_[i].lo), c1 = cell_of(boxes_[i].hi);
    for (int x = c0.x; x <= c1.x; ++x) {
      for (int y = c0.y; y <= c1.y; ++y) {
        for (int z = c0.z; z <= c1.z; ++z) {
          entries_.push_back({key_of({x, y, z}), i});
        }
      }
    }
  }
  std::sort(entries_.begin(), entries_.end());

  for (std::size_t begin = 0; begin < entries_.size();) {
    std::size_t end = begin + 1;
    while (end < entries_.size() && entries_[end].cell == entries_[begin].cell) ++end;
    for (std::size_t i = begin; i < end; ++i) {
      for (std::size_t j = i + 1; j < end; ++j) {
        const TriangleBox& a = boxes_[entries_[i].slot];
        const TriangleBox& b = boxes_[entries_[j].slot];
        if (!boxes_overlap(a, b)) continue;
        // Only in the cell that holds the overlap's lower corner: each pair once.
        if (key_of(cell_of(glm::max(a.lo, b.lo))) != entries_[begin].cell) continue;
        std::uint32_t s = triangles[entries_[i].slot], t = triangles[entries_[j].slot];
        if (s > t) std::swap(s, t);
        if (s == t || share_a_vertex(indices, s, t)) continue;
        if (mesh_triangles_intersect(positions, indices, s, t)) pairs.push_back({s, t});
      }
    }
    begin = end;
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
}

}  // namespace sweepd::deform
