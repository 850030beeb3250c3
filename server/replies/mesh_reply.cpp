#include "server/replies/mesh_reply.h"

#include "protocol/messages.h"

namespace sweepd::server {

void build_mesh(flatbuffers::FlatBufferBuilder& builder, const RegisteredModel& registered,
                std::uint64_t request_id) {
  namespace pb = sweepd::protocol;
  const deform::Model& model = registered.bound.model;
  const std::size_t n = model.vertex_count();
  static_assert(sizeof(glm::vec2) == 2 * sizeof(float) && sizeof(glm::vec3) == 3 * sizeof(float));
  const auto indices = builder.CreateVector(model.indices);
  const auto uvs =
      builder.CreateVector(reinterpret_cast<const float*>(model.uvs.data()), 2 * model.uvs.size());
  const auto positions =
      builder.CreateVector(reinterpret_cast<const float*>(model.positions.data()), 3 * n);
  const auto joints = builder.CreateVector(
      reinterpret_cast<const std::uint16_t*>(model.skin_joints.data()), deform::kInfluences * n);
  const auto weights = builder.CreateVector(
      reinterpret_cast<const float*>(model.skin_weights.data()), deform::kInfluences * n);
  pb::finish_message(
      builder, pb::CreateMesh(builder, registered.id, indices, uvs, positions, joints, weights),
      request_id);
}

}  // namespace sweepd::server
