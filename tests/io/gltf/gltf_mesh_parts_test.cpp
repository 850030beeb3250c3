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
#include "io/gltf/gltf_load.h"
#include "io/gltf/gltf_save.h"
#include "mannequin/mannequin.h"
#include "tests/cli/sweepctl_process.h"
#include "tests/deform/shared_male.h"
#include "tests/io/gltf_test_files.h"
#include "tests/io/split_character.h"

namespace sweepd::io {
namespace {

namespace fs = std::filesystem;
using deform::MeshPart;
using deform::Model;
using testing::ScratchDirectory;
using testing::split_character;
using testing::SplitCharacter;

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
