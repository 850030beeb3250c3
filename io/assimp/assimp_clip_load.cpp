#include "io/assimp/assimp_clip_load.h"

#include <assimp/anim.h>

#include <algorithm>
#include <cmath>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <set>

#include "io/animation_choice.h"
#include "io/assimp/assimp_scene.h"
#include "io/rest_transform.h"

namespace sweepd::io {

namespace {

namespace fs = std::filesystem;
using namespace assimp;

// assimp's own default when a file gives no ticks per second (its viewer and glTF exporter).
constexpr double kDefaultTicksPerSecond = 25.0;
constexpr double kMovedTranslation = 1e-6;  // m: below this a joint's translation is its rest's
constexpr double kMovedScale = 1e-4;        // relative

std::vector<std::string> animation_names(const aiScene& scene) {
  std::vector<std::string> names;
  for (unsigned a = 0; a < scene.mNumAnimations; ++a)
    names.emplace_back(scene.mAnimations[a]->mName.C_Str());
  return names;
}

// The key interval holding `time` (ticks): k with keys[k].mTime <= time < keys[k+1].mTime, and
// the fraction of the way to k+1; the first or last key alone outside the keys.
template <typename Key>
std::pair<unsigned, double> key_interval(const Key* keys, unsigned count, double time) {
  if (count == 1 || time <= keys[0].mTime) return {0, 0.0};
  if (time >= keys[count - 1].mTime) return {count - 1, 0.0};
  const Key* after = std::upper_bound(keys, keys + count, time,
                                      [](double t, const Key& key) { return t < key.mTime; });
  const unsigned k = static_cast<unsigned>(after - keys) - 1;
  return {k, (time - keys[k].mTime) / (keys[k + 1].mTime - keys[k].mTime)};
}

glm::dvec3 vector_at(const aiVectorKey* keys, unsigned count, double time) {
  const auto [k, s] = key_interval(keys, count, time);
  const glm::dvec3 a(keys[k].mValue.x, keys[k].mValue.y, keys[k].mValue.z);
  if (s == 0.0) return a;
  const glm::dvec3 b(keys[k + 1].mValue.x, keys[k + 1].mValue.y, keys[k + 1].mValue.z);
  return (1.0 - s) * a + s * b;
}

glm::dquat rotation_at(const aiQuatKey* keys, unsigned count, double time) {
  const auto [k, s] = key_interval(keys, count, time);
  const aiQuaternion& q = keys[k].mValue;
  const glm::dquat a(q.w, q.x, q.y, q.z);
  if (s == 0.0) return a;
  const aiQuaternion& r = keys[k + 1].mValue;
  glm::dquat b(r.w, r.x, r.y, r.z);
  if (glm::dot(a, b) < 0.0) b = -b;  // the shorter arc, as assimp interpolates
  return glm::normalize(glm::slerp(a, b, s));
}

// A node's local transform at `time` (ticks): its channel's keys where it has them, its rest
// transform's parts where it does not.
glm::dmat4 node_transform(const aiNode& node, const aiNodeAnim* channel, double time,
                          double unit_scale) {
  if (!channel) return to_glm(node.mTransformation, unit_scale);
  aiVector3D rest_scale, rest_position;
  aiQuaternion rest_rotation;
  node.mTransformation.Decompose(rest_scale, rest_rotation, rest_position);
  const glm::dvec3 position =
      channel->mNumPositionKeys > 0
          ? vector_at(channel->mPositionKeys, channel->mNumPositionKeys, time)
          : glm::dvec3(rest_position.x, rest_position.y, rest_position.z);
  const glm::dquat rotation =
      channel->mNumRotationKeys > 0
          ? rotation_at(channel->mRotationKeys, channel->mNumRotationKeys, time)
          : glm::dquat(rest_rotation.w, rest_rotation.x, rest_rotation.y, rest_rotation.z);
  const glm::dvec3 scale = channel->mNumScalingKeys > 0
                               ? vector_at(channel->mScalingKeys, channel->mNumScalingKeys, time)
                               : glm::dvec3(rest_scale.x, rest_scale.y, rest_scale.z);
  glm::dmat4 m = glm::mat4_cast(rotation);
  for (int c = 0; c < 3; ++c) m[c] *= scale[c];
  m[3] = glm::dvec4(position * unit_scale, 1.0);
  return m;
}

void add_key_times(const aiNodeAnim& channel, std::set<double>& times) {
  for (unsigned k = 0; k < channel.mNumPositionKeys; ++k) times.insert(channel.mPositionKeys[k].mTime);
  for (unsigned k = 0; k < channel.mNumRotationKeys; ++k) times.insert(channel.mRotationKeys[k].mTime);
  for (unsigned k = 0; k < channel.mNumScalingKeys; ++k) times.insert(channel.mScalingKeys[k].mTime);
}

bool finite_keys(const aiNodeAnim& channel) {
  auto finite = [](double v) { return std::isfinite(v); };
  for (unsigned k = 0; k < channel.mNumPositionKeys; ++k) {
    const aiVectorKey& key = channel.mPositionKeys[k];
    if (!finite(key.mTime) || !finite(key.mValue.x) || !finite(key.mValue.y) || !finite(key.mValue.z))
      return false;
  }
  for (unsigned k = 0; k < channel.mNumRotationKeys; ++k) {
    const aiQuatKey& key = channel.mRotationKeys[k];
    if (!finite(key.mTime) || !finite(key.mValue.w) || !finite(key.mValue.x) ||
        !finite(key.mValue.y) || !finite(key.mValue.z))
      return false;
  }
  for (unsigned k = 0; k < channel.mNumScalingKeys; ++k) {
    const aiVectorKey& key = channel.mScalingKeys[k];
    if (!finite(key.mTime) || !finite(key.mValue.x) || !finite(key.mValue.y) || !finite(key.mValue.z))
      return false;
  }
  return true;
}

motion::Clip clip_of(const ImportedScene& imported, const fs::path& file, int index) {
  const aiScene& scene = *imported.scene;
  const std::vector<std::string> names = animation_names(scene);
  const aiAnimation& animation = *scene.mAnimations[index];
  const std::string name = "animation " + std::to_string(index) + " ('" + names[index] + "')";
  auto fail = [&](const std::string& reason) { throw LoadError(file, name + ": " + reason); };

  LoadReport report;
  const SceneNodes nodes = scene_nodes(scene, imported.unit_scale);
  std::vector<const aiNodeAnim*> channel_of(nodes.node.size(), nullptr);
  int outside = 0;
  for (unsigned c = 0; c < animation.mNumChannels; ++c) {
    const aiNodeAnim& channel = *animation.mChannels[c];
    if (!finite_keys(channel))
      fail("channel " + std::to_string(c) + " ('" + channel.mNodeName.C_Str() +
           "') has a key that is not a finite number");
    const auto node = nodes.by_name.find(channel.mNodeName.C_Str());
    if (node == nodes.by_name.end()) {
      ++outside;
      continue;
    }
    channel_of[node->second] = &channel;
  }
  // The model's joints when the file has a skin; else (an animation exported alone) the joints
  // of the animated nodes.
  const Character character = find_character(scene, nodes, file, report);
  std::vector<int> bones;
  if (character.body >= 0) {
    bones = character.bones;
  } else {
    for (std::size_t v = 0; v < nodes.node.size(); ++v)
      if (channel_of[v] && helper_owner(nodes, static_cast<int>(v)) >= 0)
        bones.push_back(helper_owner(nodes, static_cast<int>(v)));
    if (bones.empty()) fail("no skin, and no channel animates a node of the scene");
  }
  const AssimpSkeleton skeleton = build_assimp_skeleton(nodes, bones, file, report);

  motion::Clip result;
  for (const deform::Joint& joint : skeleton.skeleton.joints) {
    motion::ClipJoint& clip_joint = result.joints.emplace_back();
    clip_joint.name = joint.name;
    clip_joint.parent = joint.parent;
    clip_joint.rest_rotation = joint.rest_rotation;
    clip_joint.offset = joint.rest_translation;
  }
  const double ticks_per_second =
      animation.mTicksPerSecond > 0.0 ? animation.mTicksPerSecond : kDefaultTicksPerSecond;
  std::vector<char> played(nodes.node.size(), 0);
  std::string scaled;
  for (int j = 0; j < skeleton.skeleton.size(); ++j) {
    const deform::Joint& joint = skeleton.skeleton.joints[j];
    // The nodes of the joint's local transform, from its parent joint's node (exclusive; the
    // scene's root, inclusive, for a root joint) down to its own node.
    const int own = skeleton.joint_node[j];
    const int stop = joint.parent < 0 ? -1 : skeleton.joint_node[joint.parent];
    std::vector<int> path;
    for (int v = own; v != stop; v = nodes.parent[v]) path.push_back(v);
    std::reverse(path.begin(), path.end());
    std::set<double> ticks;
    for (const int v : path)
      if (channel_of[v]) {
        add_key_times(*channel_of[v], ticks);
        played[v] = 1;
      }
    if (ticks.empty()) continue;

    motion::KeyframeTrack rotation, translation;
    rotation.joint = translation.joint = j;
    rotation.path = motion::TrackPath::kRotation;
    translation.path = motion::TrackPath::kTranslation;
    bool moves = false, scales = false;
    glm::quat previous(1.0f, 0.0f, 0.0f, 0.0f);
    for (const double tick : ticks) {
      const float seconds = static_cast<float>(tick / ticks_per_second);
      if (!rotation.times.empty() && !(seconds > rotation.times.back())) continue;
      glm::dmat4 local(1.0);
      for (const int v : path)
        local = local * node_transform(*nodes.node[v], channel_of[v], tick, imported.unit_scale);
      deform::Joint at;
      if (!decompose_rest_transform(local, at))
        fail("joint '" + joint.name + "' has a zero scale at " + std::to_string(seconds) + " s");
      glm::quat q = at.rest_rotation;
      if (!rotation.times.empty() && glm::dot(q, previous) < 0.0f) q = -q;  // sign-continuous
      previous = q;
      rotation.times.push_back(seconds);
      rotation.values.insert(rotation.values.end(), {q.x, q.y, q.z, q.w});
      translation.times.push_back(seconds);
      translation.values.insert(translation.values.end(),
                                {at.rest_translation.x, at.rest_translation.y,
                                 at.rest_translation.z});
      moves = moves || glm::length(glm::dvec3(at.rest_translation - joint.rest_translation)) >
                           kMovedTranslation;
      for (int c = 0; c < 3; ++c)
        scales = scales || std::abs(at.rest_scale[c] - joint.rest_scale[c]) >
                               kMovedScale * std::max(1.0f, std::abs(joint.rest_scale[c]));
    }
    if (const std::string problem = motion::track_problem(rotation); !problem.empty())
      fail("joint '" + joint.name + "': " + problem);
    result.tracks.push_back(std::move(rotation));
    if (moves) result.tracks.push_back(std::move(translation));
    if (scales) scaled += (scaled.empty() ? "" : ", ") + joint.name;
  }
  for (std::size_t v = 0; v < nodes.node.size(); ++v) outside += channel_of[v] && !played[v];
  if (result.tracks.empty())
    fail("moves none of the skeleton's joints (" + std::to_string(animation.mNumChannels) +
         " channels)");
  if (outside > 0)
    result.warnings.push_back(std::to_string(outside) +
                              " channels animate nodes that are not the skeleton's joints: not "
                              "played");
  if (!scaled.empty())
    result.warnings.push_back("scale keys on " + scaled +
                              ": not played (sweepd poses rotations and the root's translation)");
  result.set_keyframed_timing();
  return result;
}

}  // namespace

motion::Clip load_assimp_clip(std::span<const std::uint8_t> bytes, const fs::path& label,
                              const std::string& clip) {
  LoadReport report;
  const ImportedScene imported = import_assimp_scene(bytes, label, true, report);
  return clip_of(imported, label, choose_animation(animation_names(*imported.scene), clip, label));
}

std::vector<FileAnimation> load_assimp_animations(std::span<const std::uint8_t> bytes,
                                                  const fs::path& label) {
  LoadReport report;
  const ImportedScene imported = import_assimp_scene(bytes, label, true, report);
  return every_animation(animation_names(*imported.scene),
                         [&](int index) { return clip_of(imported, label, index); });
}

}  // namespace sweepd::io
