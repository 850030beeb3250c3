// Poses for the server tests: a deterministic non-trivial pose for any joint count, sending it
// as a Pose frame, and the library's own deformation of the same pose to compare replies with.
#pragma once

#include <cstring>
#include <glm/gtc/quaternion.hpp>
#include <vector>

#include "deform/job/anatomical_features.h"
#include "deform/job/deform_job.h"
#include "tests/server/daemon_process.h"

namespace sweepd::test {

// Every joint bent by up to 0.35 rad about a joint-dependent axis: far from the rest pose.
inline std::vector<glm::quat> bent_rotations(std::size_t joint_count, float phase = 0.0f) {
  std::vector<glm::quat> rotations;
  for (std::size_t j = 0; j < joint_count; ++j) {
    const float f = static_cast<float>(j) + phase;
    const glm::vec3 axis = glm::normalize(glm::vec3(std::sin(f), std::cos(2.0f * f), 0.5f));
    rotations.push_back(glm::angleAxis(0.35f * std::sin(f + 1.0f), axis));
  }
  return rotations;
}

inline std::vector<protocol::Quat> to_wire(const std::vector<glm::quat>& rotations) {
  std::vector<protocol::Quat> wire;
  for (const glm::quat& q : rotations) wire.emplace_back(q.x, q.y, q.z, q.w);
  return wire;
}

inline protocol::PoseFields pose_fields(std::uint32_t model_id, std::uint64_t sequence,
                                        std::span<const protocol::Quat> rotations) {
  protocol::PoseFields fields;
  fields.model_id = model_id;
  fields.sequence = sequence;
  fields.rotations = rotations;
  return fields;
}

inline bool send_pose(FrameClient& client, protocol::PoseFields fields,
                      std::uint64_t request_id = 0) {
  flatbuffers::FlatBufferBuilder builder;
  const auto pose = protocol::add_pose(builder, fields);
  return client.send_bytes(protocol::finish_message(builder, pose, request_id));
}

// A reply's float vector (positions_f32, normals_f32), copied; empty when absent.
inline std::vector<float> copy_floats(const flatbuffers::Vector<float>* values) {
  return values == nullptr ? std::vector<float>()
                           : std::vector<float>(values->begin(), values->end());
}

// Two float vectors of the same size and the same bits (memcmp: not even -0 for 0 passes).
inline bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

struct Deformed {
  std::vector<glm::vec3> positions, normals;
  deform::FeatureReport features;  // what folding and protrusion did
};

// What the library itself gives for `pose`, one thread, with the anatomical features selected:
// one deform::DeformJob, each frame standing alone (as the daemon runs them).
inline Deformed library_deformation(const deform::BoundModel& bound, deform::Pose pose,
                                    deform::DeformMethod method,
                                    const deform::AnatomicalFeatures& features = {}) {
  const deform::ModelRuntime runtime(bound);
  deform::DeformContext context;
  Deformed out;
  out.positions.resize(bound.model.vertex_count());
  out.normals.resize(bound.model.vertex_count());
  deform::DeformJob job{runtime, pose, method, features};
  job.positions = out.positions;
  job.normals = out.normals;
  out.features = job.run(context).features;
  return out;
}

// The same for `rotations` at the rest root translation.
inline Deformed library_deformation(const deform::BoundModel& bound,
                                    const std::vector<glm::quat>& rotations,
                                    deform::DeformMethod method,
                                    const deform::AnatomicalFeatures& features = {}) {
  deform::Pose pose;
  pose.local_rotations = rotations;
  pose.root_translation = bound.model.skeleton.joints[0].rest_translation;
  return library_deformation(bound, std::move(pose), method, features);
}

}  // namespace sweepd::test
