// A limb's section near a bent elbow and knee (issue 4): sweeps against LBS and DQS on the
// shared male, flexed to 90°, 120°, 135° and 150° (the angle between the links; the male's rest
// pose already flexes its elbows 46°, deform/model/joint_flexion.h).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "tests/deform/posed_section.h"
#include "tests/deform/shared_male.h"

namespace sweepd::deform {
namespace {

struct Sections {
  float whole = 1e9f;    // smallest full-plane section (ellipse fitted to the loop)
  float on_side = 1e9f;  // smallest section on its own link's side of the bisecting plane
};

// Smallest section near a joint: planes orthogonal to each link at half and one `spacing` from
// the joint. Near a strongly bent joint such a plane also cuts the other link through the
// crease (at the elbow flexed 135° the loops measure up to 95 cm² against 52 at rest; at 90° a
// forearm plane reaches the chest), so the figure that counts keeps only the part on the
// link's own side of the joint's bisecting plane, where the two links meet like a mitre.
Sections smallest_sections_near(std::span<const glm::vec3> posed, test::WeldedMesh& welded,
                                glm::vec3 joint, glm::vec3 upper_dir, glm::vec3 lower_dir,
                                float spacing) {
  const glm::vec3 bisector = glm::normalize(upper_dir + lower_dir);
  Sections smallest;
  for (float s : {0.5f, 1.0f}) {
    for (const auto& [point, normal, side] :
         {std::tuple{joint - s * spacing * upper_dir, upper_dir, -bisector},
          std::tuple{joint + s * spacing * lower_dir, lower_dir, bisector}}) {
      smallest.whole = std::min(smallest.whole, welded.section_area(posed, point, normal));
      smallest.on_side = std::min(smallest.on_side,
                                  welded.section_area_on_side(posed, point, normal, joint, side));
    }
  }
  return smallest;
}

TEST(JointSection, SweepKeepsMoreOfTheLimbThanSkinningAtA135DegreeElbowAndKnee) {
  REQUIRE_SHARED_MALE();
  const Model& model = male.model;
  test::Posing deformer(male);
  test::WeldedMesh welded(model);
  struct Case {
    const char* upper;
    const char* joint;
    const char* end;
    glm::vec3 axis;
  };
  // Flexion: the elbow about the axis orthogonal to the upper arm and the front, the knee
  // backwards about the lateral axis.
  for (const Case& c :
       {Case{"LeftArm", "LeftForeArm", "LeftHand", test::left_elbow_flexion_axis(model)},
        Case{"LeftUpLeg", "LeftLeg", "LeftFoot", glm::vec3(1, 0, 0)}}) {
    const int upper = model.skeleton.find(c.upper), joint = model.skeleton.find(c.joint),
              end = model.skeleton.find(c.end);
    const float spacing = 0.12f * glm::distance(test::rest_joint_position(model, c.joint),
                                                test::rest_joint_position(model, c.end));
    for (float degrees : {90.0f, 120.0f, 135.0f, 150.0f}) {
      Pose pose = rest_pose(model.skeleton);
      flex_joint(model.skeleton, pose, joint, c.axis, degrees);
      Sections area[3];
      for (DeformMethod m : {DeformMethod::kSweep, DeformMethod::kLbs, DeformMethod::kDqs}) {
        const auto posed = test::deformed(deformer, pose, m);
        const auto& world = deformer.world_pose();
        const glm::vec3 at = glm::vec3(world[joint][3]);
        const glm::vec3 upper_dir = glm::normalize(at - glm::vec3(world[upper][3]));
        const glm::vec3 lower_dir = glm::normalize(glm::vec3(world[end][3]) - at);
        area[static_cast<int>(m)] =
            smallest_sections_near(posed, welded, at, upper_dir, lower_dir, spacing);
      }
      auto row = [&](const char* what, float Sections::*field) {
        std::printf("%s flexed %3.0f°, %-26s sweep %6.1f  lbs %6.1f  dqs %6.1f cm²\n", c.joint,
                    degrees, what, 1e4f * (area[0].*field), 1e4f * (area[1].*field),
                    1e4f * (area[2].*field));
      };
      row("section on its link's side:", &Sections::on_side);
      row("whole plane (reported):", &Sections::whole);
      if (degrees == 135.0f) {
        // The criterion. Measured: elbow 30.5 vs 20.4 cm², knee 74.2 vs 36.2 (the
        // mitred joint key keeps the outside of the bend; LBS collapses it).
        EXPECT_GT(area[0].on_side, 1.2f * area[1].on_side) << c.joint;
      }
    }
  }
}

}  // namespace
}  // namespace sweepd::deform
