// The ways a DCC exporter arranges the same character in a glTF scene (issue 15, items 3 and 6),
// made mechanically here from the shared male and the mannequin (written by io::save_gltf) with
// tinygltf, and read back by io::load_gltf:
//   centimetres     every node's translation, the vertices and the inverse bind matrices'
//                   translations ×100, under a new root node scaled 0.01 (Blender's and Maya's
//                   centimetre exports);
//   rotated         the armature and the mesh under a new root node turned 90° about X, each
//                   former root's transform turned back by -90°, so the world rest pose is the
//                   same (Blender's Y-up conversion applied to the armature object), and the
//                   vertices, normals and inverse bind matrices in the turned-back frame;
//   mesh parent     the skinned mesh's node under a new node moved 0.3 m and turned 30°, which
//                   glTF says a skinned mesh ignores (the joints place it);
//   all three at once.
// Each loads with the original's rest vertices, binds, and poses (sweep, LBS) with the
// original's posed vertices within 1e-5 m: float round-off of 1 m-sized coordinates through the
// extra 0.01 and ×100 and the folded root transform (the male is 1.8 m tall, the mannequin 1.75 m:
// 1e-5 m is below 1e-5 × height on both).
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <glm/gtc/quaternion.hpp>
#include <limits>
#include <string>
#include <vector>

#include "deform/binding/bind.h"
#include "io/gltf/gltf_load.h"
#include "io/gltf/gltf_save.h"
#include "mannequin/mannequin.h"
#include "tests/deform/shared_male.h"
#include "tests/io/gltf_test_files.h"

namespace sweepd::io::gltf_scene_variants_test {
namespace {

namespace fs = std::filesystem;
using testing::ScratchDirectory;

enum Change : unsigned { kCentimetres = 1, kRotated = 2, kMeshParent = 4 };

// Calls f on every float of the accessor's elements (tightly packed or strided).
void for_each_float(tinygltf::Model& gltf, int accessor_index,
                    const std::function<void(float* element)>& f) {
  const tinygltf::Accessor& accessor = gltf.accessors[accessor_index];
  ASSERT_EQ(accessor.componentType, TINYGLTF_COMPONENT_TYPE_FLOAT);
  const tinygltf::BufferView& view = gltf.bufferViews[accessor.bufferView];
  const std::size_t size = tinygltf::GetNumComponentsInType(accessor.type) * sizeof(float);
  const std::size_t stride = view.byteStride ? view.byteStride : size;
  unsigned char* data =
      gltf.buffers[view.buffer].data.data() + view.byteOffset + accessor.byteOffset;
  for (std::size_t i = 0; i < accessor.count; ++i) {
    float element[16];
    std::memcpy(element, data + i * stride, size);
    f(element);
    std::memcpy(data + i * stride, element, size);
  }
}

glm::dquat node_rotation(const tinygltf::Node& node) {
  return node.rotation.size() == 4
             ? glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2])
             : glm::dquat(1.0, 0.0, 0.0, 0.0);
}

void set_rotation(tinygltf::Node& node, const glm::dquat& q) {
  node.rotation = {q.x, q.y, q.z, q.w};
}

// Rewrites `file` with the changes.
void change_scene(const fs::path& file, const fs::path& out, unsigned changes) {
  tinygltf::TinyGLTF io;
  tinygltf::Model gltf;
  std::string error, warning;
  ASSERT_TRUE(io.LoadBinaryFromFile(&gltf, &error, &warning, file.string())) << error;
  tinygltf::Scene& scene = gltf.scenes[gltf.defaultScene < 0 ? 0 : gltf.defaultScene];
  int mesh_node = -1;
  for (int n = 0; n < static_cast<int>(gltf.nodes.size()); ++n)
    if (gltf.nodes[n].skin >= 0) mesh_node = n;
  ASSERT_GE(mesh_node, 0);
  ASSERT_EQ(gltf.nodes[mesh_node].matrix.size(), 0u);
  const auto add_root = [&](const std::string& name) {
    tinygltf::Node root;
    root.name = name;
    root.children = scene.nodes;
    gltf.nodes.push_back(root);
    scene.nodes = {static_cast<int>(gltf.nodes.size()) - 1};
    return static_cast<int>(gltf.nodes.size()) - 1;
  };
  if (changes & kCentimetres) {
    for (tinygltf::Node& node : gltf.nodes) {
      ASSERT_EQ(node.matrix.size(), 0u) << node.name;
      for (double& t : node.translation) t *= 100.0;
    }
    for (const tinygltf::Mesh& mesh : gltf.meshes)
      for (const tinygltf::Primitive& primitive : mesh.primitives) {
        const int positions = primitive.attributes.at("POSITION");
        for_each_float(gltf, positions, [](float* p) {
          for (int k = 0; k < 3; ++k) p[k] *= 100.0f;
        });
      }
    for (const tinygltf::Skin& skin : gltf.skins)
      for_each_float(gltf, skin.inverseBindMatrices, [](float* m) {
        for (int k = 12; k < 15; ++k) m[k] *= 100.0f;
      });
    gltf.nodes[add_root("centimetres")].scale = {0.01, 0.01, 0.01};
  }
  if (changes & kRotated) {
    const glm::dquat turn = glm::angleAxis(glm::radians(90.0), glm::dvec3(1, 0, 0));
    for (int root : scene.nodes) {
      tinygltf::Node& node = gltf.nodes[root];
      const glm::dvec3 t =
          node.translation.size() == 3
              ? glm::dvec3(node.translation[0], node.translation[1], node.translation[2])
              : glm::dvec3(0.0);
      const glm::dvec3 back = glm::inverse(turn) * t;
      node.translation = {back.x, back.y, back.z};
      set_rotation(node, glm::inverse(turn) * node_rotation(node));
    }
    set_rotation(gltf.nodes[add_root("rotated")], turn);
    // The mesh's data in the armature's frame too: v' = turn^-1 v, inverseBind' = inverseBind *
    // turn, so that inverseBind' v' = inverseBind v.
    const glm::mat3 back(glm::mat3_cast(glm::quat(glm::inverse(turn))));
    for (const tinygltf::Mesh& mesh : gltf.meshes)
      for (const tinygltf::Primitive& primitive : mesh.primitives)
        for (const char* name : {"POSITION", "NORMAL"}) {
          const int vectors = primitive.attributes.at(name);
          for_each_float(gltf, vectors, [&](float* v) {
            const glm::vec3 turned = back * glm::vec3(v[0], v[1], v[2]);
            for (int k = 0; k < 3; ++k) v[k] = turned[k];
          });
        }
    const glm::mat4 forward(glm::mat4_cast(glm::quat(turn)));
    for (const tinygltf::Skin& skin : gltf.skins)
      for_each_float(gltf, skin.inverseBindMatrices, [&](float* m) {
        glm::mat4 matrix;
        std::memcpy(&matrix[0][0], m, sizeof matrix);
        matrix = matrix * forward;
        std::memcpy(m, &matrix[0][0], sizeof matrix);
      });
  }
  if (changes & kMeshParent) {
    tinygltf::Node parent;
    parent.name = "mesh_parent";
    parent.translation = {0.3, -0.2, 0.1};
    set_rotation(parent, glm::angleAxis(glm::radians(30.0), glm::dvec3(0, 1, 0)));
    parent.children = {mesh_node};
    for (tinygltf::Node& node : gltf.nodes) std::erase(node.children, mesh_node);
    std::erase(scene.nodes, mesh_node);
    gltf.nodes.push_back(parent);
    scene.nodes.push_back(static_cast<int>(gltf.nodes.size()) - 1);
  }
  // POSITION's bounds, which glTF requires, as the data now is; other bounds are optional.
  for (const tinygltf::Mesh& mesh : gltf.meshes)
    for (const tinygltf::Primitive& primitive : mesh.primitives)
      for (const auto& [name, index] : primitive.attributes) {
        tinygltf::Accessor& accessor = gltf.accessors[index];
        accessor.minValues.clear();
        accessor.maxValues.clear();
        if (name != "POSITION") continue;
        accessor.minValues.assign(3, std::numeric_limits<double>::max());
        accessor.maxValues.assign(3, -std::numeric_limits<double>::max());
        for_each_float(gltf, index, [&](float* p) {
          for (int k = 0; k < 3; ++k) {
            accessor.minValues[k] = std::min<double>(accessor.minValues[k], p[k]);
            accessor.maxValues[k] = std::max<double>(accessor.maxValues[k], p[k]);
          }
        });
      }
  ASSERT_TRUE(io.WriteGltfSceneToFile(&gltf, out.string(), true, true, false, true));
}

float farthest(std::span<const glm::vec3> a, std::span<const glm::vec3> b) {
  float worst = 0.0f;
  for (std::size_t v = 0; v < a.size(); ++v) worst = std::max(worst, glm::distance(a[v], b[v]));
  return worst;
}

struct Posed {
  std::vector<glm::vec3> sweep, lbs;
};

Posed bind_and_pose(const deform::Model& model) {
  const deform::BoundModel bound = deform::bind(model, deform::detect_rig_map(model.skeleton));
  deform::Pose pose = deform::test::left_elbow_and_knee_flexed(model, 90.0f);
  deform::test::turn(model, pose, "Spine1", {1, 0, 0}, 20.0f);
  deform::test::turn(model, pose, "Head", {0, 1, 0}, 30.0f);
  pose.root_translation += glm::vec3(0.1f, 0.05f, -0.2f);
  deform::test::Posing posing(bound);
  return {deform::test::deformed(posing, pose, deform::DeformMethod::kSweep),
          deform::test::deformed(posing, pose, deform::DeformMethod::kLbs)};
}

void check_variants(const fs::path& original_file, const ScratchDirectory& dir) {
  const deform::Model original = load_gltf(original_file);
  const Posed expected = bind_and_pose(original);
  struct Variant {
    const char* name;
    unsigned changes;
  };
  for (const Variant& variant : {Variant{"centimetres", kCentimetres}, Variant{"rotated", kRotated},
                                 Variant{"mesh parent", kMeshParent},
                                 Variant{"all three", kCentimetres | kRotated | kMeshParent}}) {
    SCOPED_TRACE(original.name + " " + variant.name);
    const fs::path file =
        dir / (std::string("variant_") + std::to_string(variant.changes) + ".glb");
    change_scene(original_file, file, variant.changes);
    const deform::Model model = load_gltf(file);
    ASSERT_EQ(model.vertex_count(), original.vertex_count());
    // The 0.01 node folds into the root joint's rest scale (io/gltf/gltf_load.h).
    EXPECT_NEAR(model.skeleton.joints[0].rest_scale.x,
                variant.changes & kCentimetres ? 0.01f : 1.0f, 1e-6f);
    const float rest = farthest(model.positions, original.positions);
    const float normals = farthest(model.normals, original.normals);
    const Posed posed = bind_and_pose(model);
    const float sweep = farthest(posed.sweep, expected.sweep);
    const float lbs = farthest(posed.lbs, expected.lbs);
    std::printf(
        "%s, %s: rest %.2e m (normals %.2e), posed sweep %.2e m, LBS %.2e m from the original\n",
        original.name.c_str(), variant.name, rest, normals, sweep, lbs);
    EXPECT_LT(rest, 1e-5f);
    EXPECT_LT(normals, 1e-5f);  // unit vectors through the same float round-off
    EXPECT_LT(sweep, 1e-5f);
    EXPECT_LT(lbs, 1e-5f);
  }
}

TEST(GltfSceneVariants, MaleInCentimetresRotatedOrReparentedPosesAsTheOriginal) {
  SWEEPD_REQUIRE_SHARED_MODEL(testing::kMale);
  const ScratchDirectory dir;
  check_variants(testing::shared_model(testing::kMale), dir);
}

TEST(GltfSceneVariants, MannequinInCentimetresRotatedOrReparentedPosesAsTheOriginal) {
  const ScratchDirectory dir;
  const fs::path file = dir / "mannequin.glb";
  save_gltf(mannequin::make_mannequin({.target_vertices = 6000}), file);
  check_variants(file, dir);
}

}  // namespace
}  // namespace sweepd::io::gltf_scene_variants_test
