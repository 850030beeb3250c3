#include "server/replies/model_info.h"

#include <algorithm>
#include <limits>
#include <vector>

#include "deform/binding/mesh_parts_joined.h"
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
  std::vector<pb::Vec3> translations, scales;
  std::vector<pb::Quat> rotations;
  for (const deform::Joint& joint : bound.model.skeleton.joints) {
    joint_names.push_back(builder.CreateString(joint.name));
    joint_parents.push_back(joint.parent);
    const glm::vec3 &t = joint.rest_translation, &s = joint.rest_scale;
    const glm::quat& r = joint.rest_rotation;
    translations.emplace_back(t.x, t.y, t.z);
    rotations.emplace_back(r.x, r.y, r.z, r.w);
    scales.emplace_back(s.x, s.y, s.z);
  }
  float floor = std::numeric_limits<float>::infinity();
  for (const glm::vec3& p : bound.model.positions) floor = std::min(floor, p.y);
  const auto summary = pb::CreateBindSummaryDirect(
      builder, bound.rig.convention.c_str(), static_cast<std::uint32_t>(bound.sweeps.size()),
      key_count, swept, static_cast<std::uint32_t>(bound.vertices.size()) - swept,
      model.bind_time_ns);
  // One range per mesh part; a model of one mesh is one range over all of it, swept.
  const std::vector<deform::MeshPart> parts = bound.model.meshes();
  std::vector<std::uint8_t> joined = deform::mesh_parts_joined(bound.model);
  joined.resize(parts.size(), 1);
  std::vector<flatbuffers::Offset<pb::MeshRange>> meshes;
  for (std::size_t k = 0; k < parts.size(); ++k)
    meshes.push_back(pb::CreateMeshRangeDirect(
        builder, parts[k].name.c_str(), parts[k].first_vertex, parts[k].vertex_count,
        parts[k].material.c_str(), parts[k].first_index / 3, parts[k].index_count / 3,
        parts[k].rigid_joint, joined[k] != 0, parts[k].mesh));
  // (1.14) The binding's self-check: regions where the sweep is still worse than skinning.
  std::vector<flatbuffers::Offset<pb::BindWarning>> warnings;
  for (const selfcheck::RegionWarning& w : model.self_check.warnings)
    warnings.push_back(pb::CreateBindWarningDirect(
        builder, w.region.c_str(), static_cast<std::uint32_t>(w.worse_poses),
        static_cast<float>(w.sweep), static_cast<float>(w.baseline), w.baseline_name.c_str(),
        w.pose.c_str(), static_cast<std::uint32_t>(w.extra_flipped), w.flipped_pose.c_str(),
        w.text.c_str()));
  const auto info = pb::CreateModelInfoDirect(
      builder, model.id, model.name.c_str(), &joint_names, &joint_parents,
      static_cast<std::uint32_t>(bound.model.vertex_count()),
      static_cast<std::uint32_t>(bound.model.triangle_count()), bound.model.has_uvs(), summary,
      &translations, &rotations, &scales, floor, model.content_id.c_str(), &meshes,
      static_cast<std::uint32_t>(model.self_check.poses), &warnings);
  pb::finish_message(builder, info, request_id);
}

}  // namespace sweepd::server
