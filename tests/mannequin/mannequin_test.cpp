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

#include "deform/mesh/disjoint_sets.h"
#include "deform/mesh/mesh_topology.h"
#include "deform/mesh/welded_mesh.h"
#include "tests/mirrored_model.h"

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

// The model's UV islands: triangles joined through shared vertices (a seam's copies split
// them). Returns each triangle's island id.
std::vector<std::uint32_t> uv_islands(const Model& model) {
  const std::vector<std::uint32_t> component =
      deform::vertex_components(model.indices, model.vertex_count());
  std::vector<std::uint32_t> island(model.triangle_count());
  for (std::size_t t = 0; t < island.size(); ++t) island[t] = component[model.indices[3 * t]];
  return island;
}

double uv_signed_area(const Model& model, std::size_t t) {
  const glm::dvec2 a = model.uvs[model.indices[3 * t]], b = model.uvs[model.indices[3 * t + 1]],
                   c = model.uvs[model.indices[3 * t + 2]];
  return 0.5 * glm::determinant(glm::dmat2(b - a, c - a));
}

struct UvLayout {
  std::size_t islands = 0;
  std::size_t folded = 0;       // triangles against their island's orientation, or flat in UV
  std::size_t overlapping = 0;  // sample points inside two triangles
  std::size_t samples_inside = 0;
};

// Folds: per island, the triangles whose signed UV area has the sign of the island's minority
// (or is zero). Overlaps: an n x n grid of points over [0, 1]^2, each counted once per triangle
// it lies inside (1e-9 of a UV unit inside every edge, so points on shared edges count once).
UvLayout check_uv_layout(const Model& model, int n) {
  UvLayout layout;
  const std::vector<std::uint32_t> island = uv_islands(model);
  std::map<std::uint32_t, std::pair<std::size_t, std::size_t>> signs;  // positive, negative
  for (std::size_t t = 0; t < island.size(); ++t) {
    const double area = uv_signed_area(model, t);
    auto& [positive, negative] = signs[island[t]];
    positive += area > 0.0;
    negative += area < 0.0;
    layout.folded += area == 0.0;
  }
  layout.islands = signs.size();
  for (const auto& [id, counts] : signs) layout.folded += std::min(counts.first, counts.second);
  std::vector<std::uint8_t> hits(static_cast<std::size_t>(n) * n, 0);
  for (std::size_t t = 0; t < island.size(); ++t) {
    glm::dvec2 p[3];
    for (int k = 0; k < 3; ++k) p[k] = glm::dvec2(model.uvs[model.indices[3 * t + k]]) * double(n);
    const double sign = uv_signed_area(model, t) < 0.0 ? -1.0 : 1.0;
    const glm::ivec2 lo = glm::max(glm::ivec2(glm::floor(glm::min(p[0], glm::min(p[1], p[2])))), 0);
    const glm::ivec2 hi =
        glm::min(glm::ivec2(glm::ceil(glm::max(p[0], glm::max(p[1], p[2])))), n - 1);
    for (int y = lo.y; y <= hi.y; ++y)
      for (int x = lo.x; x <= hi.x; ++x) {
        const glm::dvec2 q(x + 0.5, y + 0.5);
        bool inside = true;
        for (int k = 0; k < 3 && inside; ++k) {
          const glm::dvec2 e = p[(k + 1) % 3] - p[k], w = q - p[k];
          inside = sign * (e.x * w.y - e.y * w.x) > 1e-9 * n * glm::length(e);
        }
        if (!inside) continue;
        std::uint8_t& h = hits[static_cast<std::size_t>(y) * n + x];
        layout.overlapping += h == 1;  // a point counts once however many triangles hold it
        h = std::min(h + 1, 2);
      }
  }
  for (std::uint8_t h : hits) layout.samples_inside += h > 0;
  return layout;
}

// Dihedral angles (degrees, between the two triangles' normals) at the welded mesh's edges.
struct EdgeBend {
  glm::vec3 midpoint;
  float degrees;
  float length;
};

std::vector<EdgeBend> edge_bends(const Model& model) {
  const WeldedMesh welded = weld_mesh(model.positions, model.indices);
  auto normal = [&](std::size_t t) {
    const glm::vec3 a = welded.positions[welded.indices[3 * t]];
    const glm::vec3 b = welded.positions[welded.indices[3 * t + 1]];
    const glm::vec3 c = welded.positions[welded.indices[3 * t + 2]];
    return glm::normalize(glm::cross(b - a, c - a));
  };
  std::map<std::uint64_t, std::size_t> first_triangle;
  std::vector<EdgeBend> bends;
  for (std::size_t t = 0; t < welded.indices.size() / 3; ++t)
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t a = welded.indices[3 * t + k], b = welded.indices[3 * t + (k + 1) % 3];
      const auto [it, inserted] =
          first_triangle.try_emplace(std::min(a, b) << 32 | std::max(a, b), t);
      if (inserted) continue;
      const float cosine = std::clamp(glm::dot(normal(it->second), normal(t)), -1.0f, 1.0f);
      bends.push_back({0.5f * (welded.positions[a] + welded.positions[b]),
                       std::acos(cosine) * 57.29578f,
                       glm::distance(welded.positions[a], welded.positions[b])});
    }
  return bends;
}

// The chest ring: how sharply the upper chest bends, row by row, against the mesh's own smooth
// chest. Front and back of the torso (|x| under half the shoulder joints' distance from the
// midline, clear of the armpits), in rows two median edges high from the Spine1 joint up to the
// shoulder joints, where the torso meets the neck and shoulder pieces; reference: the chest
// from the Spine joint to Spine1, one smooth piece by construction. Returns the largest row's
// mean dihedral over the reference's mean: a ring of creased edges lifts one row's mean; a
// smooth surface curving no more there than lower down keeps every row near 1.
struct ChestRing {
  double reference_degrees = 0.0;  // mean dihedral below Spine1
  double worst_row_degrees = 0.0;  // the largest row mean above it
  float worst_row_height = 0.0f;
  double ratio() const { return worst_row_degrees / reference_degrees; }
};

ChestRing chest_ring(const Model& model) {
  const float spine = joint_position(model, "Spine").y, spine1 = joint_position(model, "Spine1").y;
  const glm::vec3 left = joint_position(model, "LeftArm"),
                  right = joint_position(model, "RightArm");
  const float shoulders = 0.5f * (left.y + right.y);
  const float half_width = 0.25f * std::abs(left.x - right.x);
  std::vector<EdgeBend> band;
  for (const EdgeBend& bend : edge_bends(model))
    if (std::abs(bend.midpoint.x) < half_width && bend.midpoint.y >= spine &&
        bend.midpoint.y < shoulders)
      band.push_back(bend);
  std::vector<float> lengths;
  for (const EdgeBend& bend : band) lengths.push_back(bend.length);
  std::nth_element(lengths.begin(), lengths.begin() + lengths.size() / 2, lengths.end());
  const float row = 2.0f * lengths[lengths.size() / 2];
  const int rows = std::max(1, static_cast<int>((shoulders - spine1) / row));
  std::vector<double> sum(rows, 0.0), count(rows, 0.0);
  double reference = 0.0, reference_count = 0.0;
  for (const EdgeBend& bend : band) {
    if (bend.midpoint.y < spine1) {
      reference += bend.degrees;
      ++reference_count;
      continue;
    }
    const int r = std::min(rows - 1, static_cast<int>((bend.midpoint.y - spine1) / row));
    sum[r] += bend.degrees;
    ++count[r];
  }
  ChestRing ring;
  ring.reference_degrees = reference / reference_count;
  for (int r = 0; r < rows; ++r) {
    if (count[r] == 0.0 || sum[r] / count[r] <= ring.worst_row_degrees) continue;
    ring.worst_row_degrees = sum[r] / count[r];
    ring.worst_row_height = spine1 + (static_cast<float>(r) + 0.5f) * row;
  }
  return ring;
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
  // UV seams duplicate some vertices: 17 part charts and the loose triangles (uv_atlas.h), so
  // up to a quarter at 2k, fewer above.
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
  // The 18 tiles (17 parts, loose triangles) are 1/5 wide (5 x 5 atlas): a triangle never
  // stretches across tiles.
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

// The sizes the product offers (sweepd's default model, `sweepctl mannequin`, the benches).
class MannequinProductSizes : public ::testing::TestWithParam<int> {};

// Issue 17: the default mannequin showed a crease ring around the chest at rest in every
// method. The mirrored copy measures the same band (it is symmetric about x = 0).
TEST_P(MannequinProductSizes, HasNoCreaseRingAroundTheChest) {
  const Model& model = mannequin(GetParam());
  for (const Model& body : {model, test_models::mirrored(model)}) {
    const ChestRing ring = chest_ring(body);
    std::printf("%d: chest rows up to %.2f deg mean (at %.3f m), smooth chest %.2f: %.2fx\n",
                GetParam(), ring.worst_row_degrees, ring.worst_row_height, ring.reference_degrees,
                ring.ratio());
    // Tolerance: the smooth mesh's rows reach 1.22x (3k), 1.29x (20k), 1.45x (72k): the dome
    // of the upper chest and the fillets to the neck and shoulders curve up to about twice as
    // much as the lower chest (7.8 against 4.2 per metre across the front); the ring's rows
    // read 1.71x, 3.17x and 3.12x.
    EXPECT_LT(ring.ratio(), 1.6);
  }
}

// Position maps sample every texel from the one triangle that covers it: a chart whose UV
// triangles fold (one turned against the others) or overlap gives a texel two surface points.
TEST_P(MannequinProductSizes, UvChartsNeitherFoldNorOverlap) {
  const Model& model = mannequin(GetParam());
  for (const Model& body : {model, test_models::mirrored(model)}) {
    const UvLayout layout = check_uv_layout(body, 4096);
    std::printf("%d: %zu islands, %zu folded triangles, %zu of %zu samples in two triangles\n",
                GetParam(), layout.islands, layout.folded, layout.overlapping,
                layout.samples_inside);
    EXPECT_EQ(layout.folded, 0u);
    EXPECT_EQ(layout.overlapping, 0u);
  }
}

INSTANTIATE_TEST_SUITE_P(Offered, MannequinProductSizes, ::testing::Values(3000, 20000, 72000));

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
  // Along every edge the weights change by less than 100 per metre (L1 distance of the weight
  // vectors over the edge's length): a hard cut between two bones gives 2 across one edge, 167
  // per metre on 1.2 cm edges; the shortest blend zones (+-2 cm at the finger joints,
  // smoothstep slope 1.5 / 4 cm) give 75 per metre, and where two chains' shares overlap (the
  // back of the neck) 84 was measured. Per metre, not per edge: how long the edge across a
  // finger joint is depends on the tessellation (1.47 cm there gives 1.045).
  float worst = 0.0f, worst_per_metre = 0.0f;
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
      worst_per_metre =
          std::max(worst_per_metre, change / glm::distance(model.positions[a], model.positions[b]));
    }
  }
  EXPECT_LT(worst_per_metre, 100.0f);
  std::printf(
      "  %d elbow-blended vertices, largest weight change along an edge %.3f, %.1f per metre\n",
      blended, worst, worst_per_metre);
}

}  // namespace
}  // namespace sweepd::mannequin
