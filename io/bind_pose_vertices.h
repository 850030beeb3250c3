// add_influence: adds (joint, weight) to a vertex's influences, merging a joint named twice.
//
// BindPoseVertices: how the model loaders (io/gltf/gltf_load, io/assimp/assimp_load) turn a file's skinned
// vertices into deform::Model vertices in the bind pose, and count and say what they changed.
//
// append: one vertex.
//   influences  its (joint, weight) pairs, weights > 0, one pair per joint; reordered and cut
//               in place (the loader's scratch)
//   fallback    the joint a vertex with no weight is bound to, rigidly
//   skinning    per joint: world rest matrix * inverse bind matrix
//   position    in the file's mesh space; normal and uv: nullptr when the file has none
//   Keeps the 4 largest influences renormalised to sum 1 (LoadReport: trimmed_influence_count,
//   renormalised_weight_count, zero_weight_vertex_count), skins the position with their blend
//   and the normal with its cofactor, and appends position, normal, uv, joints and weights.
// finish: normals the file lacked computed from the triangles (computed_normal_count); UVs
//   dropped when no vertex had any, (0, 0) where some lacked them; one warning per change,
//   naming the file's attributes as `normal_name` and `uv_name` (e.g. "NORMAL", "TEXCOORD_0").
#pragma once

#include <glm/glm.hpp>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "deform/model/model.h"
#include "io/load_report.h"

namespace sweepd::io {

void add_influence(std::vector<std::pair<int, double>>& influences, int joint, double weight);

class BindPoseVertices {
 public:
  BindPoseVertices(deform::Model& model, LoadReport& report) : model_(model), report_(report) {}

  void append(std::vector<std::pair<int, double>>& influences, int fallback,
              std::span<const glm::dmat4> skinning, const glm::dvec3& position,
              const glm::dvec3* normal, const glm::vec2* uv);
  void finish(const deform::Skeleton& skeleton, const std::string& normal_name,
              const std::string& uv_name);

 private:
  deform::Model& model_;
  LoadReport& report_;
  std::vector<bool> has_normal_;
  std::size_t missing_uvs_ = 0;
  double lowest_sum_ = 1.0, highest_sum_ = 1.0, largest_dropped_ = 0.0;
  int fallback_used_ = 0;
};

}  // namespace sweepd::io
