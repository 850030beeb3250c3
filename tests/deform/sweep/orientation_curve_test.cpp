// The orientation curve Q(t) (deform/sweep/orientation_curve.h): the paper's piecewise-linear
// curve and the C2 cumulative B-spline on unit quaternions.
#include "deform/sweep/orientation_curve.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace sweepd::deform {
namespace {

// Keys turning by up to ~70 degrees between neighbours about random axes, at uneven parameters.
OrientationCurve random_curve(int count, unsigned seed, OrientationCurveKind kind) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::vector<double> t{0.0};
  std::vector<glm::quat> keys{glm::quat(1, 0, 0, 0)};
  for (int i = 1; i < count; ++i) {
    t.push_back(t.back() + 0.5 + 0.5 * (unit(rng) + 1.0f));
    const glm::vec3 axis = glm::normalize(glm::vec3(unit(rng), unit(rng), unit(rng)) + 0.01f);
    keys.push_back(glm::angleAxis(glm::radians(70.0f) * unit(rng), axis) * keys.back());
  }
  for (double& v : t) v /= t.back();
  OrientationCurve curve;
  curve.set_parameters(t, kind);
  curve.set_keys(keys);
  return curve;
}

double distance(const glm::dquat& a, const glm::dquat& b) { return glm::length(a - b); }

TEST(OrientationCurve, SmoothStaysOnTheUnitSphereAndMeetsTheEndKeys) {
  const OrientationCurve curve = random_curve(7, 3u, OrientationCurveKind::kSmooth);
  for (int k = 0; k <= 200; ++k) {
    const double t = -0.05 + 1.1 * k / 200.0;                          // the extended ends too
    EXPECT_NEAR(glm::length(curve.unnormalised(t)), 1.0, 1e-12) << t;  // products of units
  }
  EXPECT_LT(distance(curve.unnormalised(0.0), curve.keys().front()), 1e-12);
  EXPECT_LT(distance(curve.unnormalised(1.0), curve.keys().back()), 1e-12);
}

TEST(OrientationCurve, SmoothDerivativeMatchesCentralDifferencesAndIsContinuousToSecondOrder) {
  for (const int count : {2, 3, 4, 7}) {  // degree 1, 2, 3 (one inner knot), 3 (three)
    const OrientationCurve curve = random_curve(count, 11u + count, OrientationCurveKind::kSmooth);
    const double h = 1e-5;
    for (int k = 1; k < 50; ++k) {
      const double t = k / 50.0 + 0.003;
      const glm::dquat numeric = (curve.unnormalised(t + h) - curve.unnormalised(t - h)) / (2 * h);
      // Central differences: error ~h² |Q'''| ≈ 1e-8 for these turns, rounding ~1e-16 / h.
      EXPECT_LT(distance(curve.derivative(t), numeric), 1e-6) << count << " keys, t " << t;
    }
    // C2 across the inner knots: Q' and the difference quotient of Q' agree from both sides.
    for (double knot : curve.breakpoints()) {
      const double e = 1e-7;
      EXPECT_LT(distance(curve.derivative(knot - e), curve.derivative(knot + e)), 1e-5);
      const glm::dquat left = (curve.derivative(knot - e) - curve.derivative(knot - 2 * e)) / e;
      const glm::dquat right = (curve.derivative(knot + 2 * e) - curve.derivative(knot + e)) / e;
      // Q'' from one-sided differences, each off by ~e |Q'''| + rounding 1e-15 / e ≈ 1e-6.
      EXPECT_LT(distance(left, right), 1e-3 * (1.0 + glm::length(left))) << "knot " << knot;
    }
  }
}

TEST(OrientationCurve, LinearCurveTurnsAtAJumpingRateAtItsKeys) {
  // What the smooth curve removes: the linear curve's Q' jumps at every inner key.
  const OrientationCurve curve = random_curve(5, 5u, OrientationCurveKind::kLinear);
  for (double key : curve.breakpoints())
    EXPECT_GT(distance(curve.derivative(key - 1e-9), curve.derivative(key + 1e-9)), 0.1);
}

TEST(OrientationCurve, SmoothReproducesAStraightRunAndStaysNearTheKeys) {
  // Equal keys: the curve is that rotation everywhere (a straight limb at rest stays straight).
  OrientationCurve curve;
  const std::vector<double> t{0.0, 0.2, 0.45, 0.7, 1.0};
  curve.set_parameters(t, OrientationCurveKind::kSmooth);
  const glm::quat q = glm::angleAxis(0.7f, glm::normalize(glm::vec3(1, 2, 3)));
  curve.set_keys(std::vector<glm::quat>(t.size(), q));
  for (double s : {0.0, 0.1, 0.33, 0.5, 0.9, 1.0})
    EXPECT_LT(distance(curve.unit(s), glm::dquat(q)), 1e-7) << s;
  // Keys turning evenly about one axis: the curve stays on that great circle and within the
  // keys' range; at an inner key it is within a third of the neighbouring turn of the key.
  std::vector<glm::quat> keys;
  for (double s : t)
    keys.push_back(glm::angleAxis(glm::radians(120.0f * float(s)), glm::vec3(0, 0, 1)));
  curve.set_keys(keys);
  for (std::size_t i = 1; i + 1 < t.size(); ++i) {
    const glm::dquat at = curve.unit(t[i]);
    EXPECT_LT(std::abs(at.x) + std::abs(at.y), 1e-12);
    const double angle = 2.0 * std::atan2(at.z, at.w);
    EXPECT_LT(std::abs(glm::degrees(angle) - 120.0 * t[i]), 120.0 * (t[i + 1] - t[i - 1]) / 3.0)
        << "key " << i;
  }
}

TEST(OrientationCurve, SmoothWithTwoKeysIsTheGeodesic) {
  OrientationCurve curve;
  curve.set_parameters(std::vector<double>{0.0, 1.0}, OrientationCurveKind::kSmooth);
  const glm::quat a = glm::angleAxis(0.3f, glm::vec3(1, 0, 0));
  const glm::quat b = glm::angleAxis(1.9f, glm::normalize(glm::vec3(0, 1, 1)));
  curve.set_keys(std::vector<glm::quat>{a, b});
  for (double s : {0.25, 0.5, 0.8})
    EXPECT_LT(distance(curve.unit(s), glm::slerp(glm::dquat(a), glm::dquat(b), s)), 1e-7) << s;
}

}  // namespace
}  // namespace sweepd::deform
