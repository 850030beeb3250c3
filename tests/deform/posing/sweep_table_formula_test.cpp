// The sweep's vertex loops (SweepVertexKinds: batched terms, junction kinds, SSE2 and AVX2)
// against the formula they evaluate, written out in double from the same per-frame sample table:
// per vertex its skinned share Σ_j s w_j M_j (p, 1) plus, per sweep term, w ((1 - f) at(row) +
// f at(row + 1)), at(r) = C_r + x X_r + y Y_r + c N_r with x = (a_r + f a_step_r + da) cos θ and y
// likewise. The loops may only reorder the float operations, so they stay within 1e-6 × height
// of it (float rounding at 1-2 m from the origin is ~1e-7 m per operation, about twenty
// operations a term) on the shared male and the 72k mannequin, at CMU and range-of-motion poses.
// Unlike the direct evaluation (sweep_poser_test.cpp, 1e-5 × height: R interpolated between
// samples), this bound holds any change of the loops to rounding.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "deform/binding/bind.h"
#include "deform/model/forward_kinematics.h"
#include "deform/posing/sweep_poser.h"
#include "deform/rig/rig_map.h"
#include "io/bvh/bvh_load.h"
#include "mannequin/mannequin.h"
#include "motion/own_skeleton_clip.h"
#include "motion/range_of_motion.h"
#include "motion/retarget.h"
#include "tests/deform/shared_male.h"

namespace sweepd::deform {
namespace {

namespace fs = std::filesystem;

float height(const Model& model) {
  const auto [lo, hi] = std::minmax_element(model.positions.begin(), model.positions.end(),
                                            [](glm::vec3 a, glm::vec3 b) { return a.y < b.y; });
  return hi->y - lo->y;
}

glm::dvec3 row_point(const SweepSample& row, double x, double y, double c) {
  return glm::dvec3(row.centre) + x * glm::dvec3(row.x_axis) + y * glm::dvec3(row.y_axis) +
         c * glm::dvec3(row.normal);
}

// The formula of sweep_vertex_kinds.h in double, from the poser's table.
glm::dvec3 table_formula(const SweepPoser& poser, const BoundModel& bound,
                         std::span<const glm::mat4> skinning, std::size_t v) {
  const VertexBinding& vb = bound.vertices[v];
  glm::dvec3 p(0.0);
  if (vb.skin_weight > 0.0f)
    for (int j = 0; j < kInfluences; ++j) {
      const float w = skinned_share_weights(bound)[v][j];
      if (w <= 0.0f) continue;
      const glm::dmat4 m(skinning[skinned_share_joints(bound)[v][j]]);
      p += double(vb.skin_weight) * w *
           glm::dvec3(m * glm::dvec4(glm::dvec3(bound.model.positions[v]), 1.0));
    }
  const std::span<const SweepSample> table = poser.sample_table();
  for (int k = 0; k < kSweepsPerVertex; ++k) {
    if (vb.sweep[k] < 0 || vb.weight[k] == 0.0f) continue;
    const SweepCoordinate& c = vb.coordinate[k];
    const SampleRowOf at = sample_row_of(poser.tables(), vb.sweep[k], c.t);
    const SweepSample& below = table[at.row];
    const double f = at.fraction;
    const double x = (below.a + f * below.a_step + c.da) * std::cos(double(c.theta));
    const double y = (below.b + f * below.b_step + c.db) * std::sin(double(c.theta));
    p += double(vb.weight[k]) *
         ((1.0 - f) * row_point(below, x, y, c.c) + f * row_point(table[at.row + 1], x, y, c.c));
  }
  return p;
}

void expect_loops_follow_the_formula(const BoundModel& bound, const std::vector<Pose>& poses,
                                     const std::string& name) {
  const Model& model = bound.model;
  std::vector<VertexLoopInstructions> sets = {VertexLoopInstructions::kBaseline};
  if (widest_vertex_loop_instructions() != VertexLoopInstructions::kBaseline)
    sets.push_back(widest_vertex_loop_instructions());
  std::vector<glm::mat4> world(model.skeleton.joints.size()), skinning(world.size());
  const std::vector<glm::mat4> rest_inverse = world_rest_inverse_matrices(model.skeleton);
  std::vector<glm::vec3> positions(model.vertex_count());
  for (const VertexLoopInstructions set : sets) {
    SweepPoser poser(bound, set);
    double worst = 0.0;
    for (const Pose& pose : poses) {
      forward_kinematics(model.skeleton, pose, world);
      skinning_matrices(world, rest_inverse, skinning);
      poser.set_pose(world);
      poser.deform(skinning, positions, {}, 2);
      for (std::size_t v = 0; v < model.vertex_count(); ++v)
        worst = std::max(worst, glm::length(glm::dvec3(positions[v]) -
                                            table_formula(poser, bound, skinning, v)));
    }
    std::printf("%s, instruction set %d, %zu poses: worst %.3g m from the table formula\n",
                name.c_str(), static_cast<int>(set), poses.size(), worst);
    EXPECT_LE(worst, 1e-6 * height(model)) << name << ", instruction set " << static_cast<int>(set);
  }
}

// A few frames of each CMU clip (walk and turns, a high knee) and the range of motion's peaks.
std::vector<Pose> clip_and_range_of_motion_poses(const BoundModel& bound) {
  std::vector<Pose> poses;
  const fs::path data(SWEEPD_SHARED_DATA);
  for (const auto& [clip, frames] :
       {std::pair<std::string, std::vector<int>>{"motion/cmu_01_01.bvh", {300, 1257, 2000}},
        std::pair<std::string, std::vector<int>>{"motion/cmu_01_03.bvh", {1100, 3249}}}) {
    const motion::Retargeter retargeter(io::load_bvh(data / clip), bound.model);
    for (const int frame : frames) poses.push_back(retargeter.pose_at_frame(frame));
  }
  const motion::RangeOfMotion rom = motion::range_of_motion(bound.model.skeleton, bound.rig);
  const motion::OwnSkeletonClip player(rom.clip, bound.model.skeleton);
  for (std::size_t m = 0; m < rom.moves.size(); m += 4)
    poses.push_back(player.pose_at_frame(rom.moves[m].peak_frame));
  return poses;
}

TEST(SweepTableFormula, LoopsFollowTheFormulaOnTheMaleWithinRounding) {
  REQUIRE_SHARED_MALE();
  if (!fs::exists(fs::path(SWEEPD_SHARED_DATA) / "motion/cmu_01_01.bvh"))
    GTEST_SKIP() << "shared data absent: the CMU clips";
  expect_loops_follow_the_formula(male, clip_and_range_of_motion_poses(male), "male");
}

TEST(SweepTableFormula, LoopsFollowTheFormulaOnThe72kMannequinWithinRounding) {
  if (!fs::exists(fs::path(SWEEPD_SHARED_DATA) / "motion/cmu_01_01.bvh"))
    GTEST_SKIP() << "shared data absent: the CMU clips";
  const Model model = mannequin::make_mannequin({.target_vertices = 72000});
  const BoundModel bound = bind(model, detect_rig_map(model.skeleton));
  expect_loops_follow_the_formula(bound, clip_and_range_of_motion_poses(bound), "mannequin 72k");
}

}  // namespace
}  // namespace sweepd::deform
