// Tests of BodyShape: one part's field, the smooth union of two, and the part coordinates.
#include "mannequin/body_shape.h"

#include <gtest/gtest.h>

#include <vector>

namespace sweepd::mannequin {

namespace {

// A 40 cm vertical part, 10 cm wide (side, X) and 6 cm deep (Z), with 5 cm round caps.
BodyPart upright_part() {
  BodyPart part;
  part.name = "upright";
  part.start = {0.0f, 0.0f, 0.0f};
  part.end = {0.0f, 0.4f, 0.0f};
  part.front = {0.0f, 0.0f, 1.0f};
  part.sections = {{0.0f, 0.10f, 0.06f, 0.0f}, {1.0f, 0.10f, 0.06f, 0.0f}};
  part.start_cap = 0.05f;
  part.end_cap = 0.05f;
  return part;
}

TEST(BodyShape, EllipticSectionSideAlongXDepthAlongZ) {
  const BodyShape body({upright_part()}, 0.02f, 0.0f);
  // On the surface exactly where the half-axes say (float rounding only).
  EXPECT_NEAR(body.value({0.10f, 0.2f, 0.0f}), 0.0f, 1e-6f);
  EXPECT_NEAR(body.value({0.0f, 0.2f, 0.06f}), 0.0f, 1e-6f);
  EXPECT_NEAR(body.value({0.0f, 0.45f, 0.0f}), 0.0f, 1e-6f);  // end cap tip
  EXPECT_LT(body.value({0.0f, 0.2f, 0.0f}), 0.0f);
  EXPECT_GT(body.value({0.0f, 0.2f, 0.07f}), 0.0f);
  EXPECT_GT(body.value({0.11f, 0.2f, 0.0f}), 0.0f);
  // Far away the value is a positive constant, and whole blocks there report "empty".
  std::vector<glm::vec3> points = {{2.0f, 2.0f, 2.0f}};
  std::vector<float> values(1);
  EXPECT_FALSE(body.evaluate_block({1.9f, 1.9f, 1.9f}, {2.1f, 2.1f, 2.1f}, points, values));
  EXPECT_GT(body.value({2.0f, 2.0f, 2.0f}), 0.0f);
}

TEST(BodyShape, SmoothUnionFillsTheCornerBetweenParts) {
  BodyPart across = upright_part();
  across.start = {0.0f, 0.2f, 0.0f};
  across.end = {0.4f, 0.2f, 0.0f};
  const BodyShape sharp({upright_part(), across}, 1e-6f, 0.0f);
  const BodyShape smooth({upright_part(), across}, 0.04f, 0.0f);
  // Just outside the inner corner of the T: outside the plain union, inside the smooth one.
  const glm::vec3 corner(0.105f, 0.305f, 0.0f);
  EXPECT_GT(sharp.value(corner), 0.0f);
  EXPECT_LT(smooth.value(corner), 0.0f);
  // Far from the corner the fillet changes nothing.
  const glm::vec3 far_from_corner(0.35f, 0.2f, 0.08f);
  EXPECT_NEAR(smooth.value(far_from_corner), sharp.value(far_from_corner), 1e-6f);
}

TEST(BodyShape, PartCoordinatesRunAlongAndAroundTheAxis) {
  const BodyShape body({upright_part()}, 0.02f, 0.0f);
  EXPECT_NEAR(body.part_coordinates(0, {0.0f, -0.05f, 0.0f}).axial, 0.0f, 1e-6f);
  EXPECT_NEAR(body.part_coordinates(0, {0.0f, 0.45f, 0.0f}).axial, 1.0f, 1e-6f);
  EXPECT_NEAR(body.part_coordinates(0, {0.0f, 0.2f, 0.0f}).axial, 0.5f, 1e-6f);
  EXPECT_NEAR(body.part_coordinates(0, {0.0f, 0.2f, 0.06f}).angle, 0.5f, 1e-6f);  // front
  EXPECT_NEAR(body.part_coordinates(0, {0.1f, 0.2f, 0.0f}).angle, 0.75f, 1e-6f);  // +X side
  // The seam is at the back: just either side of it the angle is near 0 or near 1.
  EXPECT_LT(body.part_coordinates(0, {-0.001f, 0.2f, -0.06f}).angle, 0.01f);
  EXPECT_GT(body.part_coordinates(0, {0.001f, 0.2f, -0.06f}).angle, 0.99f);
}

TEST(BodyShape, MinimumHalfAxisThickensThinParts) {
  const BodyShape body({upright_part()}, 0.02f, 0.08f);
  // The 6 cm depth is raised to 8 cm; the 10 cm side stays.
  EXPECT_NEAR(body.value({0.0f, 0.2f, 0.08f}), 0.0f, 1e-6f);
  EXPECT_NEAR(body.value({0.10f, 0.2f, 0.0f}), 0.0f, 1e-6f);
}

}  // namespace
}  // namespace sweepd::mannequin
