#include "server/model_info.h"

#include <vector>

#include "protocol/messages.h"

namespace sweepd::server {

void build_model_info(flatbuffers::FlatBufferBuilder& builder, const RegisteredModel& model,
                      std::uint64_t request_id) {
  namespace pb = sweepd::protocol;
  const deform::BoundModel& bound = model.bound;
  std::uint32_t key_count = 0;
  for (const deform::BoundSweep& sweep : bound.sweeps) {
    key_count += static_cast<std::uint32_t>(sweep.rest_keys.size());
  }
  std::uint32_t swept = 0;
  for (const deform::VertexBinding& vertex : bound.vertices) {
    if (vertex.sweep[0] >= 0) ++swept;
  }
  std::vector<flatbuffers::Offset<flatbuffers::String>> joint_names;
  std::vector<std::int32_t> joint_parents;
  for (const deform::Joint& joint : bound.model.skeleton.joints) {
    joint_names.push_back(builder.CreateString(joint.name));
    joint_parents.push_back(joint.parent);
  }
  const auto summary = pb::CreateBindSummaryDirect(
      builder, bound.rig.convention.c_str(), static_cast<std::uint32_t>(bound.sweeps.size()),
      key_count, swept, static_cast<std::uint32_t>(bound.vertices.size()) - swept,
      model.bind_time_ns);
  const auto info = pb::CreateModelInfoDirect(
      builder, model.id, model.name.c_str(), &joint_names, &joint_parents,
      static_cast<std::uint32_t>(bound.model.vertex_count()),
      static_cast<std::uint32_t>(bound.model.triangle_count()), bound.model.has_uvs(), summary);
  pb::finish_message(builder, info, request_id);
}

}  // namespace sweepd::server
