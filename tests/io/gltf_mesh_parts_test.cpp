// Characters made of several meshes (issue 15, item 2), made mechanically here from the shared
// male and the mannequin: the body cut into three skinned meshes on one skin (the torso a mesh
// of two primitives with two materials) plus a rigid prop under the head joint, written with
// the project's own writer and read back. The split character binds and poses like the
// original, the prop follows the head exactly, `sweepctl inspect` lists the meshes and a posed
// .glb keeps them.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <glm/gtc/quaternion.hpp>
#include <string>
#include <vector>

#include "deform/binding/bind.h"
#include "deform/binding/mesh_parts_joined.h"
#include "io/gltf_load.h"
#include "io/gltf_save.h"
#include "mannequin/mannequin.h"
#include "tests/cli/sweepctl_process.h"
#include "tests/deform/shared_male.h"
#include "tests/io/gltf_test_files.h"

namespace sweepd::io {
namespace {

namespace fs = std::filesystem;
using deform::MeshPart;
using deform::Model;
using testing::ScratchDirectory;

// The split character and, per vertex, the original vertex it copies (-1: the prop's).
struct SplitCharacter {
  Model model;
  std::vector<int> source;
};

// Which piece a triangle goes to, by its centroid: legs below the hips, the head above the
// neck's base, the torso (two primitives: left and right of x = 0) in between.
enum Piece { kLegs = 0, kTorsoLeft = 1, kTorsoRight = 2, kHead = 3 };
Piece piece_of(const Model& model, std::size_t triangle) {
  const std::vector<glm::mat4> world = model.skeleton.world_rest_matrices();
  const float hips = world[model.skeleton.find("Hips")][3].y;
  const float neck = world[model.skeleton.find("Neck")][3].y;
  glm::vec3 centre(0.0f);
  for (int k = 0; k < 3; ++k) centre += model.positions[model.indices[3 * triangle + k]] / 3.0f;
  if (centre.y < hips) return kLegs;
  if (centre.y > neck) return kHead;
  return centre.x < 0.0f ? kTorsoLeft : kTorsoRight;
}

// A closed octahedron of half-size 5 cm, 12 cm above the head joint: it touches nothing.
void add_prop(SplitCharacter& split, int head) {
  Model& model = split.model;
  const glm::vec3 centre =
      glm::vec3(model.skeleton.world_rest_matrices()[head][3]) + glm::vec3(0, 0.12f, 0);
  const glm::vec3 corners[6] = {{0.05f, 0, 0},  {-0.05f, 0, 0}, {0, 0.05f, 0},
                                {0, -0.05f, 0}, {0, 0, 0.05f},  {0, 0, -0.05f}};
  const std::uint32_t faces[24] = {0, 2, 4, 4, 2, 1, 1, 2, 5, 5, 2, 0,
                                   4, 3, 0, 1, 3, 4, 5, 3, 1, 0, 3, 5};
  MeshPart part{.name = "hat",
                .material = "felt",
                .mesh = 3,
                .first_vertex = static_cast<std::uint32_t>(model.vertex_count()),
                .vertex_count = 6,
                .first_index = static_cast<std::uint32_t>(model.indices.size()),
                .index_count = 24,
                .rigid_joint = head};
  for (const glm::vec3& corner : corners) {
    model.positions.push_back(centre + corner);
    model.normals.push_back(glm::normalize(corner));
    if (model.has_uvs()) model.uvs.emplace_back(0.5f, 0.5f);
    model.skin_joints.push_back({static_cast<std::uint16_t>(head), 0, 0, 0});
    model.skin_weights.push_back({1.0f, 0.0f, 0.0f, 0.0f});
    split.source.push_back(-1);
  }
  for (std::uint32_t corner : faces) model.indices.push_back(part.first_vertex + corner);
  model.parts.push_back(part);
}

// The original cut into legs, torso (two primitives) and head — each piece's triangles in their
// original order, its vertices the ones they use in ascending original order, so the seams'
// vertices appear in every piece that meets there — plus the hat.
SplitCharacter split_character(const Model& original) {
  SplitCharacter split;
  Model& model = split.model;
  model.name = original.name + "_split";
  model.skeleton = original.skeleton;
  const char* names[4] = {"legs", "torso", "torso", "head"};
  const char* materials[4] = {"skin", "shirt_left", "shirt_right", "skin"};
  const std::uint32_t meshes[4] = {0, 1, 1, 2};
  for (int piece = kLegs; piece <= kHead; ++piece) {
    std::vector<int> index_of(original.vertex_count(), -1);
    std::vector<std::uint32_t> triangles;
    for (std::size_t t = 0; t < original.triangle_count(); ++t)
      if (piece_of(original, t) == piece)
        for (int k = 0; k < 3; ++k) {
          index_of[original.indices[3 * t + k]] = 0;
          triangles.push_back(original.indices[3 * t + k]);
        }
    MeshPart part{.name = names[piece],
                  .material = materials[piece],
                  .mesh = meshes[piece],
                  .first_vertex = static_cast<std::uint32_t>(model.vertex_count()),
                  .first_index = static_cast<std::uint32_t>(model.indices.size())};
    for (std::size_t v = 0; v < original.vertex_count(); ++v) {
      if (index_of[v] < 0) continue;
      index_of[v] = static_cast<int>(model.vertex_count());
      split.source.push_back(static_cast<int>(v));
      model.positions.push_back(original.positions[v]);
      model.normals.push_back(original.normals[v]);
      if (original.has_uvs()) model.uvs.push_back(original.uvs[v]);
      model.skin_joints.push_back(original.skin_joints[v]);
      model.skin_weights.push_back(original.skin_weights[v]);
    }
    for (std::uint32_t corner : triangles) model.indices.push_back(index_of[corner]);
    part.vertex_count = static_cast<std::uint32_t>(model.vertex_count()) - part.first_vertex;
    part.index_count = static_cast<std::uint32_t>(model.indices.size()) - part.first_index;
    model.parts.push_back(part);
  }
  add_prop(split, original.skeleton.find("Head"));
  return split;
}

// A pose that bends what the split crosses: elbow, knee, spine, neck and head.
deform::Pose test_pose(const Model& model) {
  deform::Pose pose = deform::test::left_elbow_and_knee_flexed(model, 90.0f);
  deform::test::turn(model, pose, "Spine1", {1, 0, 0}, 20.0f);
  deform::test::turn(model, pose, "Neck", {0, 0, 1}, 15.0f);
  deform::test::turn(model, pose, "Head", {0, 1, 0}, 30.0f);
  return pose;
}

struct Posed {
  deform::BoundModel bound;
  std::vector<glm::vec3> positions;
  std::vector<glm::mat4> world_pose;
};

Posed bind_and_pose(const Model& model, const deform::Pose& pose) {
  Posed posed{deform::bind(model, deform::detect_rig_map(model.skeleton)), {}, {}};
  deform::test::Posing posing(posed.bound);
  posed.positions = deform::test::deformed(posing, pose, deform::DeformMethod::kSweep);
  posed.world_pose.assign(posing.world_pose().begin(), posing.world_pose().end());
  return posed;
}

// The whole check on one character; `original` is its single-mesh model.
void check_split_character(const Model& original, const fs::path& dir) {
  const SplitCharacter split = split_character(original);
  ASSERT_EQ(split.model.validate(), "");
  // Both go through the same writer and reader, so their rest positions are the same floats.
  save_gltf(original, dir / "original.glb");
  save_gltf(split.model, dir / "split.glb");
  const Model single = load_gltf(dir / "original.glb");
  LoadReport report;
  const Model loaded = load_gltf(dir / "split.glb", &report);

  // Every mesh and primitive is loaded, in file order, with its name, material and range.
  ASSERT_EQ(loaded.parts.size(), 5u);
  EXPECT_EQ(loaded.parts, split.model.parts);
  ASSERT_EQ(report.meshes.size(), 4u);
  EXPECT_EQ(report.meshes[1].name, "torso");
  EXPECT_EQ(report.meshes[1].part, 1);
  EXPECT_EQ(report.meshes[3].name, "hat");
  EXPECT_TRUE(report.meshes[3].ignored.empty());
  EXPECT_EQ(report.source_primitive_count, 5);
  EXPECT_EQ(loaded.vertex_count(), split.model.vertex_count());
  EXPECT_EQ(deform::mesh_parts_joined(loaded), (std::vector<std::uint8_t>{1, 1, 1, 1, 0}));

  const deform::Pose pose = test_pose(single);
  const Posed expected = bind_and_pose(single, pose);
  const Posed actual = bind_and_pose(loaded, pose);
  ASSERT_EQ(actual.bound.sweeps.size(), expected.bound.sweeps.size());
  const int head = loaded.skeleton.find("Head");
  const glm::mat4 head_motion =
      actual.world_pose[head] * glm::inverse(loaded.skeleton.world_rest_matrices()[head]);
  float body_error = 0.0f, prop_error = 0.0f;
  for (std::size_t v = 0; v < loaded.vertex_count(); ++v) {
    if (split.source[v] < 0) {
      const glm::vec3 rigid = glm::vec3(head_motion * glm::vec4(loaded.positions[v], 1.0f));
      prop_error = std::max(prop_error, glm::length(actual.positions[v] - rigid));
      EXPECT_EQ(actual.bound.vertices[v].skin_weight, 1.0f);
      EXPECT_EQ(actual.bound.vertices[v].sweep[0], -1);
      continue;
    }
    body_error = std::max(body_error,
                          glm::length(actual.positions[v] - expected.positions[split.source[v]]));
  }
  // Every original vertex is in some piece; those on a cut are in two or more.
  const std::size_t seam_copies = loaded.vertex_count() - 6 - original.vertex_count();
  std::printf("%s: %zu seam copies; split vs original posed: max %.3g m; hat vs head: %.3g m\n",
              original.name.c_str(), seam_copies, body_error, prop_error);
  EXPECT_GT(seam_copies, 0u);
  // The split binds the same welded surface, visited in another vertex order: float sums in
  // another order (1e-7 relative at 2 m) bound the difference; 1e-5 m is the figure.
  EXPECT_LT(body_error, 1e-5f);
  // The hat is skinned with weight 1 on the head: the head's rigid motion up to float rounding.
  EXPECT_LT(prop_error, 1e-5f);

  // sweepctl inspect lists every mesh, its vertex count and how it is handled.
  const sweepd::test::SweepctlResult inspect =
      sweepd::test::run_sweepctl("inspect " + (dir / "split.glb").string());
  ASSERT_EQ(inspect.exit_code, 0) << inspect.output;
  for (int k : {0, 1, 3}) {
    const MeshPart& part = loaded.parts[k];
    const std::string line =
        "  " + part.name + " (" +
        std::to_string(part.vertex_count + (k == 1 ? loaded.parts[2].vertex_count : 0)) +
        " vertices";
    EXPECT_NE(inspect.output.find(line), std::string::npos) << line << "\n" << inspect.output;
  }
  EXPECT_NE(inspect.output.find("skinned, swept with the body"), std::string::npos)
      << inspect.output;
  EXPECT_NE(inspect.output.find("rigid to joint Head"), std::string::npos) << inspect.output;

  // A posed .glb keeps the meshes, their names and materials.
  const fs::path posed_file = dir / "posed.glb";
  const sweepd::test::SweepctlResult pose_run = sweepd::test::run_sweepctl(
      "pose " + (dir / "split.glb").string() + " -o " + posed_file.string());
  ASSERT_EQ(pose_run.exit_code, 0) << pose_run.output;
  LoadReport posed_report;
  const Model posed = load_gltf(posed_file, &posed_report);
  EXPECT_EQ(posed.parts, loaded.parts);
  EXPECT_EQ(posed_report.meshes.size(), 4u);
}

TEST(GltfMeshParts, TheSplitMaleBindsAndPosesLikeTheOriginal) {
  SWEEPD_REQUIRE_SHARED_MODEL(testing::kMale);
  ScratchDirectory dir;
  check_split_character(load_gltf(testing::shared_model(testing::kMale)), dir / "");
}

TEST(GltfMeshParts, TheSplitMannequinBindsAndPosesLikeTheOriginal) {
  ScratchDirectory dir;
  check_split_character(mannequin::make_mannequin({.target_vertices = 6000}), dir / "");
}

// A skinned mesh that shares no position with the body stays a separate piece: LBS only.
TEST(GltfMeshParts, ASkinnedPieceThatTouchesNothingIsNotSwept) {
  Model model = mannequin::make_mannequin({.target_vertices = 3000});
  SplitCharacter split = split_character(model);
  Model& character = split.model;
  MeshPart& hat = character.parts.back();
  hat.rigid_joint = -1;  // now a skinned visor-like piece, weight 1 on the head
  EXPECT_EQ(deform::mesh_parts_joined(character), (std::vector<std::uint8_t>{1, 1, 1, 1, 0}));
  const deform::BoundModel bound = deform::bind(character, deform::detect_rig_map(model.skeleton));
  for (std::uint32_t v = hat.first_vertex; v < hat.first_vertex + hat.vertex_count; ++v)
    EXPECT_EQ(bound.vertices[v].skin_weight, 1.0f);
}

}  // namespace
}  // namespace sweepd::io
