#include "io/gltf/gltf_animations_save.h"

#include <cmath>
#include <cstring>
#include <glm/glm.hpp>
#include <map>
#include <set>
#include <utility>

namespace sweepd::io {

namespace {

// 1e-3 refuses quaternions that were never normalised and accepts float rounding of normalised
// ones; the validator's own limit is 0.00769.
constexpr double kUnitTolerance = 1e-3;

const char* path_name(motion::TrackPath path) {
  return path == motion::TrackPath::kRotation ? "rotation" : "translation";
}

const char* interpolation_name(motion::Interpolation interpolation) {
  switch (interpolation) {
    case motion::Interpolation::kStep:
      return "STEP";
    case motion::Interpolation::kCubicSpline:
      return "CUBICSPLINE";
    case motion::Interpolation::kLinear:
      break;
  }
  return "LINEAR";
}

// What glTF and its validator ask of a well-formed track (motion::track_problem passed) beyond
// that: "" or the reason.
std::string gltf_track_problem(const motion::KeyframeTrack& track) {
  if (track.times.front() < 0.0f)  // times increase: the first is the least
    return "key time 0 is negative (" + std::to_string(track.times.front()) +
           " s; glTF key times are 0 or more)";
  const bool cubic = track.interpolation == motion::Interpolation::kCubicSpline;
  if (cubic && track.times.size() < 2) return "a CUBICSPLINE track needs 2 keys or more (glTF)";
  if (track.path != motion::TrackPath::kRotation) return "";
  const std::size_t stride = cubic ? 12 : 4, offset = cubic ? 4 : 0;  // tangents need not be unit
  for (std::size_t k = 0; k < track.times.size(); ++k) {
    const float* q = track.values.data() + k * stride + offset;
    double squares = 0.0;
    for (int i = 0; i < 4; ++i) squares += double{q[i]} * q[i];
    if (std::abs(std::sqrt(squares) - 1.0) > kUnitTolerance)
      return "key " + std::to_string(k) + "'s rotation is not a unit quaternion (length " +
             std::to_string(std::sqrt(squares)) + ", more than 1e-3 from 1)";
  }
  return "";
}

// The first problem of one animation's tracks, each named by index, path and joint.
std::string tracks_problem(const SavedAnimation& animation, const deform::Skeleton& skeleton) {
  std::set<std::pair<int, motion::TrackPath>> targets;
  for (std::size_t t = 0; t < animation.tracks.size(); ++t) {
    const motion::KeyframeTrack& track = animation.tracks[t];
    const std::string where = "animation '" + animation.name + "' track " + std::to_string(t) +
                              " (" + path_name(track.path);
    if (track.joint < 0 || track.joint >= skeleton.size())
      return where + "): joint " + std::to_string(track.joint) +
             " is out of range (the model has " + std::to_string(skeleton.size()) + " joints)";
    const std::string track_name = where + " of joint '" + skeleton.joints[track.joint].name + "')";
    std::string problem = motion::track_problem(track);
    if (problem.empty()) problem = gltf_track_problem(track);
    if (!problem.empty()) return track_name + ": " + problem;
    if (!targets.insert({track.joint, track.path}).second)
      return track_name + ": that joint has an earlier " + path_name(track.path) +
             " track (glTF allows one channel per node and path)";
  }
  return "";
}

int add_times(GlbBuilder& builder, tinygltf::Model& gltf, const std::vector<float>& times) {
  const int accessor =
      builder.add_accessor(times, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_SCALAR, 0);
  gltf.accessors[accessor].minValues = {times.front()};  // glTF requires an input's bounds
  gltf.accessors[accessor].maxValues = {times.back()};
  return accessor;
}

// A track's floats as accessor elements (glm::vec3 or glm::vec4, packed floats).
template <typename Vector>
std::vector<Vector> as_elements(const std::vector<float>& values) {
  std::vector<Vector> elements(values.size() / Vector::length());
  std::memcpy(elements.data(), values.data(), elements.size() * sizeof(Vector));
  return elements;
}

int add_values(GlbBuilder& builder, const motion::KeyframeTrack& track) {
  if (track.path == motion::TrackPath::kRotation)  // x, y, z, w: glTF's order already
    return builder.add_accessor(as_elements<glm::vec4>(track.values), TINYGLTF_COMPONENT_TYPE_FLOAT,
                                TINYGLTF_TYPE_VEC4, 0);
  return builder.add_accessor(as_elements<glm::vec3>(track.values), TINYGLTF_COMPONENT_TYPE_FLOAT,
                              TINYGLTF_TYPE_VEC3, 0);
}

}  // namespace

std::string animations_problem(const std::vector<SavedAnimation>& animations,
                               const deform::Skeleton& skeleton) {
  std::set<std::string> names;
  for (std::size_t a = 0; a < animations.size(); ++a) {
    const SavedAnimation& animation = animations[a];
    if (animation.name.empty())
      return "animation " + std::to_string(a) +
             " has no name (load_gltf_clip chooses animations by name)";
    if (!names.insert(animation.name).second)
      return "two animations are named '" + animation.name + "'";
    if (animation.tracks.empty())
      return "animation '" + animation.name + "' has no tracks (glTF needs a channel)";
    if (std::string problem = tracks_problem(animation, skeleton); !problem.empty()) return problem;
  }
  return "";
}

void add_animations(GlbBuilder& builder, tinygltf::Model& gltf,
                    const std::vector<SavedAnimation>& animations) {
  std::map<std::vector<float>, int> input_of;  // key times -> their accessor, shared
  for (const SavedAnimation& saved : animations) {
    tinygltf::Animation animation;
    animation.name = saved.name;
    for (const motion::KeyframeTrack& track : saved.tracks) {
      const auto [input, added] = input_of.try_emplace(track.times, -1);
      if (added) input->second = add_times(builder, gltf, track.times);
      tinygltf::AnimationSampler sampler;
      sampler.input = input->second;
      sampler.output = add_values(builder, track);
      sampler.interpolation = interpolation_name(track.interpolation);
      tinygltf::AnimationChannel channel;
      channel.sampler = static_cast<int>(animation.samplers.size());
      channel.target_node = track.joint;  // joint j is node j
      channel.target_path = path_name(track.path);
      animation.samplers.push_back(sampler);
      animation.channels.push_back(channel);
    }
    gltf.animations.push_back(std::move(animation));
  }
}

}  // namespace sweepd::io
