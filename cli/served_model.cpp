#include "cli/served_model.h"

#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli/served_rest_skeleton.h"

namespace sweepd::cli {
namespace {

// Copies a Mesh array into `count` elements of `out` (each element: several scalars in a row).
template <typename Element, typename Scalar>
void copy_array(const flatbuffers::Vector<Scalar>* values, std::size_t count, const char* name,
                std::vector<Element>& out) {
  static_assert(sizeof(Element) % sizeof(Scalar) == 0);
  const std::size_t expected = count * (sizeof(Element) / sizeof(Scalar));
  const std::size_t got = values ? values->size() : 0;
  if (got != expected) {
    throw std::runtime_error("Mesh." + std::string(name) + " has " + std::to_string(got) +
                             " values; the model needs " + std::to_string(expected));
  }
  out.resize(count);
  if (expected > 0) std::memcpy(out.data(), values->data(), expected * sizeof(Scalar));
}

// The model's meshes from ModelInfo.meshes (1.6), as the server's model has them
// (deform::Model::meshes: one unnamed whole part for a model of one mesh, which saves as no
// parts do).
std::vector<deform::MeshPart> mesh_parts(const protocol::ModelInfo& info) {
  std::vector<deform::MeshPart> parts;
  if (info.meshes() == nullptr) return parts;
  for (const protocol::MeshRange* range : *info.meshes()) {
    deform::MeshPart part;
    part.name = range->name() ? range->name()->str() : "";
    part.material = range->material() ? range->material()->str() : "";
    part.mesh = range->mesh();
    part.first_vertex = range->first_vertex();
    part.vertex_count = range->vertex_count();
    part.first_index = 3 * range->first_triangle();
    part.index_count = 3 * range->triangle_count();
    part.rigid_joint = range->rigid_joint();
    parts.push_back(std::move(part));
  }
  return parts;
}

}  // namespace

deform::Model served_model(client::Connection& connection, const protocol::ModelInfo& info) {
  deform::Model model;
  model.name = info.name() ? info.name()->str() : "";
  model.skeleton = rest_skeleton(info);
  model.parts = mesh_parts(info);  // read now: `info` is invalid once the Mesh arrives
  const std::uint32_t model_id = info.model_id();
  const std::size_t vertex_count = info.vertex_count();
  const std::size_t triangle_count = info.triangle_count();
  const bool has_uvs = info.has_uvs();

  flatbuffers::FlatBufferBuilder& builder = connection.builder();
  builder.Clear();
  connection.send(
      protocol::finish_message(builder, protocol::CreateMeshRequest(builder, model_id)));
  const protocol::Mesh& mesh = connection.expect<protocol::Mesh>();
  if (mesh.model_id() != model_id) {
    throw std::runtime_error(connection.address() + ": Mesh for model " +
                             std::to_string(mesh.model_id()) + ", asked for " +
                             std::to_string(model_id));
  }
  copy_array(mesh.indices(), 3 * triangle_count, "indices", model.indices);
  copy_array(mesh.rest_positions(), vertex_count, "rest_positions", model.positions);
  copy_array(mesh.uvs(), has_uvs ? vertex_count : 0, "uvs", model.uvs);
  copy_array(mesh.skin_joints(), vertex_count, "skin_joints", model.skin_joints);
  copy_array(mesh.skin_weights(), vertex_count, "skin_weights", model.skin_weights);
  model.normals = deform::compute_vertex_normals(model.positions, model.indices);
  if (const std::string problem = model.validate(); !problem.empty()) {
    throw std::runtime_error(connection.address() + ": the served model '" + model.name +
                             "' is unusable: " + problem);
  }
  return model;
}

}  // namespace sweepd::cli
