// Key-ellipse edits (paper §4.2): the correction spline (zero at rest, exact at the edited
// angles, monotone between them, held beyond), validation messages, and on the shared male an
// orientation edit made at 120° shoulder abduction: fully applied at 120°, absent at rest and
// changing by a bounded amount per 1° in between.
#include "deform/edits/angle_driven_key_edits.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "tests/deform/shared_male.h"

namespace sweepd::deform {
namespace {

KeyEllipseEdit edit_with(std::initializer_list<std::pair<float, float>> angle_and_degrees) {
  KeyEllipseEdit edit;
  edit.sweep = 0, edit.key = 0, edit.joint = 0;
  for (const auto& [angle, degrees] : angle_and_degrees) {
    KeyEllipseEditSample sample;
    sample.angle_degrees = angle;
    sample.correction.rotation = {0.0f, 0.0f, degrees};
    sample.correction.scale_a = 1.0f + degrees / 100.0f;
    edit.samples.push_back(sample);
  }
  return edit;
}

TEST(KeyEllipseEdits, SplineIsZeroAtRestExactAtSamplesHeldBeyondAndNeverOvershoots) {
  const KeyEllipseEdit edit = edit_with({{40.0f, 10.0f}, {90.0f, 30.0f}, {120.0f, 30.0f}});
  EXPECT_EQ(correction_at(edit, 0.0f).rotation.z, 0.0f);
  EXPECT_EQ(correction_at(edit, 0.0f).scale_a, 1.0f);
  // At the knots the Hermite basis is exact to float rounding.
  EXPECT_NEAR(correction_at(edit, 40.0f).rotation.z, 10.0f, 1e-5f);
  EXPECT_NEAR(correction_at(edit, 90.0f).rotation.z, 30.0f, 1e-5f);
  EXPECT_NEAR(correction_at(edit, 90.0f).scale_a, 1.3f, 1e-6f);
  EXPECT_EQ(correction_at(edit, 170.0f).rotation.z, 30.0f);
  float previous = 0.0f;
  for (float angle = 0.0f; angle <= 130.0f; angle += 0.5f) {
    const float value = correction_at(edit, angle).rotation.z;
    EXPECT_GE(value, previous - 1e-5f) << angle;  // monotone data, monotone spline
    EXPECT_LE(value, 30.0f + 1e-5f) << angle;     // no overshoot on the flat last span
    previous = value;
  }
}

TEST(KeyEllipseEdits, ValidateNamesWhatIsWrong) {
  REQUIRE_SHARED_MALE();
  auto message = [&](KeyEllipseEdit edit) {
    KeyEllipseEdits edits{{edit}};
    return validate(edits, male);
  };
  KeyEllipseEdit good = edit_with({{120.0f, 30.0f}, {60.0f, 10.0f}});
  KeyEllipseEdits sorted{{good}};
  EXPECT_EQ(validate(sorted, male), "");
  EXPECT_EQ(sorted.edits[0].samples[0].angle_degrees, 60.0f);  // sorted by angle
  KeyEllipseEdit bad = good;
  bad.sweep = 99;
  EXPECT_NE(message(bad).find("sweep 99 out of range"), std::string::npos) << message(bad);
  bad = good, bad.key = -1;
  EXPECT_NE(message(bad).find("key -1"), std::string::npos) << message(bad);
  bad = good, bad.joint = 1000;
  EXPECT_NE(message(bad).find("joint 1000"), std::string::npos) << message(bad);
  bad = edit_with({{0.0f, 5.0f}});
  EXPECT_NE(message(bad).find("must be positive"), std::string::npos) << message(bad);
  bad = edit_with({{50.0f, 5.0f}, {50.0f, 6.0f}});
  EXPECT_NE(message(bad).find("two samples"), std::string::npos) << message(bad);
  bad = edit_with({{50.0f, -100.0f}});
  EXPECT_NE(message(bad).find("scales must be positive"), std::string::npos) << message(bad);
  bad = good, bad.sweep = 99;
  BoundModel with_bad_edits = male;
  with_bad_edits.edits = KeyEllipseEdits{{bad}};
  EXPECT_THROW(ModelRuntime{with_bad_edits}, std::invalid_argument);  // checked once, at load
}

// Angle between two unit quaternions, in degrees.
float degrees_between(const glm::quat& p, const glm::quat& q) {
  return glm::degrees(2.0f * std::acos(std::min(1.0f, std::abs(glm::dot(p, q)))));
}

TEST(KeyEllipseEdits, OrientationEditAt120DegreesShoulderAbductionFadesInSmoothly) {
  REQUIRE_SHARED_MALE();
  const Model& model = male.model;
  const int arm = test::sweep_of(male, BodyPart::kLeftArm);
  const int shoulder = male.rig.left_arm.upper;
  int key = -1;  // the arm sweep's joint key at the shoulder
  for (std::size_t k = 0; k < male.sweeps[arm].anchors.size(); ++k)
    if (male.sweeps[arm].anchors[k].joint == shoulder && male.sweeps[arm].anchors[k].is_joint_key())
      key = static_cast<int>(k);
  ASSERT_GE(key, 0);
  constexpr float kEdited = 30.0f;  // degrees about the key's normal, made at 120° abduction
  KeyEllipseEdit edit;
  edit.sweep = arm, edit.key = key, edit.joint = shoulder;
  edit.samples.push_back({120.0f, {{0, 0, 0}, {0, 0, kEdited}, 1.0f, 1.0f}});
  BoundModel with_edit = male;
  with_edit.edits = KeyEllipseEdits{{edit}};
  test::Posing plain(male), edited(with_edit);
  // Abduction: the left arm (on +X, 45° down at rest) rises about the model's front axis +Z.
  auto applied_at = [&](float degrees) {
    Pose pose = rest_pose(model.skeleton);
    test::turn(model, pose, "LeftArm", {0, 0, 1}, degrees);
    test::deformed(plain, pose, DeformMethod::kSweep);
    test::deformed(edited, pose, DeformMethod::kSweep);
    return degrees_between(plain.sweep_poser().posed_keys(arm)[key].orientation,
                           edited.sweep_poser().posed_keys(arm)[key].orientation);
  };
  EXPECT_EQ(applied_at(0.0f), 0.0f);                // absent at rest, exactly
  EXPECT_NEAR(applied_at(120.0f), kEdited, 0.05f);  // acos near 1 costs ~0.03° of float precision
  float previous = 0.0f, largest_step = 0.0f;
  for (int degrees = 1; degrees <= 120; ++degrees) {
    const float now = applied_at(static_cast<float>(degrees));
    largest_step = std::max(largest_step, std::abs(now - previous));
    previous = now;
  }
  std::printf(
      "orientation edit of %.0f deg at 120 deg abduction: largest change per 1 deg %.3f deg\n",
      kEdited, largest_step);
  // The stated bound: 1.5 × edit / angle = 0.375° per 1°, plus the float slack above.
  EXPECT_LE(largest_step, 1.5f * kEdited / 120.0f + 0.05f);
}

}  // namespace
}  // namespace sweepd::deform
