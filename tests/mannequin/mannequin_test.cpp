// Tests of the procedural mannequin: size, topology, rig, skin weights, UVs, and body shape.
#include "mannequin/mannequin.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <map>
#include <stdexcept>
#include <vector>

#include "deform/mesh/mesh_topology.h"

namespace sweepd::mannequin {

using namespace deform;  // the mannequin is made of the deform library's types
namespace {

// Generated once per size and shared by the tests below (72k takes about a second).
const Model& mannequin(int target_vertices) {
  static std::map<int, Model> cache;
  auto it = cache.find(target_vertices);
  if (it == cache.end()) {
    const auto start = std::chrono::steady_clock::now();
    it = cache.emplace(target_vertices, make_mannequin({target_vertices})).first;
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("mannequin(%d): %zu vertices, %zu triangles in %.2f s\n", target_vertices,
                it->second.vertex_count(), it->second.triangle_count(), seconds);
  }
  return it->second;
}

glm::vec3 joint_position(const Model& model, const std::string& name) {
  const int j = model.skeleton.find(name);
  EXPECT_GE(j, 0) << name;
  return glm::vec3(model.skeleton.world_rest_matrices()[j][3]);
}

// Largest distance from the segment a->b's line of the vertices within 4 mm of the plane
// orthogonal to it at fraction t, and within `reach` of the line (to skip other limbs).
float cross_section_radius(const Model& model, const glm::vec3& a, const glm::vec3& b, float t,
                           float reach) {
  const glm::vec3 axis = glm::normalize(b - a);
  const glm::vec3 centre = a + t * (b - a);
  float radius = 0.0f;
  for (const glm::vec3& p : model.positions) {
    const glm::vec3 d = p - centre;
    const float along = glm::dot(d, axis);
    if (std::abs(along) > 0.004f) continue;
    const float across = glm::length(d - along * axis);
    if (across < reach) radius = std::max(radius, across);
  }
  return radius;
}

class MannequinSizes : public ::testing::TestWithParam<int> {};

TEST_P(MannequinSizes, VertexCountWithinTenPercentOfTarget) {
  const Model& model = mannequin(GetParam());
  const double ratio = static_cast<double>(model.vertex_count()) / GetParam();
  EXPECT_GT(ratio, 0.9);  // the tolerance
  EXPECT_LT(ratio, 1.1);
}

TEST_P(MannequinSizes, IsOneClosedManifoldOnceSeamsAreWelded) {
  const Model& model = mannequin(GetParam());
  const MeshTopology topology = analyze_topology(model.positions, model.indices);
  EXPECT_TRUE(topology.closed_manifold())
      << "boundary " << topology.boundary_edges << ", non-manifold edges "
      << topology.non_manifold_edges << ", vertices " << topology.non_manifold_vertices
      << ", inconsistent " << topology.inconsistent_edges << ", degenerate "
      << topology.degenerate_triangles;
  EXPECT_EQ(topology.components, 1u);
  // UV seams duplicate some vertices: 17 charts, so up to a quarter at 2k, fewer above.
  EXPECT_LT(topology.welded_vertices, model.vertex_count());
  EXPECT_GT(topology.welded_vertices, model.vertex_count() * 7 / 10);
  std::printf("  welded %zu, euler characteristic %ld\n", topology.welded_vertices,
              topology.euler_characteristic);
}

TEST_P(MannequinSizes, ValidatesWithUnitWeightsAndUnitSquareUvs) {
  const Model& model = mannequin(GetParam());
  EXPECT_EQ(model.validate(), "");
  ASSERT_EQ(model.uvs.size(), model.vertex_count());
  for (const glm::vec2& uv : model.uvs) {
    ASSERT_GE(uv.x, 0.0f);
    ASSERT_LE(uv.x, 1.0f);
    ASSERT_GE(uv.y, 0.0f);
    ASSERT_LE(uv.y, 1.0f);
  }
  for (const auto& weights : model.skin_weights) {
    float sum = 0.0f;
    for (float w : weights) sum += w;
    ASSERT_NEAR(sum, 1.0f, 1e-5f);  // four floats normalised in float: a few ulps
  }
}

TEST_P(MannequinSizes, StandsOnTheGroundAboutOneSeventyFiveTall) {
  const Model& model = mannequin(GetParam());
  glm::vec3 lo(1e9f), hi(-1e9f);
  for (const glm::vec3& p : model.positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  EXPECT_EQ(lo.y, 0.0f);  // shifted exactly onto the ground
  EXPECT_GT(hi.y, 1.70f);
  EXPECT_LT(hi.y, 1.80f);
  // Left-right symmetric up to the mesh: 2k-vertex edges (~4 cm) can shave a fingertip.
  EXPECT_NEAR(lo.x, -hi.x, 0.03f);
  // Faces +Z: the toes reach further forward than the heels and the back reach backwards.
  EXPECT_GT(hi.z, -lo.z);
  std::printf("  box (%.3f %.3f %.3f) .. (%.3f %.3f %.3f)\n", lo.x, lo.y, lo.z, hi.x, hi.y, hi.z);
}

TEST_P(MannequinSizes, NormalsPointOutwardAndVolumeIsHuman) {
  const Model& model = mannequin(GetParam());
  double six_volume = 0.0;
  for (std::size_t t = 0; t < model.indices.size(); t += 3) {
    const glm::dvec3 a = model.positions[model.indices[t]];
    const glm::dvec3 b = model.positions[model.indices[t + 1]];
    const glm::dvec3 c = model.positions[model.indices[t + 2]];
    six_volume += glm::dot(a, glm::cross(b, c));
  }
  const double litres = six_volume / 6.0 * 1000.0;
  // An adult of 1.75 m and 60-90 kg displaces roughly 60-90 litres.
  EXPECT_GT(litres, 55.0);
  EXPECT_LT(litres, 95.0);
  std::printf("  volume %.1f litres\n", litres);
}

TEST_P(MannequinSizes, TrianglesAreWellShapedAndStayInOneUvChart) {
  const Model& model = mannequin(GetParam());
  std::size_t slivers = 0;
  float widest_uv_edge = 0.0f;
  for (std::size_t t = 0; t < model.indices.size(); t += 3) {
    float smallest_angle = 180.0f;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = model.indices[t + k], b = model.indices[t + (k + 1) % 3],
                          c = model.indices[t + (k + 2) % 3];
      const glm::vec3 u = glm::normalize(model.positions[b] - model.positions[a]);
      const glm::vec3 v = glm::normalize(model.positions[c] - model.positions[a]);
      smallest_angle =
          std::min(smallest_angle, std::acos(std::clamp(glm::dot(u, v), -1.0f, 1.0f)) * 57.29578f);
      widest_uv_edge = std::max(widest_uv_edge, glm::length(model.uvs[b] - model.uvs[a]));
    }
    if (smallest_angle < 10.0f) ++slivers;
  }
  // Decimation plus relaxation leave few slivers (measured: under 0.1% below 10 degrees).
  EXPECT_LT(slivers, model.triangle_count() / 100);
  // The 17 charts sit in tiles 1/5 wide (5 x 5 atlas): a triangle never stretches across charts.
  EXPECT_LT(widest_uv_edge, 0.2f);
}

TEST_P(MannequinSizes, SeamDuplicatesShareNormalsAndSkin) {
  const Model& model = mannequin(GetParam());
  std::size_t welded_count = 0;
  const std::vector<std::uint32_t> welded =
      weld_coincident_positions(model.positions, &welded_count);
  std::vector<std::size_t> first(welded_count, SIZE_MAX);
  for (std::size_t v = 0; v < model.vertex_count(); ++v) {
    ASSERT_NEAR(glm::length(model.normals[v]), 1.0f, 1e-5f);  // unit, to float rounding
    std::size_t& f = first[welded[v]];
    if (f == SIZE_MAX) {
      f = v;
      continue;
    }
    ASSERT_EQ(model.normals[v], model.normals[f]);  // copies of one vertex: exactly equal
    ASSERT_EQ(model.skin_joints[v], model.skin_joints[f]);
    ASSERT_EQ(model.skin_weights[v], model.skin_weights[f]);
  }
}

TEST_P(MannequinSizes, ConsecutiveVerticesAreNeighboursOnTheSurface) {
  // Compact vertex streams store deltas between consecutive vertices (protocol/README.md), so
  // the vertex order follows the surface: few consecutive vertices lie further apart than a
  // few triangle edges. In the marching order a quarter of them did at 72k.
  const Model& model = mannequin(GetParam());
  std::vector<float> edges;
  for (std::size_t t = 0; t < model.indices.size(); t += 3)
    edges.push_back(
        glm::distance(model.positions[model.indices[t]], model.positions[model.indices[t + 1]]));
  std::nth_element(edges.begin(), edges.begin() + edges.size() / 2, edges.end());
  const float median_edge = edges[edges.size() / 2];
  std::size_t far = 0;
  for (std::size_t v = 1; v < model.vertex_count(); ++v)
    far += glm::distance(model.positions[v], model.positions[v - 1]) > 4.0f * median_edge;
  const double far_share = static_cast<double>(far) / static_cast<double>(model.vertex_count());
  std::printf("%d: %.3f of consecutive vertices further apart than 4 median edges\n", GetParam(),
              far_share);
  EXPECT_LT(far_share, 0.10);
}

INSTANTIATE_TEST_SUITE_P(Targets, MannequinSizes, ::testing::Values(2000, 5000, 72000));

TEST(Mannequin, ReachesLargeTargetsWithinTenPercent) {
  for (int target : {15000, 250000}) {
    const Model model = make_mannequin({target});
    const double ratio = static_cast<double>(model.vertex_count()) / target;
    EXPECT_GT(ratio, 0.9) << target;  // the tolerance
    EXPECT_LT(ratio, 1.1) << target;
  }
}

TEST(Mannequin, IsBitIdenticalAcrossCalls) {
  const Model a = make_mannequin({5000});
  const Model& b = mannequin(5000);
  ASSERT_EQ(a.vertex_count(), b.vertex_count());
  ASSERT_EQ(a.indices, b.indices);
  auto same_bytes = [](const auto& x, const auto& y) {
    return x.size() == y.size() &&
           std::memcmp(x.data(), y.data(), x.size() * sizeof(x.front())) == 0;
  };
  EXPECT_TRUE(same_bytes(a.positions, b.positions));
  EXPECT_TRUE(same_bytes(a.normals, b.normals));
  EXPECT_TRUE(same_bytes(a.uvs, b.uvs));
  EXPECT_TRUE(same_bytes(a.skin_weights, b.skin_weights));
  EXPECT_TRUE(same_bytes(a.skin_joints, b.skin_joints));
}

TEST(Mannequin, RejectsTargetsOutOfRange) {
  EXPECT_THROW(make_mannequin({10}), std::invalid_argument);
  EXPECT_THROW(make_mannequin({kMannequinMaxVertices + 1}), std::invalid_argument);
}

TEST(Mannequin, HasTheCmuJointNamesParentsFirstWithIdentityRotations) {
  const Model& model = mannequin(5000);
  const Skeleton& skeleton = model.skeleton;
  EXPECT_EQ(skeleton.size(), 31);
  EXPECT_EQ(skeleton.validate(), "");
  EXPECT_EQ(skeleton.joints[0].name, "Hips");
  const std::pair<const char*, const char*> child_parent[] = {
      {"LowerBack", "Hips"},
      {"Spine", "LowerBack"},
      {"Spine1", "Spine"},
      {"Neck", "Spine1"},
      {"Neck1", "Neck"},
      {"Head", "Neck1"},
      {"LHipJoint", "Hips"},
      {"LeftUpLeg", "LHipJoint"},
      {"LeftLeg", "LeftUpLeg"},
      {"LeftFoot", "LeftLeg"},
      {"LeftToeBase", "LeftFoot"},
      {"RHipJoint", "Hips"},
      {"RightUpLeg", "RHipJoint"},
      {"RightLeg", "RightUpLeg"},
      {"RightFoot", "RightLeg"},
      {"RightToeBase", "RightFoot"},
      {"LeftShoulder", "Spine1"},
      {"LeftArm", "LeftShoulder"},
      {"LeftForeArm", "LeftArm"},
      {"LeftHand", "LeftForeArm"},
      {"LThumb", "LeftHand"},
      {"LeftFingerBase", "LeftHand"},
      {"LeftHandFinger1", "LeftFingerBase"},
      {"RightShoulder", "Spine1"},
      {"RightArm", "RightShoulder"},
      {"RightForeArm", "RightArm"},
      {"RightHand", "RightForeArm"},
      {"RThumb", "RightHand"},
      {"RightFingerBase", "RightHand"},
      {"RightHandFinger1", "RightFingerBase"}};
  for (const auto& [child, parent] : child_parent) {
    const int c = skeleton.find(child);
    ASSERT_GE(c, 0) << child;
    EXPECT_EQ(skeleton.joints[c].parent, skeleton.find(parent)) << child;
  }
  for (const Joint& joint : skeleton.joints) {
    EXPECT_EQ(joint.rest_rotation, glm::quat(1, 0, 0, 0)) << joint.name;
    EXPECT_EQ(joint.rest_scale, glm::vec3(1.0f)) << joint.name;
  }
}

TEST(Mannequin, StandsInAnAPoseWithTheLeftArmOnPlusX) {
  const Model& model = mannequin(5000);
  for (const char* side : {"Left", "Right"}) {
    const glm::vec3 shoulder = joint_position(model, std::string(side) + "Arm");
    const glm::vec3 wrist = joint_position(model, std::string(side) + "Hand");
    const glm::vec3 d = wrist - shoulder;
    const float degrees_down =
        std::atan2(-d.y, std::sqrt(d.x * d.x + d.z * d.z)) * 180.0f / 3.14159265f;
    EXPECT_GT(degrees_down, 35.0f) << side;  // A-pose: 40-45 degrees like the shared male
    EXPECT_LT(degrees_down, 50.0f) << side;
  }
  EXPECT_GT(joint_position(model, "LeftHand").x, 0.4f);
  EXPECT_LT(joint_position(model, "RightHand").x, -0.4f);
  EXPECT_GT(joint_position(model, "Head").y, 1.5f);
  EXPECT_LT(joint_position(model, "LeftFoot").y, 0.15f);
}

TEST(Mannequin, LimbsTaperAndBulgeLikeABody) {
  const Model& model = mannequin(72000);
  // Forearm: thicker below the elbow than at the wrist.
  const glm::vec3 elbow = joint_position(model, "LeftForeArm");
  const glm::vec3 wrist = joint_position(model, "LeftHand");
  const float forearm_upper = cross_section_radius(model, elbow, wrist, 0.25f, 0.08f);
  // 5 cm above the wrist joint: closer, the thumb's fillet widens the section.
  const float forearm_wrist = cross_section_radius(model, elbow, wrist, 0.8f, 0.08f);
  EXPECT_LT(forearm_wrist, 0.85f * forearm_upper);  // design: 3.1 cm vs 4.3 cm half-axes
  // Calf: the lower leg bulges a third of the way down and narrows towards the ankle.
  const glm::vec3 knee = joint_position(model, "LeftLeg");
  const glm::vec3 ankle = joint_position(model, "LeftFoot");
  const float calf = cross_section_radius(model, knee, ankle, 0.3f, 0.12f);
  const float above_ankle = cross_section_radius(model, knee, ankle, 0.8f, 0.12f);
  EXPECT_LT(above_ankle, 0.8f * calf);  // design: 3.8 cm vs 6.9 cm (with the calf offset)
  std::printf("  forearm %.3f -> %.3f, calf %.3f -> %.3f\n", forearm_upper, forearm_wrist, calf,
              above_ankle);
}

TEST(Mannequin, TorsoIsWiderThanDeep) {
  const Model& model = mannequin(72000);
  const float chest_height = joint_position(model, "Spine").y;
  glm::vec3 lo(1e9f), hi(-1e9f);
  for (const glm::vec3& p : model.positions) {
    if (std::abs(p.y - chest_height) > 0.01f || std::abs(p.x) > 0.3f) continue;
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const float width = hi.x - lo.x, depth = hi.z - lo.z;
  EXPECT_GT(width, 1.3f * depth);  // design at the Spine joint: 29 cm wide, 21 cm deep
  EXPECT_GT(width, 0.25f);
  EXPECT_LT(width, 0.40f);
  std::printf("  chest %.3f wide, %.3f deep\n", width, depth);
}

TEST(Mannequin, SkinWeightsBlendAcrossTheElbowAndChangeSmoothly) {
  const Model& model = mannequin(72000);
  const int arm = model.skeleton.find("LeftArm");
  const int fore_arm = model.skeleton.find("LeftForeArm");
  auto weight_of = [&](std::size_t v, int joint) {
    for (int k = 0; k < kInfluences; ++k)
      if (model.skin_joints[v][k] == joint) return model.skin_weights[v][k];
    return 0.0f;
  };
  int blended = 0;
  for (std::size_t v = 0; v < model.vertex_count(); ++v) {
    const float a = weight_of(v, arm), f = weight_of(v, fore_arm);
    if (a > 0.3f && f > 0.3f) ++blended;
  }
  EXPECT_GT(blended, 20);  // a blend zone around the elbow, not a hard cut
  // Along every edge the weights change by less than 1 (L1 distance of the weight vectors):
  // a hard cut between two bones gives 2; the shortest blend zones (+-2 cm at the finger
  // joints, smoothstep slope 1.5 / 4 cm) against 1.2 cm edges give about 0.9 at most.
  float worst = 0.0f;
  for (std::size_t t = 0; t < model.indices.size(); t += 3) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = model.indices[t + k], b = model.indices[t + (k + 1) % 3];
      // Joints of a, plus joints of b that a lacks: each joint counted once.
      float change = 0.0f;
      for (int i = 0; i < kInfluences; ++i) {
        change += std::abs(model.skin_weights[a][i] - weight_of(b, model.skin_joints[a][i]));
        if (weight_of(a, model.skin_joints[b][i]) == 0.0f) change += model.skin_weights[b][i];
      }
      worst = std::max(worst, change);
    }
  }
  EXPECT_LT(worst, 1.0f);
  std::printf("  %d elbow-blended vertices, largest weight change along an edge %.3f\n", blended,
              worst);
}

}  // namespace
}  // namespace sweepd::mannequin
