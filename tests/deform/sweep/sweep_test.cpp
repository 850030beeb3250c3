// Tests for the sweep surface S(θ, t) of deform/sweep/sweep.h, its orientation curve Q(t) and its
// ellipses' centre curve C̃(t) = C(t) + R(t) (o(t), 0) with in-plane key offsets o.
#include "deform/sweep/sweep.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/quaternion.hpp>
#include <random>
#include <vector>

namespace sweepd::deform {
namespace {

std::vector<KeyEllipse> random_keys(int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f), size(0.1f, 0.5f);
  std::vector<KeyEllipse> keys(count);
  for (int i = 0; i < count; ++i) {
    keys[i].centre = glm::vec3(unit(rng), unit(rng), 0.5f * static_cast<float>(i));
    keys[i].orientation = glm::normalize(glm::quat(2.0f, unit(rng), unit(rng), unit(rng)));
    keys[i].a = size(rng);
    keys[i].b = size(rng);
    keys[i].offset = 0.1f * glm::vec2(unit(rng), unit(rng));
  }
  return keys;
}

float max_abs_difference(const glm::mat3& x, const glm::mat3& y) {
  float worst = 0.0f;
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) worst = std::max(worst, std::abs(x[c][r] - y[c][r]));
  return worst;
}

TEST(Sweep, ReproducesItsKeyEllipses) {
  const auto keys = random_keys(6, 11u);
  const Sweep sweep(keys);
  ASSERT_EQ(sweep.key_count(), 6);
  EXPECT_DOUBLE_EQ(sweep.parameters().front(), 0.0);
  EXPECT_DOUBLE_EQ(sweep.parameters().back(), 1.0);
  for (int i = 0; i < 6; ++i) {
    const float t = static_cast<float>(sweep.parameters()[i]);
    // Float evaluation of double curves at a float-rounded parameter: ~1e-7 relative.
    EXPECT_LT(glm::length(sweep.centre(t) - keys[i].centre), 1e-5f) << "key " << i;
    EXPECT_LT(max_abs_difference(sweep.rotation(t), glm::mat3_cast(keys[i].orientation)), 1e-5f);
    EXPECT_NEAR(sweep.a(t), keys[i].a, 1e-5f);
    EXPECT_NEAR(sweep.b(t), keys[i].b, 1e-5f);
    EXPECT_LT(glm::length(sweep.offset(t) - keys[i].offset), 1e-5f);
    const glm::vec3 ellipse_centre =
        keys[i].centre + glm::mat3_cast(keys[i].orientation) * glm::vec3(keys[i].offset, 0.0f);
    EXPECT_LT(glm::length(sweep.ellipse_centre(t) - ellipse_centre), 1e-5f);
  }
}

TEST(Sweep, EllipseCentreDerivativeMatchesCentralDifferences) {
  // C̃' = C' + R' (o, 0) + R (o', 0) against central differences of C̃ in double precision,
  // inside the pieces (C̃ is smooth there; Q' and o' jump at keys and knot midpoints).
  const Sweep sweep(random_keys(5, 17u));
  auto ellipse_centre = [&](double t) {
    const glm::dvec3 offset(sweep.offset_x_function().value(t), sweep.offset_y_function().value(t),
                            0.0);
    return sweep.centre_curve().position(t) + sweep.orientation_curve().rotation(t) * offset;
  };
  const double h = 1e-6;
  for (double t : {0.03, 0.17, 0.31, 0.52, 0.69, 0.88, 0.97}) {
    const glm::dvec3 numeric = (ellipse_centre(t + h) - ellipse_centre(t - h)) / (2.0 * h);
    const glm::dvec3 analytic = sweep.ellipse_centre_derivative(t);
    // Central difference error ~h² |C̃'''| ~1e-11, rounding ~1e-16 / h ~1e-10: 1e-7 is safe.
    EXPECT_LT(glm::length(analytic - numeric), 1e-7 * glm::length(numeric)) << "t = " << t;
    // The offset terms matter here: C' alone differs by more than the tolerance.
    EXPECT_GT(glm::length(sweep.centre_curve().derivative(t) - numeric), 1e-3) << "t = " << t;
  }
}

TEST(Sweep, SurfacePointsLieOnTheMovingEllipse) {
  const Sweep sweep(random_keys(4, 2u));
  for (float t : {0.0f, 0.21f, 0.5f, 0.93f}) {
    for (float theta : {0.0f, 1.0f, 2.5f, 4.0f}) {
      const glm::vec3 local =
          glm::transpose(sweep.rotation(t)) * (sweep.point(theta, t) - sweep.ellipse_centre(t));
      // Float round trip through R and R^T: ~1e-6 absolute at these sizes.
      EXPECT_NEAR(local.x, sweep.a(t) * std::cos(theta), 1e-5f);
      EXPECT_NEAR(local.y, sweep.b(t) * std::sin(theta), 1e-5f);
      EXPECT_NEAR(local.z, 0.0f, 1e-5f);
      EXPECT_LT(glm::length(sweep.normal(t) - sweep.rotation(t)[2]), 1e-7f);
    }
  }
}

TEST(Sweep, FramesAgreeWithTheSingleEvaluators) {
  const Sweep sweep(random_keys(5, 13u));
  const std::vector<float> t{0.0f, 0.1f, 0.5f, 0.77f, 1.0f};
  std::vector<SweepFrame> out(t.size());
  sweep.frames(t, out);
  for (std::size_t i = 0; i < t.size(); ++i) {
    // Same double evaluation rounded to float the same way: identical results.
    EXPECT_EQ(out[i].centre, sweep.ellipse_centre(t[i]));
    EXPECT_EQ(out[i].rotation, sweep.rotation(t[i]));
    EXPECT_EQ(out[i].a, sweep.a(t[i]));
    EXPECT_EQ(out[i].b, sweep.b(t[i]));
  }
  std::vector<SweepFrame> too_small(2);
  EXPECT_THROW(sweep.frames(t, too_small), std::invalid_argument);
}

TEST(Sweep, OrientationIsSignContinuous) {
  // Keys with the same rotation but alternating quaternion signs: a naive linear blend of q and
  // -q passes through zero; the sign-continuous curve must stay at that rotation throughout.
  std::vector<KeyEllipse> keys(5);
  const glm::quat q = glm::angleAxis(0.7f, glm::normalize(glm::vec3(1, 2, 3)));
  for (int i = 0; i < 5; ++i) {
    keys[i].centre = glm::vec3(0.1f * static_cast<float>(i * i), 0, static_cast<float>(i));
    keys[i].orientation = i % 2 == 0 ? q : -q;
  }
  const Sweep sweep(keys);
  const auto flipped = sweep.orientation_curve().keys();
  for (std::size_t i = 1; i < flipped.size(); ++i)
    EXPECT_GE(glm::dot(flipped[i - 1], flipped[i]), 0.0);
  for (float t = 0.0f; t <= 1.0f; t += 0.01f) {
    EXPECT_GT(glm::length(sweep.orientation_curve().unnormalised(t)), 0.99);
    EXPECT_LT(max_abs_difference(sweep.rotation(t), glm::mat3_cast(q)), 1e-6f) << "t = " << t;
  }
}

TEST(Sweep, OrientationTakesTheShortArcBetweenKeys) {
  // Two keys 120 degrees apart about z, the second given with a negative sign: the rotation at
  // the middle must be the 60-degree one, not the long way round (which would be -120 degrees).
  std::vector<KeyEllipse> keys(2);
  keys[1].centre = glm::vec3(0, 0, 1);
  keys[1].orientation = -glm::angleAxis(glm::radians(120.0f), glm::vec3(0, 0, 1));
  const Sweep sweep(keys);
  const glm::vec3 x = sweep.rotation(0.5f)[0];
  EXPECT_NEAR(std::atan2(x.y, x.x), glm::radians(60.0f), 1e-5f);  // nlerp midpoint is exact
}

TEST(Sweep, RigidMotionOfTheKeysMovesTheSurfaceRigidly) {
  auto keys = random_keys(5, 7u);
  Sweep sweep(keys);
  const glm::quat turn = glm::angleAxis(1.1f, glm::normalize(glm::vec3(0.3f, -1, 0.5f)));
  const glm::vec3 shift(0.4f, -2.0f, 1.5f);
  std::vector<glm::vec3> before;
  for (float t = 0.0f; t <= 1.0f; t += 0.1f) before.push_back(sweep.point(0.8f, t));
  for (auto& k : keys) {
    k.centre = turn * k.centre + shift;
    k.orientation = turn * k.orientation;
    k.a *= 3.0f;  // ignored by set_key_frames: a(t), b(t) are kept
  }
  sweep.set_key_frames(keys);
  int index = 0;
  for (float t = 0.0f; t <= 1.0f; t += 0.1f) {
    // Interpolation is linear in the data and Q(t) is left-multiplied: exact up to float rounding.
    EXPECT_LT(glm::length(sweep.point(0.8f, t) - (turn * before[index++] + shift)), 2e-5f);
  }
}

TEST(Sweep, SetKeyHalfAxesReinterpolatesAAndBAndTheOffsets) {
  auto keys = random_keys(4, 3u);
  Sweep sweep(keys);
  for (auto& k : keys) {
    k.a *= 2.0f;
    k.b *= 0.5f;
    k.offset = glm::vec2(k.offset.y, -2.0f * k.offset.x);
  }
  sweep.set_key_half_axes(keys);
  for (int i = 0; i < 4; ++i) {
    const float t = static_cast<float>(sweep.parameters()[i]);
    EXPECT_NEAR(sweep.a(t), keys[i].a, 1e-5f);  // interpolation, float output
    EXPECT_NEAR(sweep.b(t), keys[i].b, 1e-5f);
    EXPECT_LT(glm::length(sweep.offset(t) - keys[i].offset), 1e-5f);
  }
}

TEST(Sweep, RejectsInvalidKeys) {
  auto keys = random_keys(3, 5u);
  EXPECT_THROW(Sweep(std::span(keys).first(1)), std::invalid_argument);
  auto coincident = keys;
  coincident[1].centre = coincident[0].centre;
  EXPECT_THROW(Sweep{coincident}, std::invalid_argument);
  auto flat = keys;
  flat[2].b = 0.0f;
  EXPECT_THROW(Sweep{flat}, std::invalid_argument);
  auto astray = keys;
  astray[1].offset.x = std::nanf("");
  EXPECT_THROW(Sweep{astray}, std::invalid_argument);
  Sweep sweep(keys);
  EXPECT_THROW(sweep.set_key_frames(std::span(keys).first(2)), std::invalid_argument);
}

}  // namespace
}  // namespace sweepd::deform
