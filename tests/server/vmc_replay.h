// The tests that replay clips as VMC (daemon_vmc_test, daemon_vmc_streams_test): each frame's
// bones as a sender sends them (vmc_pose_bones), a subscription (subscribe_to_stream), the
// subscriber's mesh (positions_of) against PoseFromClip's (pose_from_clip_mesh) within
// kVmcSameMesh, and a stream's series on /metrics (vmc_series).
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "client/connection.h"
#include "deform/binding/bound_model.h"
#include "deform/rig/human_body_bones.h"
#include "protocol/messages.h"
#include "server/services/vmc/unity_frame.h"
#include "tests/server/services/vmc/vmc_packets.h"

namespace sweepd::test {

// A streamed mesh and PoseFromClip's of the same frame: the same pose, deformed by the same
// code, so nanometres apart at most.
inline constexpr double kVmcSameMesh = 1e-5;

// A VMC series of `stream` on /metrics: sweepd_vmc_X{stream="NAME"} (and its other labels).
inline std::string vmc_series(const std::string& name, const std::string& stream,
                              const std::string& more_labels = "") {
  return name + "{stream=\"" + stream + "\"" + (more_labels.empty() ? "" : "," + more_labels) + "}";
}

// The VMC bones of `pose` on `model`: each HumanBodyBones bone the model has, its joint's local
// rotation (and, on joint 0, the root translation; elsewhere the rest translation) in Unity's
// frame.
inline std::vector<VmcBone> vmc_pose_bones(const deform::BoundModel& model,
                                           const deform::Pose& pose) {
  const deform::Skeleton& skeleton = model.model.skeleton;
  const auto bones = deform::map_human_body_bones(skeleton, model.rig);
  std::vector<VmcBone> sent;
  for (int bone = 0; bone < deform::kHumanBodyBoneCount; ++bone) {
    const int joint = bones[bone];
    if (joint < 0) continue;
    const glm::vec3 position =
        joint == 0 ? pose.root_translation : skeleton.joints[joint].rest_translation;
    sent.push_back({std::string(deform::kHumanBodyBones[bone]), server::unity_mirrored(position),
                    server::unity_mirrored(pose.local_rotations[joint])});
  }
  return sent;
}

inline std::vector<glm::vec3> positions_of(const protocol::PosedVertices& reply) {
  std::vector<glm::vec3> positions(reply.vertex_count());
  EXPECT_TRUE(protocol::copy_positions(reply, {&positions[0].x, 3 * positions.size()}));
  return positions;
}

// SubscribeStream on `connection` (latest wins, the default pose): the reply's model id, or the
// ServerError thrown.
inline std::uint32_t subscribe_to_stream(client::Connection& connection,
                                         const std::string& stream) {
  flatbuffers::FlatBufferBuilder& builder = connection.builder();
  builder.Clear();
  const auto pose = protocol::add_pose(builder, protocol::PoseFields{});
  connection.send(protocol::finish_message(
      builder, protocol::CreateSubscribeStream(builder, builder.CreateString(stream), pose), 5));
  const protocol::StreamSubscribed& reply = connection.expect<protocol::StreamSubscribed>();
  EXPECT_EQ(reply.stream()->str(), stream);
  return reply.model_id();
}

// PoseFromClip's mesh of `frame` of an uploaded clip, asked on an in-order `connection`.
inline std::vector<glm::vec3> pose_from_clip_mesh(client::Connection& connection,
                                                  std::uint32_t model, const std::string& clip_id,
                                                  std::uint32_t frame) {
  flatbuffers::FlatBufferBuilder& builder = connection.builder();
  builder.Clear();
  protocol::PoseFields fields;
  fields.model_id = model;
  fields.sequence = frame + 1;
  const auto pose = protocol::add_pose(builder, fields);
  const auto clip = protocol::CreateClipFrame(builder, builder.CreateString(clip_id), frame);
  connection.send(
      protocol::finish_message(builder, protocol::CreatePoseFromClip(builder, pose, clip)));
  return positions_of(connection.expect<protocol::PosedVertices>());
}

}  // namespace sweepd::test
