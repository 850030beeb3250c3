// Where the sweep runs backwards through itself (metrics/sweep_plane_crossing.h; issue 47).
// The forward speed against a bend of known radius, that no shared body's rest binding has a
// crossed plane, and the cause of the flips the corpus gate counts, measured on the heavy male.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "deform/binding/bind.h"
#include "io/bvh/bvh_load.h"
#include "io/gltf/gltf_load.h"
#include "mannequin/mannequin.h"
#include "metrics/region_quality.h"
#include "metrics/sweep_plane_crossing.h"
#include "motion/retarget.h"
#include "selfcheck/binding_self_check.h"
#include "tests/deform/shared_male.h"

namespace sweepd::metrics {
namespace {

namespace fs = std::filesystem;
using deform::DeformMethod;

// A sweep along a quarter circle of radius `radius` in the x-y plane, its planes orthogonal to
// the circle, its ellipses' x axes towards the circle's centre.
deform::Sweep quarter_circle(float radius) {
  std::vector<deform::KeyEllipse> keys;
  constexpr int kKeys = 17;
  for (int k = 0; k < kKeys; ++k) {
    const float phi = 0.5f * 3.14159265f * static_cast<float>(k) / (kKeys - 1);
    const glm::vec3 inward(-std::cos(phi), -std::sin(phi), 0.0f);
    const glm::vec3 along(-std::sin(phi), std::cos(phi), 0.0f);
    const glm::vec3 up = glm::cross(along, inward);
    deform::KeyEllipse key;
    key.centre = -radius * inward;
    key.orientation = glm::normalize(glm::quat_cast(glm::mat3(inward, up, along)));
    key.a = key.b = 0.05f;
    keys.push_back(key);
  }
  return deform::Sweep(keys);
}

// A point of the quarter circle's middle plane, `distance` from the centre line towards the
// circle's centre (theta 0) or away from it (theta pi).
deform::SweepCoordinate point_at(float distance, float theta) {
  deform::SweepCoordinate c;
  c.t = 0.5f;
  c.theta = theta;
  c.da = distance - 0.05f;
  c.db = distance - 0.05f;
  return c;
}

// On a bend of radius r, a point d towards its inside moves at (1 - d / r) of the centre's speed
// and d towards its outside at (1 + d / r): the sweep reverses past d = r. Within 2 % of the
// centre's speed: the spline and the piecewise-linear frames only approximate the circle.
TEST(SweepPlaneCrossing, ForwardSpeedFallsAsTheDistanceInsideABendNearsItsRadius) {
  constexpr float kRadius = 0.2f;
  const deform::Sweep sweep = quarter_circle(kRadius);
  const double centre = forward_speed(sweep, point_at(0.0f, 0.0f));
  EXPECT_NEAR(centre, 0.5 * 3.14159265 * kRadius, 0.02 * centre) << "the arc's length per unit t";
  for (const float fraction : {0.25f, 0.5f, 0.9f, 1.1f, 1.5f}) {
    const double inside = forward_speed(sweep, point_at(fraction * kRadius, 0.0f));
    const double outside = forward_speed(sweep, point_at(fraction * kRadius, 3.14159265f));
    std::printf("d = %.2f r: inside %.3f, outside %.3f of the centre's speed\n", fraction,
                inside / centre, outside / centre);
    EXPECT_NEAR(inside / centre, 1.0 - fraction, 0.02) << fraction;
    EXPECT_NEAR(outside / centre, 1.0 + fraction, 0.02) << fraction;
  }
}

// Every shared body as the corpus gate binds it: no bound point has a crossed plane at rest
// (f_rest > 0), so f_pose / f_rest is a measure of each point's compression, and the posed sweep
// reproduces the rest ratios (1) at the rest pose.
TEST(SweepPlaneCrossing, NoSharedBodyIsBoundAcrossCrossedPlanes) {
  const fs::path data(SWEEPD_SHARED_DATA);
  std::vector<std::pair<std::string, deform::Model>> bodies;
  bodies.push_back({"mannequin", mannequin::make_mannequin({})});
  for (const char* file :
       {"models/makehuman_male_cmu.glb", "models/RiggedFigure/RiggedFigure.gltf",
        "models/corpus/makehuman_child_mixamo_unity.glb",
        "models/corpus/makehuman_female_old_heavy_mixamo.glb",
        "models/corpus/makehuman_female_slim_openpose.glb",
        "models/corpus/makehuman_male_old_heavy_unreal.glb"})
    if (fs::exists(data / file)) bodies.push_back({file, io::load_gltf(data / file)});
  for (const auto& [name, model] : bodies) {
    const deform::BoundModel bound =
        selfcheck::bind_checked(model, deform::detect_rig_map(model.skeleton), {}, true).bound;
    const PlaneCrossingMeter meter(bound);
    const deform::SweepPoser rest(bound);
    double least_ratio = 1.0, most_ratio = 1.0;
    for (const double r : meter.speed_ratios(rest)) {
      least_ratio = std::min(least_ratio, r);
      most_ratio = std::max(most_ratio, r);
    }
    std::printf("%-52s least rest speed %.4f m per unit t; rest ratios %.6f-%.6f\n",
                name.c_str(), meter.least_rest_speed(), least_ratio, most_ratio);
    EXPECT_GT(meter.least_rest_speed(), 0.0) << name;
    // The poser rebuilds its sweeps from keys posed at the rest pose (float forward kinematics,
    // the torso's centres laid along the column): the same speeds within 2e-3 (measured 1.5e-3
    // at most, on the child).
    EXPECT_NEAR(least_ratio, 1.0, 2e-3) << name;
    EXPECT_NEAR(most_ratio, 1.0, 2e-3) << name;
  }
}

// The cause of the flips the gate counts, measured where they are densest: the heavy male on
// cmu_01_03 frames 400-3100 (hip and spine flexion), every 100th. Of the triangles the sweep
// method flips and neither LBS nor DQS does, measured 79 % (1,198 of 1,508) had a vertex where
// the sweep runs backwards (f_pose / f_rest < 0) and 91 % (1,366) one below 0.4. The plane turn
// limit (deform/posing/plane_turn_limit.h) then took the excess turn of the spans whose planes
// crossed in the skin into the spans beside them: 1,223 such flips, 70 % (861) still with a
// vertex running backwards and 89 % (1,085) below 0.4, as the poser evaluates the sweep (its
// frames turned). They remain where the whole sweep has too little room for the bend: the heavy
// male's torso sweep (pelvis to spine_03) is 18 cm of centre line that cmu_01_03 frame 1100
// bends 77° while its belly reaches 16-20 cm in front of it, so it may turn 53° without a
// crossing. Asserted: at most 915 such flips (3 % over the measurement: another CPU's
// rounding, not the limit undone) and at least 60 % and 80 % of them at a vertex that runs
// backwards or below 0.4 (the same cause), and every frame's count printed.
TEST(SweepPlaneCrossing, TheFlipsSkinningDoesNotHaveAreWhereTheSweepRunsBackwards) {
  const fs::path data(SWEEPD_SHARED_DATA);
  const fs::path file = data / "models/corpus/makehuman_male_old_heavy_unreal.glb";
  if (!fs::exists(file) || !fs::exists(data / "motion/cmu_01_03.bvh"))
    GTEST_SKIP() << "shared data absent";
  const deform::Model model = io::load_gltf(file);
  const deform::BoundModel bound =
      selfcheck::bind_checked(model, deform::detect_rig_map(model.skeleton), {}, true).bound;
  const motion::Retargeter clip(io::load_bvh(data / "motion/cmu_01_03.bvh"), model);
  deform::test::Posing posing(bound);
  const PlaneCrossingMeter meter(bound);
  const RegionLabels labels = label_regions(bound);
  const auto& indices = model.indices;
  const std::size_t triangles = indices.size() / 3;
  const std::vector<glm::mat4> world_rest = model.skeleton.world_rest_matrices();
  int extra = 0, reversed = 0, crowded = 0;
  for (int frame = 400; frame <= 3100 && frame < clip.frame_count(); frame += 100) {
    deform::Pose pose = clip.pose_at_frame(frame);
    std::vector<glm::vec3> positions[3];
    for (int m = 2; m >= 0; --m) {  // the sweep last: its poser then holds this pose
      positions[m].resize(model.vertex_count());
      posing.deform(pose, static_cast<DeformMethod>(m), positions[m]);
    }
    const std::vector<double> ratio = meter.speed_ratios(posing.sweep_poser());
    const auto world = posing.world_pose();
    std::vector<glm::mat3> joint_turn(world.size());
    for (std::size_t j = 0; j < world.size(); ++j)
      joint_turn[j] = glm::mat3(world[j] * glm::inverse(world_rest[j]));
    int frame_extra = 0, frame_reversed = 0;
    for (std::size_t t = 0; t < triangles; ++t) {
      const std::uint32_t v[3] = {indices[3 * t], indices[3 * t + 1], indices[3 * t + 2]};
      if (bound.vertices[v[0]].skin_weight >= 1.0f && bound.vertices[v[1]].skin_weight >= 1.0f &&
          bound.vertices[v[2]].skin_weight >= 1.0f)
        continue;  // not swept
      // RegionMeter's rule: the normal against the rest normal turned by each corner's
      // strongest joint.
      const int corner_joint[3] = {labels.strongest_joint[v[0]], labels.strongest_joint[v[1]],
                                   labels.strongest_joint[v[2]]};
      const glm::vec3 rest_normal = triangle_normal(model.positions, indices, t);
      auto flipped = [&](int m) {
        return flipped_from_rest(triangle_normal(positions[m], indices, t), rest_normal, joint_turn,
                                 corner_joint);
      };
      if (!flipped(0) || flipped(1) || flipped(2)) continue;
      const double least = std::min({ratio[v[0]], ratio[v[1]], ratio[v[2]]});
      ++frame_extra;
      frame_reversed += least < 0.0;
      crowded += least < 0.4;
    }
    std::printf("frame %4d: %3d flips skinning does not have, %3d where the sweep runs backwards\n",
                frame, frame_extra, frame_reversed);
    extra += frame_extra;
    reversed += frame_reversed;
  }
  std::printf("in all %d; with a vertex below 0 of its rest speed %d (%.0f %%), below 0.4 %d "
              "(%.0f %%)\n",
              extra, reversed, 100.0 * reversed / extra, crowded, 100.0 * crowded / extra);
  ASSERT_GT(extra, 0);
  // 1,508 before the plane turn limit, 1,223 with it, 1,023 with one link key per link, 974
  // judged against each corner's joint (metrics::flipped_from_rest), 888 with the torso's first
  // key turned with the pelvis, not halfway to the root above it (deform/posing/key_posing.h).
  EXPECT_LE(extra, 915);
  EXPECT_GE(reversed, 0.60 * extra);
  EXPECT_GE(crowded, 0.80 * extra);
}

}  // namespace
}  // namespace sweepd::metrics
