#include "deform/model/model.h"

#include <algorithm>
#include <cmath>

namespace sweepd::deform {

namespace {
bool finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

std::string validate_parts(const Model& model) {
  std::size_t next_vertex = 0, next_index = 0;
  for (std::size_t k = 0; k < model.parts.size(); ++k) {
    const MeshPart& part = model.parts[k];
    const std::string which = "mesh part " + std::to_string(k) + " ('" + part.name + "')";
    if (part.first_vertex != next_vertex || part.first_index != next_index)
      return which + " does not start where the part before it ends";
    next_vertex += part.vertex_count;
    next_index += part.index_count;
    if (next_vertex > model.positions.size() || next_index > model.indices.size() ||
        part.index_count % 3 != 0)
      return which + " runs past the model's vertices or triangles";
    for (std::size_t i = part.first_index; i < next_index; ++i)
      if (model.indices[i] < part.first_vertex || model.indices[i] >= next_vertex)
        return which + " has a triangle on another part's vertex";
    if (part.rigid_joint >= model.skeleton.size())
      return which + " follows joint " + std::to_string(part.rigid_joint) + " of " +
             std::to_string(model.skeleton.size());
  }
  if (!model.parts.empty() &&
      (next_vertex != model.positions.size() || next_index != model.indices.size()))
    return "the mesh parts cover " + std::to_string(next_vertex) + " of " +
           std::to_string(model.positions.size()) + " vertices and " + std::to_string(next_index) +
           " of " + std::to_string(model.indices.size()) + " triangle corners";
  return {};
}

}  // namespace

std::string Model::validate() const {
  const std::size_t n = positions.size();
  if (n == 0) return "the model has no vertices";
  if (normals.size() != n)
    return "normal count " + std::to_string(normals.size()) + " != vertex count " +
           std::to_string(n);
  if (!uvs.empty() && uvs.size() != n)
    return "UV count " + std::to_string(uvs.size()) + " != vertex count " + std::to_string(n);
  if (indices.empty() || indices.size() % 3 != 0)
    return "index count " + std::to_string(indices.size()) + " is not a positive multiple of 3";
  for (std::size_t i = 0; i < indices.size(); ++i)
    if (indices[i] >= n)
      return "index " + std::to_string(i) + " refers to vertex " + std::to_string(indices[i]) +
             " of " + std::to_string(n);
  for (std::size_t v = 0; v < n; ++v)
    if (!finite(positions[v]) || !finite(normals[v]))
      return "vertex " + std::to_string(v) + " has a non-finite position or normal";
  if (std::string why = skeleton.validate(); !why.empty()) return why;
  if (skeleton.size() == 0) return "the model has no joints";
  if (skin_joints.size() != n || skin_weights.size() != n)
    return "skin influence count != vertex count";
  for (std::size_t v = 0; v < n; ++v) {
    float sum = 0.0f;
    for (int k = 0; k < kInfluences; ++k) {
      if (skin_joints[v][k] >= skeleton.size())
        return "vertex " + std::to_string(v) + " refers to joint " +
               std::to_string(skin_joints[v][k]) + " of " + std::to_string(skeleton.size());
      if (!(skin_weights[v][k] >= 0.0f))
        return "vertex " + std::to_string(v) + " has a negative or NaN skin weight";
      sum += skin_weights[v][k];
    }
    if (std::abs(sum - 1.0f) > 1e-3f)
      return "vertex " + std::to_string(v) + " has skin weights summing to " + std::to_string(sum);
  }
  return validate_parts(*this);
}

int Model::strongest_influence(std::size_t v) const {
  const auto& weights = skin_weights[v];
  return static_cast<int>(std::max_element(weights.begin(), weights.end()) - weights.begin());
}

std::vector<MeshPart> Model::meshes() const {
  if (!parts.empty()) return parts;
  MeshPart whole;  // unnamed: the model's name is a label (a file stem, a store name), not a mesh's
  whole.vertex_count = static_cast<std::uint32_t>(vertex_count());
  whole.index_count = static_cast<std::uint32_t>(indices.size());
  return {whole};
}

std::vector<glm::vec3> compute_vertex_normals(const std::vector<glm::vec3>& positions,
                                              const std::vector<std::uint32_t>& indices) {
  std::vector<glm::vec3> normals(positions.size(), glm::vec3(0.0f));
  for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
    const glm::vec3& a = positions[indices[t]];
    const glm::vec3& b = positions[indices[t + 1]];
    const glm::vec3& c = positions[indices[t + 2]];
    const glm::vec3 area_normal = glm::cross(b - a, c - a);  // length = 2 * area
    for (int k = 0; k < 3; ++k) normals[indices[t + k]] += area_normal;
  }
  for (glm::vec3& n : normals) {
    const float length = glm::length(n);
    n = length > 0.0f ? n / length : glm::vec3(0, 1, 0);
  }
  return normals;
}

}  // namespace sweepd::deform
