#include "io/gltf/gltf_clip_load.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/quaternion.hpp>
#include <limits>
#include <vector>

#include "io/animation_choice.h"
#include "io/gltf/gltf_accessors.h"
#include "io/gltf/gltf_skin_skeleton.h"
#include "io/rest_transform.h"

namespace sweepd::io {

namespace {

using namespace gltf;

// Rotation outputs may be normalised integers (glTF 2.0, section 3.11).
const std::vector<int> kRotationTypes = {
    TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_BYTE,
    TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_SHORT,
    TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT};

// What carries a joint node's animated local transform into its clip joint's frame: the
// transform of the non-joint nodes between it and its parent joint (or the scene, for a root),
// then the scale of its ancestor joints (clip offsets are in scene units).
struct JointFrame {
  bool identity = true;     // the node's parent node is its parent joint's node (or none)
  glm::dmat4 between{1.0};  // parent joint's world^-1 * parent node's world
  glm::dquat rotation{1.0, 0.0, 0.0, 0.0};
  glm::dvec3 ancestor_scale{1.0};

  glm::vec3 point(const float* t) const {
    const glm::dvec4 p = between * glm::dvec4(t[0], t[1], t[2], 1.0);
    return glm::vec3(ancestor_scale * glm::dvec3(p));
  }
  glm::vec3 vector(const float* t) const {
    return glm::vec3(ancestor_scale * (glm::dmat3(between) * glm::dvec3(t[0], t[1], t[2])));
  }
  glm::quat turn(const float* q) const {  // q is x, y, z, w
    const glm::dquat r = rotation * glm::dquat(q[3], q[0], q[1], q[2]);
    return glm::quat(glm::dquat(r.w, r.x, r.y, r.z));
  }
};

std::vector<JointFrame> joint_frames(const AccessorReader& reader, const tinygltf::Skin& skin,
                                     const SkinSkeleton& skin_skeleton, const NodeGraph& graph) {
  const deform::Skeleton& skeleton = skin_skeleton.skeleton;
  std::vector<JointFrame> frames(skeleton.joints.size());
  std::vector<glm::dvec3> world_scale(skeleton.joints.size());
  for (int j = 0; j < skeleton.size(); ++j) {
    const int parent = skeleton.joints[j].parent;
    JointFrame& frame = frames[j];
    frame.ancestor_scale = parent < 0 ? glm::dvec3(1.0) : world_scale[parent];
    world_scale[j] = frame.ancestor_scale * glm::dvec3(skeleton.joints[j].rest_scale);
    const int node = skin.joints[skin_skeleton.order[j]];
    const int parent_node = graph.parent[node];
    const int parent_joint_node = parent < 0 ? -1 : skin.joints[skin_skeleton.order[parent]];
    if (parent_node == parent_joint_node) continue;
    frame.identity = false;
    frame.between = parent_joint_node < 0
                        ? graph.world[parent_node]
                        : glm::inverse(graph.world[parent_joint_node]) * graph.world[parent_node];
    deform::Joint between;
    if (!decompose_rest_transform(frame.between, between))
      reader.fail("the nodes above joint '" + skeleton.joints[j].name +
                  "' have a degenerate (zero-scale) transform");
    frame.rotation = glm::dquat(between.rest_rotation);
  }
  return frames;
}

motion::Interpolation interpolation_of(const AccessorReader& reader, const std::string& name,
                                       const std::string& where) {
  if (name == "LINEAR") return motion::Interpolation::kLinear;
  if (name == "STEP") return motion::Interpolation::kStep;
  if (name == "CUBICSPLINE") return motion::Interpolation::kCubicSpline;
  reader.fail(where + ": unknown interpolation '" + name +
              "' (expected LINEAR, STEP or CUBICSPLINE)");
}

// A track's values moved into its clip joint's frame (tangents as vectors).
void carry_into_joint_frame(motion::KeyframeTrack& track, const JointFrame& frame) {
  const std::size_t c = static_cast<std::size_t>(track.components());
  const bool cubic = track.interpolation == motion::Interpolation::kCubicSpline;
  for (std::size_t i = 0; i + c <= track.values.size(); i += c) {
    float* v = track.values.data() + i;
    const bool tangent = cubic && (i / c) % 3 != 1;
    if (track.path == motion::TrackPath::kRotation) {
      const glm::quat q = frame.turn(v);
      v[0] = q.x, v[1] = q.y, v[2] = q.z, v[3] = q.w;
    } else {
      const glm::vec3 t = tangent ? frame.vector(v) : frame.point(v);
      v[0] = t.x, v[1] = t.y, v[2] = t.z;
    }
  }
}

// Whether any key value (not a tangent) of a scale output differs from the rest scale.
bool scale_moves(const std::vector<double>& values, bool cubic, const glm::vec3& rest) {
  for (std::size_t i = 0; i + 3 <= values.size(); i += 3) {
    if (cubic && (i / 3) % 3 != 1) continue;
    for (int k = 0; k < 3; ++k)
      if (std::abs(values[i + k] - rest[k]) > 1e-6 * std::max(1.0f, std::abs(rest[k]))) return true;
  }
  return false;
}

// The animation `clip` of a parsed document; `file` names it in messages.
motion::Clip clip_of(const tinygltf::Model& gltf, const std::filesystem::path& file,
                     int animation_index, LoadReport& report) {
  const AccessorReader reader(file, gltf);
  const tinygltf::Animation& animation = gltf.animations[animation_index];
  const NodeGraph graph = build_node_graph(reader, gltf);
  const int mesh_node = choose_skinned_node(reader, gltf, report);
  if (mesh_node < 0 && gltf.skins.empty())
    reader.fail("no skin: the clip's joints are a skin's joints, and the file has none");
  const tinygltf::Skin& skin = gltf.skins[mesh_node < 0 ? 0 : gltf.nodes[mesh_node].skin];
  const SkinSkeleton skin_skeleton = build_skeleton(reader, gltf, skin, graph);
  const deform::Skeleton& skeleton = skin_skeleton.skeleton;
  const std::vector<JointFrame> frames = joint_frames(reader, skin, skin_skeleton, graph);

  motion::Clip result;
  for (const deform::Joint& joint : skeleton.joints) {
    motion::ClipJoint& clip_joint = result.joints.emplace_back();
    clip_joint.name = joint.name;
    clip_joint.parent = joint.parent;
    clip_joint.rest_rotation = joint.rest_rotation;
    clip_joint.offset = joint.rest_translation;
  }
  for (std::size_t j = 0; j < frames.size(); ++j)
    result.joints[j].offset *= glm::vec3(frames[j].ancestor_scale);

  std::vector<int> joint_of_node(gltf.nodes.size(), -1);
  for (std::size_t s = 0; s < skin.joints.size(); ++s)
    joint_of_node[skin.joints[s]] = skin_skeleton.new_index[s];
  const std::string name =
      "animation " + std::to_string(animation_index) + " ('" + animation.name + "')";
  int outside = 0, morphs = 0;
  std::string scaled;
  for (std::size_t c = 0; c < animation.channels.size(); ++c) {
    const tinygltf::AnimationChannel& channel = animation.channels[c];
    std::string where = name + " channel " + std::to_string(c);
    if (channel.sampler < 0 || channel.sampler >= static_cast<int>(animation.samplers.size()))
      reader.fail(where + " refers to missing sampler " + std::to_string(channel.sampler));
    if (channel.target_node < 0 || channel.target_node >= static_cast<int>(gltf.nodes.size()))
      reader.fail(where + " targets missing node " + std::to_string(channel.target_node));
    const std::string& path = channel.target_path;
    if (path != "rotation" && path != "translation" && path != "scale" && path != "weights")
      reader.fail(where + " has unknown target path '" + path +
                  "' (expected rotation, translation, scale or weights)");
    where += " (" + path + " of node " + std::to_string(channel.target_node) + " '" +
             gltf.nodes[channel.target_node].name + "')";
    const tinygltf::AnimationSampler& sampler = animation.samplers[channel.sampler];
    motion::KeyframeTrack track;
    track.interpolation = interpolation_of(reader, sampler.interpolation, where);
    const std::vector<double> times =
        reader.read(sampler.input, {where + " input", TINYGLTF_TYPE_SCALAR, kFloat, false});
    track.times.assign(times.begin(), times.end());
    if (path == "weights") {
      ++morphs;
      continue;
    }
    const int joint = joint_of_node[channel.target_node];
    if (joint < 0) {
      ++outside;
      continue;
    }
    const bool rotation = path == "rotation";
    const std::vector<double> values = reader.read(
        sampler.output, {where + " output", rotation ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3,
                         rotation ? kRotationTypes : kFloat, rotation});
    if (path == "scale") {
      if (scale_moves(values, track.interpolation == motion::Interpolation::kCubicSpline,
                      skeleton.joints[joint].rest_scale))
        scaled += (scaled.empty() ? "" : ", ") + skeleton.joints[joint].name;
      continue;
    }
    track.joint = joint;
    track.path = rotation ? motion::TrackPath::kRotation : motion::TrackPath::kTranslation;
    track.values.assign(values.begin(), values.end());
    if (const std::string problem = motion::track_problem(track); !problem.empty())
      reader.fail(where + ": " + problem);
    if (!frames[joint].identity || frames[joint].ancestor_scale != glm::dvec3(1.0))
      carry_into_joint_frame(track, frames[joint]);
    result.tracks.push_back(std::move(track));
  }
  if (result.tracks.empty())
    reader.fail(name + " moves none of the skin's joints (" +
                std::to_string(animation.channels.size()) + " channels)");
  if (outside > 0)
    result.warnings.push_back(std::to_string(outside) +
                              " channels animate nodes that are not the skin's joints: not played");
  if (morphs > 0)
    result.warnings.push_back(std::to_string(morphs) + " morph-target weight channels: not played");
  if (!scaled.empty())
    result.warnings.push_back("scale keys on " + scaled +
                              ": not played (sweepd poses rotations and the root's translation)");
  result.set_keyframed_timing();
  return result;
}

std::vector<std::string> animation_names(const tinygltf::Model& gltf) {
  std::vector<std::string> names;
  for (const tinygltf::Animation& animation : gltf.animations) names.push_back(animation.name);
  return names;
}

// The animation a user's `clip` names (io/animation_choice.h).
motion::Clip chosen_clip(const tinygltf::Model& gltf, const std::filesystem::path& file,
                         const std::string& clip, LoadReport& report) {
  return clip_of(gltf, file, choose_animation(animation_names(gltf), clip, file), report);
}

}  // namespace

motion::Clip load_gltf_clip(const std::filesystem::path& file, const std::string& clip) {
  return load_gltf_clip(file, clip,
                        GltfUriPolicy::within(std::filesystem::absolute(file).parent_path()));
}

motion::Clip load_gltf_clip(const std::filesystem::path& file, const std::string& clip,
                            const GltfUriPolicy& uris) {
  LoadReport report;
  return chosen_clip(parse_gltf_file(file, uris, &report), file, clip, report);
}

std::vector<FileAnimation> load_gltf_animations(const std::filesystem::path& file) {
  LoadReport report;
  const tinygltf::Model gltf = parse_gltf_file(
      file, GltfUriPolicy::within(std::filesystem::absolute(file).parent_path()), &report);
  return every_animation(animation_names(gltf),
                         [&](int index) { return clip_of(gltf, file, index, report); });
}

motion::Clip load_gltf_clip(std::span<const std::uint8_t> bytes, const std::filesystem::path& label,
                            const std::string& clip) {
  LoadReport report;
  return chosen_clip(parse_gltf_bytes(bytes, label, GltfUriPolicy::self_contained(), &report),
                     label, clip, report);
}

}  // namespace sweepd::io
