// The throat under the CMU clips' head turns, on the shared male: the largest edge stretch of
// the neck and head over the frames where cmu_01_01 turns the head furthest (88° about the neck
// against the chest at frame 1046, the clip's median being 30° in all) and cmu_01_03's worst
// head frames, with sweeps against LBS; and the neck's key posing that spreads such a twist
// along the neck (deform/posing/key_posing.h).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <glm/gtc/quaternion.hpp>
#include <vector>

#include "deform/model/forward_kinematics.h"
#include "deform/posing/key_posing.h"
#include "io/bvh/bvh_load.h"
#include "motion/retarget.h"
#include "tests/deform/mesh_edges.h"
#include "tests/deform/shared_male.h"

namespace sweepd::deform {
namespace {

namespace fs = std::filesystem;

// Edges whose first vertex weighs most on a neck or head joint (as clip_deformation_test
// assigns regions).
std::vector<test::MeshEdge> throat_and_head_edges(const BoundModel& bound) {
  const std::vector<BodyPart> joint_part = label_joints(bound.rig, bound.model.skeleton);
  std::vector<test::MeshEdge> edges;
  for (const test::MeshEdge& e : test::distinct_edges(bound.model)) {
    const BodyPart part = test::heaviest_part(bound.model, joint_part, e.a);
    if (part == BodyPart::kNeck || part == BodyPart::kHead) edges.push_back(e);
  }
  return edges;
}

struct Worst {
  float stretch = 0.0f;
  int frame = -1;
  test::MeshEdge edge{};
};

TEST(NeckStretch, TheClipsHeadTurnsStretchNoThroatEdgeOverThreeTimes) {
  REQUIRE_SHARED_MALE();
  const fs::path data(SWEEPD_SHARED_DATA);
  test::Posing deformer(male);
  const std::vector<test::MeshEdge> edges = throat_and_head_edges(male);
  ASSERT_GT(edges.size(), 1000u);
  std::vector<glm::vec3> positions(male.model.vertex_count());
  struct Span {
    const char* clip;
    int first, last;
  };
  // cmu_01_01 turns the head 70-99° from frame 1000 to 1100 (3.43x at frame 1046 when the neck
  // handed over to the head by skin weight); cmu_01_03's worst head frames were near 690
  // (2.76x) and are near 955 now.
  for (const Span& span :
       {Span{"motion/cmu_01_01.bvh", 1000, 1100}, Span{"motion/cmu_01_03.bvh", 640, 760},
        Span{"motion/cmu_01_03.bvh", 900, 1000}}) {
    const motion::Retargeter retargeter(io::load_bvh(data / span.clip), male.model);
    Worst sweep, lbs;
    for (int frame = span.first; frame <= span.last; ++frame)
      for (DeformMethod method : {DeformMethod::kSweep, DeformMethod::kLbs}) {
        Pose pose = retargeter.pose_at_frame(frame);
        deformer.deform(pose, method, positions, {});
        Worst& worst = method == DeformMethod::kSweep ? sweep : lbs;
        for (const test::MeshEdge& e : edges) {
          const float stretch = glm::length(positions[e.a] - positions[e.b]) / e.rest_length;
          if (stretch > worst.stretch) worst = {stretch, frame, e};
        }
      }
    std::printf(
        "%s frames %d-%d, neck and head: sweep %.2fx (frame %d, edge %u-%u, rest %.2f mm)"
        " | lbs %.2fx (frame %d, edge %u-%u)\n",
        span.clip, span.first, span.last, sweep.stretch, sweep.frame, sweep.edge.a, sweep.edge.b,
        1e3f * sweep.edge.rest_length, lbs.stretch, lbs.frame, lbs.edge.a, lbs.edge.b);
    // Issue 4's bound on every edge; the sweeps stay under it with the neck's hand-over to the
    // head spread along the surface and its twist spread along the neck (2.68x at frame 1046).
    EXPECT_LE(sweep.stretch, 3.0f) << span.clip;
    // And they tear the throat less than the male's painted weights do (LBS: 3.25x at 1046).
    EXPECT_LT(sweep.stretch, lbs.stretch) << span.clip;
  }
}

TEST(NeckStretch, ATwistAtNeck1SpreadsEvenlyOverTheNecksKeys) {
  REQUIRE_SHARED_MALE();
  const Model& model = male.model;
  const int neck = test::sweep_of(male, BodyPart::kNeck);
  ASSERT_GE(neck, 0);
  const BoundSweep& sweep = male.sweeps[neck];
  // The male's neck: Neck, Neck1, Head with one link key per link (bind's default), so five
  // keys a quarter of the neck's turn apart when the turn spreads evenly.
  ASSERT_EQ(sweep.chain.size(), 3u);
  ASSERT_EQ(sweep.rest_keys.size(), 5u);

  const float degrees = 60.0f;
  const glm::vec3 twist_axis =
      test::rest_joint_position(model, "Head") - test::rest_joint_position(model, "Neck1");
  Pose pose = rest_pose(model.skeleton);
  test::turn(model, pose, "Neck1", twist_axis, degrees);
  const std::vector<glm::mat4> rest = model.skeleton.world_rest_matrices();
  std::vector<glm::mat4> world(rest.size());
  forward_kinematics(model.skeleton, pose, world);
  std::vector<glm::quat> joint_rotation(rest.size());
  std::vector<glm::vec3> rest_joint(rest.size()), pose_joint(rest.size());
  for (std::size_t j = 0; j < rest.size(); ++j) {
    joint_rotation[j] = glm::normalize(glm::quat_cast(glm::mat3(world[j])) *
                                       glm::inverse(glm::quat_cast(glm::mat3(rest[j]))));
    rest_joint[j] = glm::vec3(rest[j][3]);
    pose_joint[j] = glm::vec3(world[j][3]);
  }
  std::vector<KeyEllipse> keys(sweep.rest_keys.size());
  pose_key_ellipses(sweep, mitre_spread(sweep), model.skeleton, joint_rotation, rest_joint,
                    pose_joint, keys);

  for (std::size_t k = 0; k < keys.size(); ++k) {
    const glm::quat turn = keys[k].orientation * glm::inverse(sweep.rest_keys[k].orientation);
    const float turned = glm::degrees(2.0f * std::acos(std::min(1.0f, std::abs(turn.w))));
    std::printf("neck key %zu turns %.3f degrees\n", k, turned);
    // Key k turns k/4 of the 60°: the joint keys halfway between their links (0°, 30°, 60°),
    // the link keys in between (15°, 45°; a link key rigid with its link would turn 0° or 60°).
    // 0.01°: float rounding of the quaternion products.
    EXPECT_NEAR(turned, degrees * static_cast<float>(k) / 4.0f, 0.01f) << "key " << k;
  }
}

}  // namespace
}  // namespace sweepd::deform
