// Tests for the skinning baselines: deform::linear_blend_skinning and
// deform::dual_quaternion_skinning, over a SkinningTable or a Model.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <numbers>
#include <utility>
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

// The instruction sets this CPU runs: SSE2 always, AVX2+FMA where it has them.
std::vector<VertexLoopInstructions> instruction_sets() {
  std::vector<VertexLoopInstructions> sets = {VertexLoopInstructions::kBaseline};
  if (widest_vertex_loop_instructions() == VertexLoopInstructions::kAvx2Fma)
    sets.push_back(VertexLoopInstructions::kAvx2Fma);
  return sets;
}

using TableFunction = void (*)(const SkinningTable&, std::span<const glm::mat4>,
                               std::span<glm::vec3>, std::span<glm::vec3>, int);
const std::pair<const char*, TableFunction> kTableMethods[] = {{"LBS", linear_blend_skinning},
                                                               {"DQS", dual_quaternion_skinning}};

TEST(Skinning, ThreadCountsGiveBitIdenticalResultsOnEveryInstructionSet) {
  const Model model =
      std::filesystem::exists(shared_male()) ? io::load_gltf(shared_male()) : tube_arm();
  const std::vector<glm::mat4> skinning = skinning_for(model, bent_pose(model.skeleton));
  const std::size_t n = model.vertex_count();
  std::vector<glm::vec3> positions(n), normals(n), parallel_positions(n), parallel_normals(n);
  for (const VertexLoopInstructions instructions : instruction_sets()) {
    const SkinningTable table(model, instructions);
    for (const auto& [name, skin] : kTableMethods) {
      skin(table, skinning, positions, normals, 1);
      for (int threads : {2, 3, 7}) {
        skin(table, skinning, parallel_positions, parallel_normals, threads);
        EXPECT_EQ(std::memcmp(positions.data(), parallel_positions.data(), n * sizeof(glm::vec3)),
                  0)
            << name << ", " << threads << " threads on " << model.name;
        EXPECT_EQ(std::memcmp(normals.data(), parallel_normals.data(), n * sizeof(glm::vec3)), 0)
            << name << ", " << threads << " threads on " << model.name;
      }
    }
  }
}

// The textbook formulas, per vertex in double, as the reference the table's loops must match:
// LBS blends the matrices with the weights divided by their sum; DQS blends the dual quaternions
// (sign-flipped against the first weighted influence), normalises and applies the result.
struct Reference {
  glm::dvec3 lbs, dqs;
};
Reference reference_vertex(const Model& model, std::span<const glm::mat4> skinning, std::size_t v) {
  const auto& w = model.skin_weights[v];
  const auto& j = model.skin_joints[v];
  double sum = 0.0;
  for (const float weight : w) sum += weight;
  glm::dmat4 blended(0.0);
  glm::dquat real(0, 0, 0, 0), dual(0, 0, 0, 0);
  int first = -1;
  for (int k = 0; k < kInfluences; ++k) {
    if (w[k] <= 0.0f) continue;
    blended += glm::dmat4(skinning[j[k]]) * (w[k] / sum);
    const DualQuaternion q = to_dual_quaternion(skinning[j[k]]);
    if (first < 0) first = j[k];
    const DualQuaternion q0 = to_dual_quaternion(skinning[first]);
    const double sign = glm::dot(q.real, q0.real) < 0.0f ? -1.0 : 1.0;
    real += glm::dquat(q.real) * (sign * w[k]);
    dual += glm::dquat(q.dual) * (sign * w[k]);
  }
  const glm::dvec3 p(model.positions[v]);
  const double length = glm::length(real);
  real /= length;
  dual /= length;
  const glm::dquat translation = 2.0 * dual * glm::conjugate(real);
  return {glm::dvec3(blended * glm::dvec4(p, 1.0)),
          real * p + glm::dvec3(translation.x, translation.y, translation.z)};
}

TEST(Skinning, TableLoopsMatchTheTextbookFormulasOnEveryInstructionSet) {
  std::vector<Model> models = {tube_arm(), make_mannequin({.target_vertices = 5000})};
  if (std::filesystem::exists(shared_male())) models.push_back(io::load_gltf(shared_male()));
  for (const Model& model : models) {
    const std::vector<glm::mat4> skinning = skinning_for(model, bent_pose(model.skeleton));
    const std::size_t n = model.vertex_count();
    std::vector<glm::vec3> lbs(n), dqs(n);
    // Float against double on a body about 2 m across, through a chain of ~20 matrices: 1e-5 m.
    const double tolerance = 1e-5 * std::max(1.0f, height(model));
    for (const VertexLoopInstructions instructions : instruction_sets()) {
      const SkinningTable table(model, instructions);
      linear_blend_skinning(table, skinning, lbs, {}, 1);
      dual_quaternion_skinning(table, skinning, dqs, {}, 1);
      double worst_lbs = 0.0, worst_dqs = 0.0;
      for (std::size_t v = 0; v < n; ++v) {
        const Reference expected = reference_vertex(model, skinning, v);
        worst_lbs = std::max(worst_lbs, glm::distance(glm::dvec3(lbs[v]), expected.lbs));
        worst_dqs = std::max(worst_dqs, glm::distance(glm::dvec3(dqs[v]), expected.dqs));
      }
      const char* set = instructions == VertexLoopInstructions::kAvx2Fma ? "AVX2" : "SSE2";
      EXPECT_LT(worst_lbs, tolerance) << "LBS, " << set << ", " << model.name;
      EXPECT_LT(worst_dqs, tolerance) << "DQS, " << set << ", " << model.name;
      std::printf("%s %s: LBS %.3g m, DQS %.3g m from the reference\n", model.name.c_str(), set,
                  worst_lbs, worst_dqs);
    }
  }
}

TEST(Skinning, TheTableGroupsVerticesByTheirWeightedJointsAndNormalisesTheWeights) {
  Model model = tube_arm();
  model.skin_weights[0] = {0.25f, 0.25f, 0.0f, 0.0f};  // sums to 0.5: divided at build
  model.skin_weights[1] = {0.0f, 0.0f, 0.0f, 0.0f};    // no weight: stays at rest
  const SkinningTable table(model);
  std::size_t items = 0;
  int previous = -1;
  for (const SkinningTable::Group& group : table.groups()) {
    EXPECT_GT(group.influences, previous) << "groups in increasing influence count";
    previous = group.influences;
    items += group.end - group.begin;
    for (std::size_t i = group.begin; i < group.end; ++i) {
      const std::uint32_t v = table.vertices()[i];
      int weighted = 0;
      for (const float w : model.skin_weights[v]) weighted += w > 0.0f;
      EXPECT_EQ(weighted, group.influences) << "vertex " << v;
      float sum = 0.0f;
      for (int k = 0; k < group.influences; ++k)
        sum += table.weights()[group.first_influence + (i - group.begin) * group.influences + k];
      if (group.influences > 0) {
        EXPECT_NEAR(sum, 1.0f, 1e-6f) << "vertex " << v;
      }
    }
  }
  EXPECT_EQ(table.vertex_count(), model.vertex_count());
  EXPECT_EQ(items, table.item_count());
  EXPECT_EQ(items % kSkinningChunk, 0u) << "each group padded to whole chunks";
  const std::vector<glm::mat4> skinning = skinning_for(model, bent_pose(model.skeleton));
  std::vector<glm::vec3> positions(model.vertex_count());
  for (const auto& [name, skin] : kTableMethods) {
    skin(table, skinning, positions, {}, 1);
    EXPECT_EQ(positions[1], model.positions[1]) << name << ": the unweighted vertex stays at rest";
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
