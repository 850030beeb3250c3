// Tests for the skinning baselines: deform::linear_blend_skinning and
// deform::dual_quaternion_skinning (and their parallel variants).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <numbers>
#include <vector>

#include "deform/baselines/dual_quaternion_skinning.h"
#include "deform/baselines/linear_blend_skinning.h"
#include "deform/model/forward_kinematics.h"
#include "io/gltf/gltf_load.h"
#include "mannequin/mannequin.h"
#include "tests/deform/tube_mesh.h"

namespace sweepd::deform::skinning_test {

using mannequin::make_mannequin;
namespace {

constexpr float kPi = std::numbers::pi_v<float>;

using SkinningFunction = void (*)(const Model&, std::span<const glm::mat4>, std::span<glm::vec3>,
                                  std::span<glm::vec3>);

struct Method {
  const char* name;
  SkinningFunction skin;
};
const Method kMethods[] = {{"LBS", linear_blend_skinning}, {"DQS", dual_quaternion_skinning}};

// An "arm" along +X: joints shoulder (0,0,0), elbow (1,0,0), wrist (2,0,0); a tube of radius 0.1
// around it, rigid to the shoulder for x < 0.8, to the elbow for x > 1.2, blended linearly in
// between.
Model tube_arm() {
  test_geometry::Mesh mesh;
  test_geometry::add_tube(mesh, {.base = {0, 0, 0},
                                 .axis = {1, 0, 0},
                                 .radial = {0, 1, 0},
                                 .radius_1 = 0.1f,
                                 .radius_2 = 0.1f,
                                 .length = 2.0f,
                                 .segments = 32,
                                 .rings = 41});
  Model model;
  model.name = "tube arm";
  model.positions = mesh.positions;
  model.indices = mesh.indices;
  model.normals = compute_vertex_normals(model.positions, model.indices);
  model.skeleton.joints = {{.name = "shoulder", .parent = -1},
                           {.name = "elbow", .parent = 0, .rest_translation = {1, 0, 0}},
                           {.name = "wrist", .parent = 1, .rest_translation = {1, 0, 0}}};
  for (const glm::vec3& p : model.positions) {
    const float elbow = std::clamp((p.x - 0.8f) / 0.4f, 0.0f, 1.0f);
    model.skin_joints.push_back({0, 1, 2, 0});
    model.skin_weights.push_back({1.0f - elbow, elbow, 0.0f, 0.0f});
  }
  return model;
}

std::filesystem::path shared_male() {
  return std::filesystem::path(SWEEPD_SHARED_DATA) / "models" / "makehuman_male_cmu.glb";
}

float height(const Model& model) {
  float low = model.positions[0].y, high = low;
  for (const glm::vec3& p : model.positions) low = std::min(low, p.y), high = std::max(high, p.y);
  return high - low;
}

std::vector<glm::mat4> skinning_for(const Model& model, const Pose& pose) {
  std::vector<glm::mat4> world(model.skeleton.joints.size()), skinning(world.size());
  forward_kinematics(model.skeleton, pose, world);
  skinning_matrices(world, world_rest_inverse_matrices(model.skeleton), skinning);
  return skinning;
}

// A pose that bends every joint a little, differently (deterministic).
Pose bent_pose(const Skeleton& skeleton) {
  Pose pose = rest_pose(skeleton);
  for (int j = 0; j < skeleton.size(); ++j)
    pose.local_rotations[j] =
        pose.local_rotations[j] *
        glm::angleAxis(0.2f + 0.05f * static_cast<float>(j % 7),
                       glm::normalize(glm::vec3(std::sin(1.0f + j), std::cos(2.0f * j), 0.5f)));
  pose.root_translation += glm::vec3(0.1f, -0.05f, 0.2f);
  return pose;
}

void expect_rest_mesh_reproduced(const Model& model) {
  const std::vector<glm::mat4> skinning = skinning_for(model, rest_pose(model.skeleton));
  const float tolerance = 1e-5f * height(model);  // the acceptance bound
  std::vector<glm::vec3> positions(model.vertex_count()), normals(model.vertex_count());
  for (const Method& method : kMethods) {
    method.skin(model, skinning, positions, normals);
    float worst = 0.0f, worst_normal = 0.0f;
    for (std::size_t v = 0; v < model.vertex_count(); ++v) {
      worst = std::max(worst, glm::distance(positions[v], model.positions[v]));
      worst_normal = std::max(worst_normal, glm::distance(normals[v], model.normals[v]));
    }
    EXPECT_LT(worst, tolerance) << method.name << " on " << model.name;
    // Unit normals turned by identity: float round-off only.
    EXPECT_LT(worst_normal, 1e-5f) << method.name << " on " << model.name;
    std::printf("%s rest-pose error on %s: %.3g m (bound %.3g m)\n", method.name,
                model.name.c_str(), worst, tolerance);
  }
}

TEST(Skinning, RestPoseReproducesTheTubeArm) { expect_rest_mesh_reproduced(tube_arm()); }

TEST(Skinning, RestPoseReproducesTheSharedMale) {
  if (!std::filesystem::exists(shared_male()))
    GTEST_SKIP() << "shared data absent: " << shared_male();
  expect_rest_mesh_reproduced(io::load_gltf(shared_male()));
}

TEST(Skinning, RestPoseReproducesTheMannequin) {
  expect_rest_mesh_reproduced(make_mannequin({.target_vertices = 15000}));
}

TEST(Skinning, RigidlyBoundVerticesMoveWithTheirJoint) {
  Model model = tube_arm();
  for (auto& w : model.skin_weights) w = {1.0f, 0.0f, 0.0f, 0.0f};  // all on the shoulder
  Pose pose = rest_pose(model.skeleton);
  const glm::quat turn = glm::angleAxis(2.0f, glm::normalize(glm::vec3(0.3f, 1.0f, -0.2f)));
  pose.local_rotations[0] = turn;
  pose.root_translation = {0.5f, -0.25f, 1.0f};
  const std::vector<glm::mat4> skinning = skinning_for(model, pose);
  std::vector<glm::vec3> positions(model.vertex_count()), normals(model.vertex_count());
  for (const Method& method : kMethods) {
    method.skin(model, skinning, positions, normals);
    for (std::size_t v = 0; v < model.vertex_count(); ++v) {
      const glm::vec3 expected = turn * model.positions[v] + pose.root_translation;
      // A rigid motion of a 2 m model in float: 1e-5 × height.
      ASSERT_LT(glm::distance(positions[v], expected), 2e-5f) << method.name << " vertex " << v;
      ASSERT_LT(glm::distance(normals[v], turn * model.normals[v]), 1e-5f) << method.name;
    }
  }
}

// Largest distance from the arm's axis (the X axis) among vertices at the elbow ring (x = 1).
float elbow_ring_radius(const Model& model, const std::vector<glm::vec3>& positions) {
  float radius = 0.0f;
  for (std::size_t v = 0; v < model.vertex_count(); ++v)
    if (std::abs(model.positions[v].x - 1.0f) < 1e-4f)
      radius = std::max(radius, std::hypot(positions[v].y, positions[v].z));
  return radius;
}

TEST(Skinning, TwistCollapsesLbsButNotDqs) {
  const Model model = tube_arm();
  Pose pose = rest_pose(model.skeleton);
  const float twist = 2.0f * kPi / 3.0f;  // 120° about the arm's own axis
  pose.local_rotations[1] = glm::angleAxis(twist, glm::vec3(1, 0, 0));
  const std::vector<glm::mat4> skinning = skinning_for(model, pose);
  std::vector<glm::vec3> positions(model.vertex_count());
  // At the elbow ring the weights are 1/2 - 1/2. LBS averages the points p and twist(p): radius
  // 0.1·cos(60°) = 0.05. DQS blends the rotations: a 60° twist, radius 0.1 kept. Float + the
  // ring's exact x: 1e-5.
  linear_blend_skinning(model, skinning, positions, {});
  EXPECT_NEAR(elbow_ring_radius(model, positions), 0.1f * std::cos(twist / 2), 1e-5f);
  dual_quaternion_skinning(model, skinning, positions, {});
  EXPECT_NEAR(elbow_ring_radius(model, positions), 0.1f, 1e-5f);
}

TEST(Skinning, DqsBlendsAntipodalQuaternionsTheShortWay) {
  // Two roots at the origin, every vertex half on each: the blend is a pure rotation.
  Model model = tube_arm();
  model.skeleton.joints = {{.name = "a", .parent = -1}, {.name = "b", .parent = -1}};
  for (auto& j : model.skin_joints) j = {0, 1, 0, 0};
  for (auto& w : model.skin_weights) w = {0.5f, 0.5f, 0.0f, 0.0f};
  // As converted from matrices (largest component positive), these two have a negative 4D dot
  // product although the rotations are only 2·acos(0.48) ≈ 123° apart.
  const glm::quat qa(0.8f, 0.0f, 0.6f, 0.0f), qb(-0.6f, 0.0f, 0.0f, 0.8f);
  Pose pose = rest_pose(model.skeleton);
  pose.local_rotations = {qa, qb};
  const std::vector<glm::mat4> skinning = skinning_for(model, pose);
  ASSERT_LT(glm::dot(to_dual_quaternion(skinning[0]).real, to_dual_quaternion(skinning[1]).real),
            0.0f);
  const glm::quat short_way = glm::normalize(qa - qb);  // qb's sign aligned with qa
  const glm::quat naive = glm::normalize(qa + qb);
  // The two candidates differ by far more than the tolerance below, so the test can fail.
  ASSERT_GT(glm::angle(short_way * glm::inverse(naive)), 1.0f);
  std::vector<glm::vec3> positions(model.vertex_count());
  dual_quaternion_skinning(model, skinning, positions, {});
  // A rotation about the origin of a model 2 m long, in float: 1e-5.
  for (std::size_t v = 0; v < model.vertex_count(); ++v)
    ASSERT_LT(glm::distance(positions[v], short_way * model.positions[v]), 1e-5f) << "vertex " << v;
}

TEST(Skinning, ParallelVariantsAreBitIdentical) {
  const Model model =
      std::filesystem::exists(shared_male()) ? io::load_gltf(shared_male()) : tube_arm();
  const std::vector<glm::mat4> skinning = skinning_for(model, bent_pose(model.skeleton));
  const std::size_t n = model.vertex_count();
  std::vector<glm::vec3> positions(n), normals(n), parallel_positions(n), parallel_normals(n);
  using ParallelFunction = void (*)(const Model&, std::span<const glm::mat4>, std::span<glm::vec3>,
                                    std::span<glm::vec3>, int);
  const std::pair<SkinningFunction, ParallelFunction> pairs[] = {
      {linear_blend_skinning, linear_blend_skinning_parallel},
      {dual_quaternion_skinning, dual_quaternion_skinning_parallel}};
  for (const auto& [single, parallel] : pairs) {
    single(model, skinning, positions, normals);
    for (int threads : {1, 2, 3, 7}) {
      parallel(model, skinning, parallel_positions, parallel_normals, threads);
      EXPECT_EQ(std::memcmp(positions.data(), parallel_positions.data(), n * sizeof(glm::vec3)), 0)
          << threads << " threads on " << model.name;
      EXPECT_EQ(std::memcmp(normals.data(), parallel_normals.data(), n * sizeof(glm::vec3)), 0)
          << threads << " threads on " << model.name;
    }
  }
}

TEST(Skinning, PosedNormalsAreUnitAndPositionsMatchWithOrWithoutNormals) {
  const Model model = tube_arm();
  const std::vector<glm::mat4> skinning = skinning_for(model, bent_pose(model.skeleton));
  const std::size_t n = model.vertex_count();
  std::vector<glm::vec3> positions(n), normals(n), positions_only(n);
  for (const Method& method : kMethods) {
    method.skin(model, skinning, positions, normals);
    method.skin(model, skinning, positions_only, {});
    EXPECT_EQ(std::memcmp(positions.data(), positions_only.data(), n * sizeof(glm::vec3)), 0)
        << method.name;
    // Normalised in float: a few ulps.
    for (const glm::vec3& normal : normals) ASSERT_NEAR(glm::length(normal), 1.0f, 1e-5f);
  }
}

}  // namespace
}  // namespace sweepd::deform::skinning_test
