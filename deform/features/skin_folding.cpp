#include "deform/features/skin_folding.h"

#include <algorithm>
#include <cmath>

#include "deform/mesh/enclosed_volume.h"

namespace sweepd::deform {
namespace {

constexpr int kRelaxIterations = 12;
constexpr float kRelaxStep = 0.5f;  // of the way to the neighbours' mean, per iteration

// Eigenvector of the smallest eigenvalue of a symmetric 3x3 matrix (columns c).
glm::dvec3 smallest_eigenvector(const glm::dmat3& c) {
  // Eigenvalues by the trigonometric method (symmetric, so all real).
  const double p1 = c[0][1] * c[0][1] + c[0][2] * c[0][2] + c[1][2] * c[1][2];
  const double q = (c[0][0] + c[1][1] + c[2][2]) / 3.0;
  const double p2 = (c[0][0] - q) * (c[0][0] - q) + (c[1][1] - q) * (c[1][1] - q) +
                    (c[2][2] - q) * (c[2][2] - q) + 2.0 * p1;
  const double p = std::sqrt(p2 / 6.0);
  if (!(p > 0.0)) return {0.0, 0.0, 1.0};  // isotropic: any direction
  const glm::dmat3 b = (c - q * glm::dmat3(1.0)) / p;
  const double r = std::clamp(glm::determinant(b) / 2.0, -1.0, 1.0);
  const double phi = std::acos(r) / 3.0;
  const double smallest = q + 2.0 * p * std::cos(phi + 2.0 * M_PI / 3.0);
  const glm::dmat3 m = c - smallest * glm::dmat3(1.0);
  // The null vector of m: the longest cross product of two of its rows (= columns).
  const glm::dvec3 candidates[3] = {glm::cross(m[0], m[1]), glm::cross(m[0], m[2]),
                                    glm::cross(m[1], m[2])};
  glm::dvec3 best = candidates[0];
  for (const glm::dvec3& v : candidates) {
    if (glm::dot(v, v) > glm::dot(best, best)) best = v;
  }
  return glm::dot(best, best) > 0.0 ? glm::normalize(best) : glm::dvec3(0.0, 0.0, 1.0);
}

}  // namespace

glm::vec3 fit_plane(std::span<const glm::vec3> points, glm::vec3& centroid) {
  glm::dvec3 mean(0.0);
  for (const glm::vec3& p : points) mean += glm::dvec3(p);
  mean /= static_cast<double>(points.size());
  glm::dmat3 covariance(0.0);
  for (const glm::vec3& p : points) {
    const glm::dvec3 d = glm::dvec3(p) - mean;
    covariance += glm::outerProduct(d, d);
  }
  centroid = glm::vec3(mean);
  return glm::vec3(smallest_eigenvector(covariance));
}

std::uint32_t IntersectingGroups::find(std::uint32_t slot) {
  while (parent_[slot] != slot) slot = parent_[slot] = parent_[parent_[slot]];
  return slot;
}

void IntersectingGroups::build(std::span<const std::uint32_t> indices,
                               std::span<const TrianglePair> pairs, std::size_t vertex_count) {
  slot_of_vertex_.resize(std::max(slot_of_vertex_.size(), vertex_count), -1);
  triangles_.clear();
  for (const TrianglePair& p : pairs) triangles_.push_back(p.first), triangles_.push_back(p.second);
  std::sort(triangles_.begin(), triangles_.end());
  triangles_.erase(std::unique(triangles_.begin(), triangles_.end()), triangles_.end());
  auto slot_of = [&](std::uint32_t t) {
    return static_cast<std::uint32_t>(std::lower_bound(triangles_.begin(), triangles_.end(), t) -
                                      triangles_.begin());
  };
  parent_.resize(triangles_.size());
  for (std::uint32_t s = 0; s < parent_.size(); ++s) parent_[s] = s;
  auto unite = [&](std::uint32_t a, std::uint32_t b) { parent_[find(a)] = find(b); };
  for (const TrianglePair& p : pairs) unite(slot_of(p.first), slot_of(p.second));
  for (std::uint32_t s = 0; s < triangles_.size(); ++s) {
    for (int k = 0; k < 3; ++k) {
      std::int32_t& owner = slot_of_vertex_[indices[3 * triangles_[s] + k]];
      if (owner >= 0)
        unite(s, static_cast<std::uint32_t>(owner));
      else
        owner = static_cast<std::int32_t>(s);
    }
  }
  // Slots grouped by their root; a group's distinct vertices are those its slots claimed above.
  order_.resize(triangles_.size());
  for (std::uint32_t slot = 0; slot < triangles_.size(); ++slot) order_[slot] = {find(slot), slot};
  std::sort(order_.begin(), order_.end());
  group_start_.assign(1, 0);
  vertex_start_.assign(1, 0);
  group_triangles_.clear();
  group_vertices_.clear();
  for (std::size_t begin = 0; begin < order_.size();) {
    std::size_t end = begin;
    for (; end < order_.size() && order_[end].first == order_[begin].first; ++end) {
      const std::uint32_t slot = order_[end].second;
      group_triangles_.push_back(triangles_[slot]);
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = indices[3 * triangles_[slot] + k];
        if (slot_of_vertex_[v] == static_cast<std::int32_t>(slot)) group_vertices_.push_back(v);
      }
    }
    group_start_.push_back(static_cast<std::uint32_t>(group_triangles_.size()));
    vertex_start_.push_back(static_cast<std::uint32_t>(group_vertices_.size()));
    begin = end;
  }
  for (std::uint32_t t : triangles_) {
    for (int k = 0; k < 3; ++k) slot_of_vertex_[indices[3 * t + k]] = -1;
  }
}

float in_plane_extent(std::span<const glm::vec3> points, const glm::vec3& centre,
                      const glm::vec3& normal) {
  float extent = 0.0f;
  for (const glm::vec3& p : points) {
    const glm::vec3 d = p - centre;
    extent = std::max(extent, glm::length(d - glm::dot(d, normal) * normal));
  }
  return extent;
}

void pull_back_to_plane(const glm::vec3& centre, const glm::vec3& normal, float extent,
                        std::span<const std::uint32_t> vertices, std::span<const std::int8_t> sides,
                        float gap, std::span<glm::vec3> positions, FoldingResult& result) {
  // Per side, the deepest penetration past the plane among the vertices within reach
  // (own-side distance o = d * side; o < 0 went through).
  float deepest[2] = {-INFINITY, -INFINITY};
  // Full effect within one extent of the centre (in the plane), fading out by two.
  auto reach = [&](const glm::vec3& p, float d) {
    const float r = glm::length(p - centre - d * normal) / std::max(extent, 1e-12f);
    const float x = std::clamp(2.0f - r, 0.0f, 1.0f);
    return x * x * (3.0f - 2.0f * x);
  };
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const glm::vec3& p = positions[vertices[i]];
    const float d = glm::dot(p - centre, normal);
    if (reach(p, d) > 0.0f) {
      float& depth = deepest[sides[i] > 0];
      depth = std::max(depth, -d * sides[i]);
    }
  }
  for (int side_index = 0; side_index < 2; ++side_index) {
    const float depth = deepest[side_index];
    if (!(depth > -gap)) continue;  // every vertex at least `gap` on its own side
    result.max_depth = std::max(result.max_depth, depth);
    // Own-side distances in [-depth, band] map linearly onto [gap, band]: pulled back behind
    // the plane, layers kept in order (onto the plane itself they would overlap, coplanar).
    const float band = 2.0f * std::max(depth, 0.0f) + 4.0f * gap;
    const float scale = (band - gap) / (band + depth);
    const std::int8_t side = side_index ? 1 : -1;
    for (std::size_t i = 0; i < vertices.size(); ++i) {
      if (sides[i] != side) continue;
      glm::vec3& p = positions[vertices[i]];
      const float d = glm::dot(p - centre, normal);
      const float own = d * side;
      const float weight = reach(p, d);
      if (own >= band || weight <= 0.0f) continue;
      const float moved = gap + (own + depth) * scale;
      p += normal * (static_cast<float>(side) * weight * (moved - own));
      result.moved += own < 0.0f;
    }
  }
}

bool tears_skin(const CollisionRegion& region, std::span<const std::uint32_t> indices,
                std::span<const glm::vec3> before, std::span<const glm::vec3> positions) {
  for (std::size_t i = 0; i < region.triangles.size(); ++i) {
    const std::uint32_t t = region.triangles[i];
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = indices[3 * t + k], b = indices[3 * t + (k + 1) % 3];
      const float now = glm::distance(positions[a], positions[b]);
      if (now <= kMostFoldStretch * region.rest_edges[3 * i + k]) continue;
      const auto was = [&](int corner, std::uint32_t v) {
        const std::int32_t slot = region.corner_slots[3 * i + corner];
        return slot >= 0 ? before[slot] : positions[v];
      };
      if (now > glm::distance(was(k, a), was((k + 1) % 3, b))) return true;
    }
  }
  return false;
}

void SkinFolder::pull_back(const CollisionRegion& region, float gap, std::span<glm::vec3> positions,
                           FoldingResult& result) {
  glm::vec3 centre;
  glm::vec3 normal = fit_plane(points_, centre);
  // Orient the normal from the "before" side to the "past" side of the joint, judged by all
  // region vertices (the intersecting ones alone straddle the plane from both sides).
  double before = 0.0, past = 0.0;
  int before_count = 0, past_count = 0;
  for (std::size_t i = 0; i < region.vertices.size(); ++i) {
    const double d = glm::dot(positions[region.vertices[i]] - centre, normal);
    if (region.sides[i] < 0) before += d, ++before_count;
    if (region.sides[i] > 0) past += d, ++past_count;
  }
  if (before_count == 0 || past_count == 0) return;  // one skin only: nothing to separate
  if (before / before_count > past / past_count) normal = -normal;
  pull_back_to_plane(centre, normal, in_plane_extent(points_, centre, normal), region.vertices,
                     region.sides, gap, positions, result);
}

FoldingResult SkinFolder::fold(const CollisionRegion& region,
                               std::span<const std::uint32_t> indices,
                               std::span<const TrianglePair> pairs, float gap,
                               std::span<glm::vec3> positions) {
  FoldingResult result;
  if (pairs.empty()) return result;
  // One plane per group, through the group's distinct vertices.
  groups_.build(indices, pairs, positions.size());
  const double volume_before = enclosed_volume(positions, indices, region.triangles);
  for (std::size_t g = 0; g < groups_.size(); ++g) {
    points_.clear();
    for (std::uint32_t v : groups_.vertices(g)) points_.push_back(positions[v]);
    ++result.groups;
    before_.resize(region.vertices.size());
    for (std::size_t i = 0; i < region.vertices.size(); ++i)
      before_[i] = positions[region.vertices[i]];
    const FoldingResult counted = result;
    pull_back(region, gap, positions, result);
    // As far as the skin allows: the whole pull-back, else a half, a quarter, an eighth of it,
    // else none (see the header).
    after_.resize(region.vertices.size());
    for (std::size_t i = 0; i < region.vertices.size(); ++i)
      after_[i] = positions[region.vertices[i]];
    bool kept = false;
    for (float share = 1.0f; share >= kSmallestShare && !kept; share *= 0.5f) {
      for (std::size_t i = 0; i < region.vertices.size(); ++i)
        positions[region.vertices[i]] = glm::mix(before_[i], after_[i], share);
      kept = !tears_skin(region, indices, before_, positions);
      if (kept && share < 1.0f) ++result.eased;
    }
    if (!kept) {
      for (std::size_t i = 0; i < region.vertices.size(); ++i)
        positions[region.vertices[i]] = before_[i];
      const int eased = result.eased;
      result = counted;
      result.eased = eased;
      ++result.refused;
    }
  }
  result.volume_change = enclosed_volume(positions, indices, region.triangles) - volume_before;
  return result;
}

void SkinFolder::relax(const CollisionRegion& region, std::span<const std::uint32_t> indices,
                       std::span<const TrianglePair> pairs, std::span<glm::vec3> positions) {
  // Movable: region vertices (mark 1), and of them the corners of intersecting triangles (2).
  mark_.assign(positions.size(), 0);
  for (std::uint32_t v : region.vertices) mark_[v] = 1;
  for (const TrianglePair& p : pairs) {
    for (std::uint32_t t : {p.first, p.second}) {
      for (int k = 0; k < 3; ++k) {
        std::uint8_t& m = mark_[indices[3 * t + k]];
        if (m) m = 2;
      }
    }
  }
  sum_.resize(positions.size());
  count_.resize(positions.size());
  for (int iteration = 0; iteration < kRelaxIterations; ++iteration) {
    for (std::uint32_t t : region.triangles) {
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = indices[3 * t + k];
        sum_[v] = glm::vec3(0.0f), count_[v] = 0;
      }
    }
    for (std::uint32_t t : region.triangles) {
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = indices[3 * t + k];
        if (mark_[v] != 2) continue;
        sum_[v] +=
            positions[indices[3 * t + (k + 1) % 3]] + positions[indices[3 * t + (k + 2) % 3]];
        count_[v] += 2;
      }
    }
    for (std::uint32_t v : region.vertices) {
      if (mark_[v] == 2 && count_[v] > 0)
        positions[v] += kRelaxStep * (sum_[v] / static_cast<float>(count_[v]) - positions[v]);
    }
  }
}

}  // namespace sweepd::deform
