// Tests for the spline interpolation behind C(t), a(t), b(t) (deform/sweep/interpolating_splines.h).
#include "deform/sweep/interpolating_splines.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace sweepd::deform {
namespace {

std::vector<glm::vec3> random_points(int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> coordinate(-2.0f, 2.0f);
  std::vector<glm::vec3> points(count);
  for (auto& p : points) p = {coordinate(rng), coordinate(rng), coordinate(rng)};
  return points;
}

TEST(ChordLengthParameters, FollowCumulativeLengthNormalised) {
  const std::vector<glm::vec3> points{{0, 0, 0}, {1, 0, 0}, {1, 3, 0}};
  std::vector<double> t(3);
  ASSERT_TRUE(chord_length_parameters(points, t));
  // Lengths 1 and 3 of a total 4; exact in double up to rounding.
  EXPECT_NEAR(t[0], 0.0, 1e-15);
  EXPECT_NEAR(t[1], 1.0 / 4.0, 1e-15);
  EXPECT_NEAR(t[2], 1.0, 1e-15);
}

TEST(ChordLengthParameters, RejectCoincidentPoints) {
  const std::vector<glm::vec3> points{{0, 0, 0}, {1, 0, 0}, {1, 0, 0}};
  std::vector<double> t(3);
  EXPECT_FALSE(chord_length_parameters(points, t));
  EXPECT_FALSE(chord_length_parameters(std::span(points).first(1), std::span(t).first(1)));
}

TEST(InterpolatingCubicSpline, PassesThroughItsDataPoints) {
  for (SplineEnds ends : {SplineEnds::kNotAKnot, SplineEnds::kNatural}) {
    for (int count : {2, 3, 4, 5, 9}) {
      const auto points = random_points(count, 17u + count);
      std::vector<double> t(count);
      ASSERT_TRUE(chord_length_parameters(points, t));
      InterpolatingCubicSpline spline;
      spline.set_parameters(t, ends);
      spline.interpolate(points);
      for (int i = 0; i < count; ++i) {
        // Float data, double solve: the residual is rounding only.
        const glm::dvec3 error = spline.position(t[i]) - glm::dvec3(points[i]);
        EXPECT_LT(glm::length(error), 1e-6) << "count " << count << " point " << i;
      }
    }
  }
}

TEST(InterpolatingCubicSpline, NotAKnotReproducesACubic) {
  // Data sampled from a cubic at uneven parameters: not-a-knot ends reproduce it exactly.
  auto cubic = [](double t) {
    return glm::dvec3(1 + 2 * t - 3 * t * t + 4 * t * t * t, t * t * t, 0.5 - t);
  };
  auto cubic_derivative = [](double t) {
    return glm::dvec3(2 - 6 * t + 12 * t * t, 3 * t * t, -1);
  };
  const std::vector<double> t{0.0, 0.1, 0.35, 0.4, 0.8, 1.0};
  std::vector<glm::vec3> points;
  for (double s : t) points.push_back(glm::vec3(cubic(s)));
  InterpolatingCubicSpline spline;
  spline.set_parameters(t, SplineEnds::kNotAKnot);
  spline.interpolate(points);
  for (double s = -0.1; s <= 1.1; s += 0.01) {
    // Tolerance: the data are rounded to float (~1e-7 relative), amplified mildly by the solve.
    EXPECT_LT(glm::length(spline.position(s) - cubic(s)), 2e-6) << "t = " << s;
    EXPECT_LT(glm::length(spline.derivative(s) - cubic_derivative(s)), 2e-5) << "t = " << s;
  }
}

TEST(InterpolatingCubicSpline, DerivativeMatchesCentralDifferences) {
  const auto points = random_points(6, 5u);
  std::vector<double> t(points.size());
  ASSERT_TRUE(chord_length_parameters(points, t));
  for (SplineEnds ends : {SplineEnds::kNotAKnot, SplineEnds::kNatural}) {
    InterpolatingCubicSpline spline;
    spline.set_parameters(t, ends);
    spline.interpolate(points);
    const double h = 1e-5;
    for (double s = 0.013; s < 1.0; s += 0.05) {
      const glm::dvec3 numeric = (spline.position(s + h) - spline.position(s - h)) / (2 * h);
      // Central difference error ~ h^2 |C'''| plus rounding 1e-16/h: far below 1e-5 relative.
      EXPECT_LT(glm::length(numeric - spline.derivative(s)), 1e-5 * glm::length(numeric) + 1e-8);
    }
  }
}

TEST(InterpolatingCubicSpline, TwoPointsGiveTheSegment) {
  const std::vector<glm::vec3> points{{1, 2, 3}, {4, 0, -1}};
  const std::vector<double> t{0.0, 1.0};
  InterpolatingCubicSpline spline;
  spline.set_parameters(t);
  spline.interpolate(points);
  const glm::dvec3 expected = glm::mix(glm::dvec3(points[0]), glm::dvec3(points[1]), 0.3);
  EXPECT_LT(glm::length(spline.position(0.3) - expected), 1e-12);  // linear: rounding only
}

TEST(InterpolatingCubicSpline, NaturalEndsHaveZeroCurvature) {
  const auto points = random_points(5, 9u);
  std::vector<double> t(points.size());
  ASSERT_TRUE(chord_length_parameters(points, t));
  InterpolatingCubicSpline spline;
  spline.set_parameters(t, SplineEnds::kNatural);
  spline.interpolate(points);
  const double h = 1e-4;
  for (double end : {0.0, 1.0}) {
    // C'' by a central difference of C' at the ends (C' is extended polynomially outside).
    const glm::dvec3 curvature =
        (spline.derivative(end + h) - spline.derivative(end - h)) / (2 * h);
    const glm::dvec3 interior = (spline.derivative(0.5 + h) - spline.derivative(0.5 - h)) / (2 * h);
    EXPECT_LT(glm::length(curvature), 1e-6 * glm::length(interior) + 1e-6);
  }
}

TEST(InterpolatingCubicSpline, RejectsBadInput) {
  InterpolatingCubicSpline spline;
  const std::vector<double> decreasing{0.0, 0.5, 0.4};
  EXPECT_THROW(spline.set_parameters(decreasing), std::invalid_argument);
  const std::vector<double> t{0.0, 1.0};
  spline.set_parameters(t);
  const std::vector<glm::vec3> three(3);
  EXPECT_THROW(spline.interpolate(three), std::invalid_argument);
}

TEST(InterpolatingQuadraticSpline, PassesThroughItsValues) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> value(0.1, 2.0);
  for (int count : {2, 3, 4, 7, 12}) {
    std::vector<double> sites(count), values(count);
    double s = 0.0;
    for (int i = 0; i < count; ++i) {
      sites[i] = s;
      s += value(rng);
      values[i] = value(rng);
    }
    InterpolatingQuadraticSpline spline;
    spline.set_parameters(sites);
    spline.interpolate(values);
    EXPECT_EQ(spline.degree(), count == 2 ? 1 : 2);
    for (int i = 0; i < count; ++i)  // double solve of a diagonally dominant system
      EXPECT_NEAR(spline.value(sites[i]), values[i], 1e-12) << "count " << count << " i " << i;
  }
}

TEST(InterpolatingQuadraticSpline, ReproducesLinearFunctions) {
  // Needed for cone frustums: a linear half-axis must stay exactly linear between the keys.
  const std::vector<double> sites{0.0, 0.07, 0.3, 0.55, 0.6, 1.0};
  std::vector<double> values;
  for (double s : sites) values.push_back(0.5 - 0.3 * s);
  InterpolatingQuadraticSpline spline;
  spline.set_parameters(sites);
  spline.interpolate(values);
  for (double s = 0.0; s <= 1.0; s += 0.01) EXPECT_NEAR(spline.value(s), 0.5 - 0.3 * s, 1e-12);
}

TEST(InterpolatingQuadraticSpline, BasisIsAPartitionOfUnity) {
  const std::vector<double> sites{0.0, 0.2, 0.25, 0.7, 1.0};
  InterpolatingQuadraticSpline spline;
  spline.set_parameters(sites);
  std::array<double, 3> basis{};
  for (double s = 0.0; s <= 1.0; s += 0.01) {
    const int first = spline.nonzero_basis(s, basis);
    EXPECT_GE(first, 0);
    EXPECT_LE(first + spline.degree(), spline.control_count() - 1);
    double sum = 0.0;
    for (double b : basis) {
      EXPECT_GE(b, -1e-15);  // B-spline basis functions are non-negative inside the domain
      sum += b;
    }
    EXPECT_NEAR(sum, 1.0, 1e-12);
  }
}

}  // namespace
}  // namespace sweepd::deform
