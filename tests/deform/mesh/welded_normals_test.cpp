// WeldedNormals: seam copies share the welded normal, area weighting, the fallback for vertices
// outside every triangle, bad indices and buffer sizes refused, agreement with a direct
// per-triangle sum on the shared male, bit-identical for any thread count, and within 0.001° of
// a double-precision sum on the male and the 72k mannequin at range-of-motion peaks.
#include "deform/mesh/welded_normals.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <vector>

#include "deform/mesh/mesh_topology.h"
#include "mannequin/mannequin.h"
#include "motion/own_skeleton_clip.h"
#include "motion/range_of_motion.h"
#include "tests/deform/shared_male.h"

namespace sweepd::deform {
namespace {

// A regular octahedron (vertices on the axes) whose +x vertex has a seam copy (vertex 6) used by
// the two triangles on the -z side, and an unused vertex 7.
struct Octahedron {
  std::vector<glm::vec3> positions = {{1, 0, 0}, {0, 1, 0},  {-1, 0, 0}, {0, -1, 0},
                                      {0, 0, 1}, {0, 0, -1}, {1, 0, 0},  {5, 5, 5}};
  std::vector<std::uint32_t> indices = {0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4,   // +z side
                                        6, 5, 1, 1, 5, 2, 2, 5, 3, 3, 5, 6};  // -z side
};

TEST(WeldedNormals, SeamCopiesShareTheNormalOfAllTheirTriangles) {
  Octahedron mesh;
  WeldedNormals normals(mesh.positions, mesh.indices);
  std::vector<FloatLanes> sums;
  std::vector<glm::vec3> out(mesh.positions.size());
  normals.compute(mesh.positions, out, sums);
  // By symmetry each octahedron vertex's four triangles sum to its own direction; the +x vertex
  // and its copy each see only two of them unwelded (they would tilt by 45° towards ±z).
  for (std::size_t v = 0; v < 7; ++v)
    EXPECT_LE(glm::length(out[v] - glm::normalize(mesh.positions[v])), 1e-6f)  // float rounding
        << "vertex " << v;
  EXPECT_EQ(out[7], glm::vec3(0, 1, 0));  // in no triangle: the documented fallback
}

TEST(WeldedNormals, WeighsTrianglesByArea) {
  // A fan around vertex 0: a big triangle in the z = 0 plane and a small one in the x = 0 plane.
  const std::vector<glm::vec3> positions = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0, 0, 0.5f}};
  const std::vector<std::uint32_t> indices = {0, 1, 2, 0, 2, 3};
  WeldedNormals normals(positions, indices);
  std::vector<FloatLanes> sums;
  std::vector<glm::vec3> out(positions.size());
  normals.compute(positions, out, sums);
  // Cross products: (0, 0, 4) and (1, 0, 0): the sum's direction, not the mean of unit normals.
  EXPECT_LE(glm::length(out[0] - glm::normalize(glm::vec3(1, 0, 4))), 1e-6f);  // float rounding
}

TEST(WeldedNormals, RefusesBadIndicesAndBuffers) {
  Octahedron mesh;
  WeldedNormals normals(mesh.positions, mesh.indices);
  std::vector<FloatLanes> sums;
  std::vector<glm::vec3> short_buffer(3), out(mesh.positions.size());
  EXPECT_THROW(normals.compute(short_buffer, out, sums), std::invalid_argument);
  EXPECT_THROW(normals.compute(mesh.positions, short_buffer, sums), std::invalid_argument);
  mesh.indices.push_back(0);
  EXPECT_THROW(WeldedNormals(mesh.positions, mesh.indices), std::invalid_argument);
  mesh.indices.insert(mesh.indices.end(), {1, 8});
  EXPECT_THROW(WeldedNormals(mesh.positions, mesh.indices), std::invalid_argument);
}

TEST(WeldedNormals, MatchesADirectSumOnThePosedMale) {
  REQUIRE_SHARED_MALE();
  const Model& model = male.model;
  test::Posing deformer(male);
  Pose pose = rest_pose(model.skeleton);
  test::turn(model, pose, "LeftForeArm", {0, 0, 1}, 100.0f);
  std::vector<glm::vec3> posed(model.vertex_count()), fast(model.vertex_count());
  deformer.deform(pose, DeformMethod::kLbs, posed, {});
  std::vector<FloatLanes> scratch;
  const WeldedNormals welded(model.positions, model.indices);
  welded.compute(posed, fast, scratch);
  // Split over threads: every vertex adds the same triangles in the same order.
  for (const int threads : {2, 3, 7}) {
    std::vector<glm::vec3> split(model.vertex_count());
    welded.compute(posed, split, scratch, threads);
    EXPECT_EQ(0, std::memcmp(fast.data(), split.data(), fast.size() * sizeof(glm::vec3)))
        << threads << " threads";
  }
  // Direct: every triangle's cross product added to its corners, then seam copies (coincident
  // rest positions) summed by a search over all vertices with the same rest position.
  std::vector<glm::vec3> sums(model.vertex_count(), glm::vec3(0.0f));
  for (std::size_t t = 0; t + 2 < model.indices.size(); t += 3) {
    const glm::vec3 a = posed[model.indices[t]];
    const glm::vec3 n =
        glm::cross(posed[model.indices[t + 1]] - a, posed[model.indices[t + 2]] - a);
    for (int k = 0; k < 3; ++k) sums[model.indices[t + k]] += n;
  }
  std::vector<std::size_t> order(model.vertex_count());
  for (std::size_t v = 0; v < order.size(); ++v) order[v] = v;
  const auto before = [&](std::size_t i, std::size_t j) {
    const glm::vec3 &p = model.positions[i], &q = model.positions[j];
    return p.x != q.x ? p.x < q.x : p.y != q.y ? p.y < q.y : p.z < q.z;
  };
  std::sort(order.begin(), order.end(), before);
  float worst = 0.0f;
  for (std::size_t first = 0; first < order.size();) {
    std::size_t last = first;
    glm::vec3 sum(0.0f);
    while (last < order.size() && model.positions[order[last]] == model.positions[order[first]])
      sum += sums[order[last++]];
    const glm::vec3 expected = glm::length(sum) > 0.0f ? glm::normalize(sum) : glm::vec3(0, 1, 0);
    for (std::size_t i = first; i < last; ++i)
      worst = std::max(worst, glm::length(fast[order[i]] - expected));
    first = last;
  }
  // Float sums in another order; unit vectors: rounding stays far below 1e-4.
  EXPECT_LE(worst, 1e-4f);
}

// Unit normals summed in double from the float positions: each triangle's cross product added to
// its welded corners (coincident rest positions), (0, 1, 0) where the sum is zero.
std::vector<glm::dvec3> double_precision_normals(const Model& model,
                                                 std::span<const glm::vec3> posed) {
  std::size_t welded_count = 0;
  const std::vector<std::uint32_t> welded =
      weld_coincident_positions(model.positions, &welded_count);
  std::vector<glm::dvec3> sums(welded_count, glm::dvec3(0.0));
  for (std::size_t t = 0; t + 2 < model.indices.size(); t += 3) {
    const glm::dvec3 a(posed[model.indices[t]]);
    const glm::dvec3 n = glm::cross(glm::dvec3(posed[model.indices[t + 1]]) - a,
                                    glm::dvec3(posed[model.indices[t + 2]]) - a);
    for (int k = 0; k < 3; ++k) sums[welded[model.indices[t + k]]] += n;
  }
  std::vector<glm::dvec3> normals(posed.size());
  for (std::size_t v = 0; v < posed.size(); ++v) {
    const glm::dvec3& sum = sums[welded[v]];
    normals[v] = glm::length(sum) > 0.0 ? glm::normalize(sum) : glm::dvec3(0, 1, 0);
  }
  return normals;
}

// Degrees between two unit vectors (2 asin(|a − b| / 2): exact for small angles, where acos of
// the dot product loses them).
double degrees_between(const glm::dvec3& a, const glm::dvec3& b) {
  return glm::degrees(2.0 * std::asin(std::min(1.0, glm::length(a - b) / 2.0)));
}

// At three range-of-motion peaks of the sweep: the normals within 0.001° of the double-precision sum (float rounding only: measured 0.00001° to
// 0.0001°, so a wrong triangle or a lost seam copy, degrees off, fails), and bit-identical for 1,
// 2, 3 and 7 threads.
void expect_within_a_thousandth_of_a_degree(const BoundModel& bound) {
  const Model& model = bound.model;
  const motion::RangeOfMotion rom = motion::range_of_motion(model.skeleton, bound.rig);
  const motion::OwnSkeletonClip player(rom.clip, model.skeleton);
  test::Posing posing(bound);
  int peaks = 0;
  for (const motion::RomMove& move : rom.moves) {
    if (move.name != "elbow flexion 150°" && move.name != "left knee to chest" &&
        move.name != "deep squat")
      continue;
    SCOPED_TRACE(move.name);
    ++peaks;
    const std::vector<glm::vec3> posed =
        test::deformed(posing, player.pose_at_frame(move.peak_frame), DeformMethod::kSweep);
    const std::vector<glm::dvec3> expected = double_precision_normals(model, posed);
    const WeldedNormals welded(model.positions, model.indices);
    std::vector<FloatLanes> scratch;
    std::vector<glm::vec3> one(posed.size());
    welded.compute(posed, one, scratch);
    double worst = 0.0;
    for (std::size_t v = 0; v < posed.size(); ++v)
      worst = std::max(worst, degrees_between(glm::dvec3(one[v]), expected[v]));
    EXPECT_LE(worst, 0.001);
    for (const int threads : {2, 3, 7}) {
      std::vector<glm::vec3> split(posed.size());
      welded.compute(posed, split, scratch, threads);
      EXPECT_EQ(0, std::memcmp(one.data(), split.data(), one.size() * sizeof(glm::vec3)))
          << threads << " threads";
    }
  }
  EXPECT_EQ(peaks, 3);  // every named move is in the range of motion
}

TEST(WeldedNormals, IsWithinAThousandthOfADegreeOnTheMale) {
  REQUIRE_SHARED_MALE();
  expect_within_a_thousandth_of_a_degree(male);
}

TEST(WeldedNormals, IsWithinAThousandthOfADegreeOnThe72kMannequin) {
  const Model model = mannequin::make_mannequin({.target_vertices = 72000});
  const BoundModel bound = bind(model, detect_rig_map(model.skeleton));
  expect_within_a_thousandth_of_a_degree(bound);
}

}  // namespace
}  // namespace sweepd::deform
