// A glTF clip made in the test from the shared data: frames of the CMU clip cmu_01_01.bvh
// retargeted onto the shared MakeHuman male (motion::Retargeter), baked as keyframes of every
// joint's local rotation and the root's translation, and written into a copy of the male
// (io::save_gltf, whose joint nodes 0..J-1 are its skeleton's joints) as three animations with
// the same keys: "linear" (LINEAR), "step" (STEP) and "cubic" (CUBICSPLINE, Catmull-Rom-like
// tangents so that the tangent terms matter).
//   bake_cmu_clip(model, keys)   keys = K keyframes, 1/30 s apart, every 8th frame of the clip
//   write_baked_gltf(model, baked, file)
//   write_baked_fbx(glb, fbx)    that .glb as ASCII FBX with its three animation stacks, written
//                                by assimp's exporter (io/assimp/assimp_convert.h); returns its bytes
#pragma once

#include <assimp/scene.h>
#include <tiny_gltf.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <string>
#include <vector>

#include "deform/model/model.h"
#include "io/assimp/assimp_convert.h"
#include "io/bvh/bvh_load.h"
#include "io/gltf/gltf_save.h"
#include "motion/retarget.h"
#include "tests/test_paths.h"

namespace sweepd::io::testing {

struct BakedClip {
  std::vector<float> times;                            // K
  std::vector<std::vector<glm::quat>> rotations;       // K × J local rotations
  std::vector<glm::vec3> root;                         // K root translations
  std::vector<std::vector<glm::quat>> rotation_slope;  // K × J tangents (per second)
  std::vector<glm::vec3> root_slope;                   // K
};

inline BakedClip bake_cmu_clip(const deform::Model& model, int keys) {
  const motion::Retargeter clip(
      io::load_bvh(std::filesystem::path(SWEEPD_SHARED_DATA) / "motion/cmu_01_01.bvh"), model);
  BakedClip baked;
  for (int k = 0; k < keys; ++k) {
    const deform::Pose pose = clip.pose_at_frame(8 * k);
    baked.times.push_back(static_cast<float>(k) / 30.0f);
    baked.rotations.push_back(pose.local_rotations);
    baked.root.push_back(pose.root_translation);
    if (k > 0)  // one hemisphere from key to key, so the cubic tangents make sense
      for (std::size_t j = 0; j < pose.local_rotations.size(); ++j)
        if (glm::dot(baked.rotations[k][j], baked.rotations[k - 1][j]) < 0.0f)
          baked.rotations[k][j] = -baked.rotations[k][j];
  }
  const std::size_t joints = model.skeleton.joints.size();
  for (int k = 0; k < keys; ++k) {
    const int a = std::max(k - 1, 0), b = std::min(k + 1, keys - 1);
    const float dt = baked.times[b] - baked.times[a];
    std::vector<glm::quat> slope(joints);
    for (std::size_t j = 0; j < joints; ++j)
      slope[j] = (baked.rotations[b][j] - baked.rotations[a][j]) / dt;
    baked.rotation_slope.push_back(slope);
    baked.root_slope.push_back((baked.root[b] - baked.root[a]) / dt);
  }
  return baked;
}

// Appends floats to buffer 0 as a new accessor (4-byte aligned); returns its index.
inline int add_float_accessor(tinygltf::Model& gltf, const std::vector<float>& values, int type,
                              std::size_t count) {
  std::vector<unsigned char>& data = gltf.buffers[0].data;
  while (data.size() % 4 != 0) data.push_back(0);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = data.size();
  view.byteLength = values.size() * sizeof(float);
  data.resize(data.size() + view.byteLength);
  std::memcpy(data.data() + view.byteOffset, values.data(), view.byteLength);
  gltf.bufferViews.push_back(view);
  tinygltf::Accessor accessor;
  accessor.bufferView = static_cast<int>(gltf.bufferViews.size()) - 1;
  accessor.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
  accessor.type = type;
  accessor.count = count;
  if (type == TINYGLTF_TYPE_SCALAR) {
    accessor.minValues = {values.front()};
    accessor.maxValues = {values.back()};
  }
  gltf.accessors.push_back(accessor);
  return static_cast<int>(gltf.accessors.size()) - 1;
}

inline void add_baked_animation(tinygltf::Model& gltf, const BakedClip& baked,
                                const std::string& interpolation) {
  const bool cubic = interpolation == "CUBICSPLINE";
  const std::size_t keys = baked.times.size();
  tinygltf::Animation animation;
  animation.name = interpolation == "LINEAR" ? "linear" : cubic ? "cubic" : "step";
  const int input = add_float_accessor(gltf, baked.times, TINYGLTF_TYPE_SCALAR, keys);
  const auto add_channel = [&](int node, const std::string& path, const std::vector<float>& out) {
    tinygltf::AnimationSampler sampler;
    sampler.input = input;
    sampler.interpolation = interpolation;
    const int type = path == "rotation" ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3;
    sampler.output = add_float_accessor(gltf, out, type, cubic ? 3 * keys : keys);
    animation.samplers.push_back(sampler);
    tinygltf::AnimationChannel channel;
    channel.sampler = static_cast<int>(animation.samplers.size()) - 1;
    channel.target_node = node;
    channel.target_path = path;
    animation.channels.push_back(channel);
  };
  const auto put_quat = [](std::vector<float>& out, const glm::quat& q) {
    out.insert(out.end(), {q.x, q.y, q.z, q.w});
  };
  const auto put_vec = [](std::vector<float>& out, const glm::vec3& v) {
    out.insert(out.end(), {v.x, v.y, v.z});
  };
  for (std::size_t j = 0; j < baked.rotations[0].size(); ++j) {
    std::vector<float> out;
    for (std::size_t k = 0; k < keys; ++k) {
      if (cubic) put_quat(out, baked.rotation_slope[k][j]);
      put_quat(out, baked.rotations[k][j]);
      if (cubic) put_quat(out, baked.rotation_slope[k][j]);
    }
    add_channel(static_cast<int>(j), "rotation", out);
  }
  std::vector<float> out;
  for (std::size_t k = 0; k < keys; ++k) {
    if (cubic) put_vec(out, baked.root_slope[k]);
    put_vec(out, baked.root[k]);
    if (cubic) put_vec(out, baked.root_slope[k]);
  }
  add_channel(0, "translation", out);
  gltf.animations.push_back(animation);
}

inline tinygltf::Model read_glb(const std::filesystem::path& file) {
  tinygltf::TinyGLTF io;
  tinygltf::Model gltf;
  std::string error, warning;
  if (!io.LoadBinaryFromFile(&gltf, &error, &warning, file.string()))
    throw std::runtime_error("cannot read " + file.string() + ": " + error);
  return gltf;
}

inline void write_glb(tinygltf::Model& gltf, const std::filesystem::path& file) {
  gltf.buffers[0].uri.clear();
  if (!tinygltf::TinyGLTF().WriteGltfSceneToFile(&gltf, file.string(), false, true, false, true))
    throw std::runtime_error("cannot write " + file.string());
}

// The model with the three baked animations, as a .glb at `file`.
inline void write_baked_gltf(const deform::Model& model, const BakedClip& baked,
                             const std::filesystem::path& file) {
  io::save_gltf(model, file);
  tinygltf::Model gltf = read_glb(file);
  for (const char* interpolation : {"LINEAR", "STEP", "CUBICSPLINE"})
    add_baked_animation(gltf, baked, interpolation);
  write_glb(gltf, file);
}

// assimp 5.2.5's FBX exporter writes key times as if they were seconds, whatever the
// animation's ticks per second (its glTF importer counts milliseconds): keys go in seconds.
inline void keys_in_seconds(aiScene& scene) {
  for (unsigned a = 0; a < scene.mNumAnimations; ++a) {
    aiAnimation& animation = *scene.mAnimations[a];
    const double ticks = animation.mTicksPerSecond > 0.0 ? animation.mTicksPerSecond : 25.0;
    for (unsigned c = 0; c < animation.mNumChannels; ++c) {
      aiNodeAnim& channel = *animation.mChannels[c];
      for (unsigned k = 0; k < channel.mNumPositionKeys; ++k) channel.mPositionKeys[k].mTime /= ticks;
      for (unsigned k = 0; k < channel.mNumRotationKeys; ++k) channel.mRotationKeys[k].mTime /= ticks;
      for (unsigned k = 0; k < channel.mNumScalingKeys; ++k) channel.mScalingKeys[k].mTime /= ticks;
    }
    animation.mDuration /= ticks;
    animation.mTicksPerSecond = 1.0;
  }
}

inline std::vector<std::uint8_t> write_baked_fbx(const std::filesystem::path& glb,
                                                 const std::filesystem::path& fbx) {
  const std::vector<std::uint8_t> bytes =
      io::convert_with_assimp(glb, io::AssimpExport::kFbxMetres, keys_in_seconds);
  std::ofstream(fbx, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  return bytes;
}

}  // namespace sweepd::io::testing
