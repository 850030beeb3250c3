#include "deform/features/skin_contact.h"

#include <algorithm>
#include <cmath>
#include <thread>

#include "deform/binding/mesh_parts_joined.h"
#include "deform/features/whole_body_detector.h"

namespace sweepd::deform {

ContactModel make_contact_model(const BoundModel& bound,
                                std::span<const std::uint32_t> welded_indices) {
  const Model& model = bound.model;
  ContactModel out;
  const std::vector<std::uint8_t> joined = vertices_joined(model);
  for (std::uint32_t t = 0; t < model.triangle_count(); ++t)
    if (joined[model.indices[3 * t]]) out.skin_triangles.push_back(t);
  WholeBodyDetector detector;
  detector.detect(model.positions, welded_indices, out.skin_triangles, out.rest_pairs,
                  static_cast<int>(std::max(1u, std::thread::hardware_concurrency())));
  out.adjacency = vertex_adjacency(model.positions, welded_indices);
  out.triangle_sweep.assign(model.triangle_count(), -1);
  for (std::uint32_t t = 0; t < model.triangle_count(); ++t) {
    const VertexBinding& binding = bound.vertices[model.indices[3 * t]];
    float best = 0.0f;
    for (std::size_t k = 0; k < binding.weight.size(); ++k) {
      if (binding.sweep[k] >= 0 && binding.weight[k] > best)
        best = binding.weight[k], out.triangle_sweep[t] = binding.sweep[k];
    }
  }
  return out;
}

void remove_rest_pairs(std::span<const TrianglePair> rest, std::vector<TrianglePair>& pairs) {
  if (rest.empty()) return;
  // In place: the kept pairs are written at or before where they are read.
  std::size_t kept = 0;
  auto r = rest.begin();
  for (const TrianglePair& p : pairs) {
    while (r != rest.end() && *r < p) ++r;
    if (r != rest.end() && *r == p) continue;
    pairs[kept++] = p;
  }
  pairs.resize(kept);
}

bool tears_around(const ContactModel& model, std::span<const std::uint32_t> moved,
                  std::span<const glm::vec3> before, std::span<const glm::vec3> positions) {
  for (std::uint32_t v : moved) {
    const std::span<const std::uint32_t> neighbours = model.adjacency.neighbours(v);
    const std::span<const float> rest = model.adjacency.lengths(v);
    for (std::size_t i = 0; i < neighbours.size(); ++i) {
      const std::uint32_t u = neighbours[i];
      const float now = glm::distance(positions[v], positions[u]);
      if (now > kMostFoldStretch * rest[i] && now > glm::distance(before[v], before[u]))
        return true;
    }
  }
  return false;
}

void skin_sweep_volumes(const ContactModel& model, std::span<const std::uint32_t> indices,
                        std::span<const glm::vec3> positions, std::span<double> volumes) {
  std::fill(volumes.begin(), volumes.end(), 0.0);
  for (std::uint32_t t : model.skin_triangles) {
    const int s = model.triangle_sweep[t];
    if (s < 0 || static_cast<std::size_t>(s) >= volumes.size()) continue;
    const glm::dvec3 p(positions[indices[3 * t]]), q(positions[indices[3 * t + 1]]),
        r(positions[indices[3 * t + 2]]);
    volumes[s] += glm::dot(p, glm::cross(q, r)) / 6.0;
  }
}

void ContactResolver::split_elongated(std::span<const std::uint32_t> triangles,
                                      std::span<const std::uint32_t> indices,
                                      std::span<const glm::vec3> positions) {
  const auto offset = static_cast<std::uint32_t>(piece_triangles_.size());
  piece_triangles_.insert(piece_triangles_.end(), triangles.begin(), triangles.end());
  auto centroid = [&](std::uint32_t t) {
    return (positions[indices[3 * t]] + positions[indices[3 * t + 1]] +
            positions[indices[3 * t + 2]]) /
           3.0f;
  };
  // Ranges of piece_triangles_ still to judge; a piece is emitted in triangle order of the
  // ranges' ends, which keeps the pieces contiguous.
  std::vector<std::pair<std::uint32_t, std::uint32_t>>& todo = split_todo_;
  todo.assign(1, {offset, static_cast<std::uint32_t>(piece_triangles_.size())});
  std::vector<std::pair<std::uint32_t, std::uint32_t>>& done = split_done_;
  done.clear();
  while (!todo.empty()) {
    const auto [begin, end] = todo.back();
    todo.pop_back();
    if (end - begin < 2 * kSmallestPiece) {
      done.push_back({begin, end});
      continue;
    }
    centres_.clear();
    for (std::uint32_t i = begin; i < end; ++i) centres_.push_back(centroid(piece_triangles_[i]));
    glm::vec3 mean;
    const glm::vec3 normal = fit_plane(centres_, mean);
    const glm::vec3 helper =
        std::abs(normal.x) < 0.9f ? glm::vec3(1.0f, 0.0f, 0.0f) : glm::vec3(0.0f, 1.0f, 0.0f);
    const glm::vec3 u = glm::normalize(glm::cross(normal, helper)), v = glm::cross(normal, u);
    double uu = 0.0, uv = 0.0, vv = 0.0;
    for (const glm::vec3& c : centres_) {
      const double a = glm::dot(c - mean, u), b = glm::dot(c - mean, v);
      uu += a * a, uv += a * b, vv += b * b;
    }
    // The in-plane spread's eigenvalues (largest, smallest) and the largest one's direction.
    const double half_trace = 0.5 * (uu + vv);
    const double root = std::sqrt(0.25 * (uu - vv) * (uu - vv) + uv * uv);
    const double largest = half_trace + root, smallest = half_trace - root;
    if (!(largest > kMostElongation * kMostElongation * smallest)) {
      done.push_back({begin, end});
      continue;
    }
    const double angle = 0.5 * std::atan2(2.0 * uv, uu - vv);
    const glm::vec3 axis =
        static_cast<float>(std::cos(angle)) * u + static_cast<float>(std::sin(angle)) * v;
    const auto first = piece_triangles_.begin() + begin, last = piece_triangles_.begin() + end;
    const auto middle = first + (end - begin) / 2;
    std::nth_element(first, middle, last, [&](std::uint32_t a, std::uint32_t b) {
      return glm::dot(centroid(a), axis) < glm::dot(centroid(b), axis);
    });
    const auto split = static_cast<std::uint32_t>(middle - piece_triangles_.begin());
    todo.push_back({begin, split});
    todo.push_back({split, end});
  }
  std::sort(done.begin(), done.end());
  for (const auto& range : done) piece_start_.push_back(range.second);
}

std::uint32_t ContactResolver::find(std::uint32_t slot) {
  while (parent_[slot] != slot) slot = parent_[slot] = parent_[parent_[slot]];
  return slot;
}

bool ContactResolver::find_sides(std::span<const std::uint32_t> triangles,
                                 std::span<const std::uint32_t> indices,
                                 std::span<const glm::vec3> positions, const glm::vec3& normal) {
  const auto n = static_cast<std::uint32_t>(triangles.size());
  auto corner = [&](std::uint32_t slot, int k) { return indices[3 * triangles[slot] + k]; };
  auto area_normal = [&](std::uint32_t slot) {
    const glm::vec3 p = positions[corner(slot, 0)];
    return glm::cross(positions[corner(slot, 1)] - p, positions[corner(slot, 2)] - p);
  };
  // Patches: the group's triangles joined through shared vertices.
  parent_.resize(n);
  for (std::uint32_t s = 0; s < n; ++s) parent_[s] = s;
  for (std::uint32_t s = 0; s < n; ++s) {
    for (int k = 0; k < 3; ++k) {
      std::int32_t& owner = owner_[corner(s, k)];
      if (owner >= 0)
        parent_[find(s)] = find(static_cast<std::uint32_t>(owner));
      else
        owner = static_cast<std::int32_t>(s);
    }
  }
  for (std::uint32_t s = 0; s < n; ++s)
    for (int k = 0; k < 3; ++k) owner_[corner(s, k)] = -1;
  patch_normal_.assign(n, glm::vec3(0.0f));
  for (std::uint32_t s = 0; s < n; ++s) patch_normal_[find(s)] += area_normal(s);
  // A skin goes to the side its outward normal points away from.
  auto side_of = [&](const glm::vec3& outward) -> std::int8_t {
    return glm::dot(outward, normal) > 0.0f ? -1 : 1;
  };
  triangle_side_.resize(n);
  bool seen[2] = {false, false};
  for (std::uint32_t s = 0; s < n; ++s) {
    triangle_side_[s] = side_of(patch_normal_[find(s)]);
    seen[triangle_side_[s] > 0] = true;
  }
  if (seen[0] && seen[1]) return true;
  seen[0] = seen[1] = false;
  for (std::uint32_t s = 0; s < n; ++s) {
    triangle_side_[s] = side_of(area_normal(s));
    seen[triangle_side_[s] > 0] = true;
  }
  return seen[0] && seen[1];
}

ContactResult ContactResolver::resolve(const ContactModel& model,
                                       std::span<const std::uint32_t> indices,
                                       std::span<const TrianglePair> pairs, float gap,
                                       std::span<glm::vec3> positions, int only_group) {
  ContactResult result;
  moved_.clear();
  moved_start_.assign(1, 0);
  if (pairs.empty()) return result;
  owner_.resize(std::max(owner_.size(), positions.size()), -1);
  label_.resize(std::max(label_.size(), positions.size()), 0);
  if (only_group < 0) {
    groups_.build(indices, pairs, positions.size());
    piece_triangles_.clear();
    piece_start_.assign(1, 0);
    for (std::size_t g = 0; g < groups_.size(); ++g)
      split_elongated(groups_.triangles(g), indices, positions);
  }
  const VertexAdjacency& adjacency = model.adjacency;
  result.groups = static_cast<int>(piece_start_.size()) - 1;
  for (std::size_t piece = 0; piece + 1 < piece_start_.size(); ++piece) {
    if (only_group >= 0 && piece != static_cast<std::size_t>(only_group)) continue;
    const std::span<const std::uint32_t> triangles =
        std::span<const std::uint32_t>(piece_triangles_)
            .subspan(piece_start_[piece], piece_start_[piece + 1] - piece_start_[piece]);
    points_.clear();
    for (std::uint32_t t : triangles)
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = indices[3 * t + k];
        if (label_[v] != 0) continue;
        label_[v] = 1;
        points_.push_back(positions[v]);
        grown_.push_back(v);
      }
    for (std::uint32_t v : grown_) label_[v] = 0;
    grown_.clear();
    glm::vec3 centre;
    const glm::vec3 normal = fit_plane(points_, centre);
    if (!find_sides(triangles, indices, positions, normal)) continue;
    ++result.separated;
    const float extent = in_plane_extent(points_, centre, normal);
    const float reach_in_plane = 2.0f * extent, reach_across = extent + 4.0f * gap;
    // The moving skin: grown breadth-first from every patch at once.
    grown_.clear();
    grown_side_.clear();
    for (std::size_t s = 0; s < triangles.size(); ++s) {
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = indices[3 * triangles[s] + k];
        if (label_[v] != 0) continue;
        label_[v] = triangle_side_[s];
        grown_.push_back(v);
      }
    }
    for (std::size_t next = 0; next < grown_.size(); ++next) {
      const std::uint32_t v = grown_[next];
      for (std::uint32_t u : adjacency.neighbours(v)) {
        if (label_[u] != 0) continue;
        const glm::vec3 d = positions[u] - centre;
        const float across = glm::dot(d, normal);
        if (std::abs(across) >= reach_across || glm::length(d - across * normal) >= reach_in_plane)
          continue;
        label_[u] = label_[v];
        grown_.push_back(u);
      }
    }
    for (std::uint32_t v : grown_) grown_side_.push_back(label_[v]), label_[v] = 0;
    FoldingResult pulled;
    pull_back_to_plane(centre, normal, extent, grown_, grown_side_, gap, positions, pulled);
    result.moved += pulled.moved;
    result.max_depth = std::max(result.max_depth, pulled.max_depth);
    moved_.insert(moved_.end(), grown_.begin(), grown_.end());
    moved_start_.push_back(static_cast<std::uint32_t>(moved_.size()));
  }
  return result;
}

}  // namespace sweepd::deform
