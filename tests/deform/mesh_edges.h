// Test helper for the edge-stretch tests: the distinct edges of a model's triangles (vertex
// pairs, smaller index first, in the order the triangles first use them; zero-length edges
// left out) with their rest lengths, and the body part of the joint weighing most on a vertex,
// which is how those tests assign an edge to a region.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <set>
#include <utility>
#include <vector>

#include "deform/model/model.h"
#include "deform/rig/rig_map.h"

namespace sweepd::deform::test {

struct MeshEdge {
  std::uint32_t a, b;
  float rest_length;
};

inline std::vector<MeshEdge> distinct_edges(const Model& model) {
  std::set<std::pair<std::uint32_t, std::uint32_t>> seen;
  std::vector<MeshEdge> edges;
  for (std::size_t t = 0; t < model.indices.size(); t += 3)
    for (int k = 0; k < 3; ++k) {
      std::uint32_t a = model.indices[t + k], b = model.indices[t + (k + 1) % 3];
      if (a > b) std::swap(a, b);
      if (!seen.insert({a, b}).second) continue;
      const float length = glm::length(model.positions[a] - model.positions[b]);
      if (length > 0.0f) edges.push_back({a, b, length});
    }
  return edges;
}

// joint_part: label_joints(rig, model.skeleton).
inline BodyPart heaviest_part(const Model& model, const std::vector<BodyPart>& joint_part,
                              std::uint32_t v) {
  int heaviest = 0;
  for (int i = 1; i < kInfluences; ++i)
    if (model.skin_weights[v][i] > model.skin_weights[v][heaviest]) heaviest = i;
  return joint_part[model.skin_joints[v][heaviest]];
}

}  // namespace sweepd::deform::test
