// Tests for fitting ellipses to closed polygons by their area moments (deform/binding/polygon_ellipse.h).
#include "deform/binding/polygon_ellipse.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace sweepd::deform {
namespace {

constexpr double kPi = std::numbers::pi;

struct TrueEllipse {
  glm::dvec2 centre;
  double angle, a, b;
};

// m points on the ellipse at evenly spaced parameter angles starting at `phase`.
std::vector<glm::vec2> sample(const TrueEllipse& e, int m, double phase) {
  std::vector<glm::vec2> polygon;
  const glm::dvec2 major(std::cos(e.angle), std::sin(e.angle)), minor(-major.y, major.x);
  for (int k = 0; k < m; ++k) {
    const double s = phase + 2.0 * kPi * k / m;
    polygon.push_back(glm::vec2(e.centre + e.a * std::cos(s) * major + e.b * std::sin(s) * minor));
  }
  return polygon;
}

// Difference of two axis angles, modulo π (an axis has no direction).
double angle_difference(double x, double y) {
  const double d = std::fmod(std::abs(x - y), kPi);
  return std::min(d, kPi - d);
}

TEST(FitEllipse, RecoversSampledEllipses) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> centre(-5, 5), angle(-kPi / 2, kPi / 2), major(0.5, 3),
      ratio(0.2, 0.9), phase(0, 2 * kPi);
  for (int trial = 0; trial < 50; ++trial) {
    const double a = major(rng);
    const TrueEllipse e{{centre(rng), centre(rng)}, angle(rng), a, a * ratio(rng)};
    const auto polygon = sample(e, 256, phase(rng));
    const EllipseFit fit = fit_polygon_ellipse(polygon);
    ASSERT_TRUE(fit.valid);
    // The inscribed 256-gon is an affine image of a regular polygon, so its moment ellipse has
    // the true centre, angle and axis ratio; its area is smaller by (1 - sin(x)/x), x = 2π/256,
    // i.e. ~1e-4, which the 1e-3 relative tolerance covers.
    EXPECT_LT(glm::length(glm::dvec2(fit.centre) - e.centre), 1e-3 * e.a) << "trial " << trial;
    EXPECT_NEAR(fit.a, e.a, 1e-3 * e.a) << "trial " << trial;
    EXPECT_NEAR(fit.b, e.b, 1e-3 * e.b) << "trial " << trial;
    EXPECT_LT(angle_difference(fit.angle, e.angle), 1e-3) << "trial " << trial;
    EXPECT_GE(fit.a, fit.b);
    EXPECT_LT(fit.fit_error, 1e-3);  // vertices lie on the true ellipse, ~1e-4 from the fit
    EXPECT_NEAR(fit.area, kPi * fit.a * fit.b, 1e-5 * fit.area);  // area preserved by design
  }
}

TEST(FitEllipse, DoesNotDependOnOrientationOrStartVertex) {
  const TrueEllipse e{{1.0, -2.0}, 0.4, 2.0, 0.7};
  auto polygon = sample(e, 64, 0.3);
  const EllipseFit forward = fit_polygon_ellipse(polygon);
  std::reverse(polygon.begin(), polygon.end());
  std::rotate(polygon.begin(), polygon.begin() + 17, polygon.end());
  const EllipseFit backward = fit_polygon_ellipse(polygon);
  ASSERT_TRUE(forward.valid && backward.valid);
  // Same sums in another order: float-level agreement.
  EXPECT_LT(glm::length(forward.centre - backward.centre), 1e-5f);
  EXPECT_NEAR(forward.a, backward.a, 1e-5f);
  EXPECT_NEAR(forward.b, backward.b, 1e-5f);
  EXPECT_NEAR(forward.angle, backward.angle, 1e-5f);
}

TEST(FitEllipse, FixedCentreUsesMomentsAboutThatPoint) {
  const TrueEllipse e{{0.5, 0.25}, -0.9, 1.5, 0.6};
  const auto polygon = sample(e, 256, 0.0);
  EllipseFitOptions at_true_centre;
  at_true_centre.fixed_centre = glm::vec2(e.centre);
  const EllipseFit fit = fit_polygon_ellipse(polygon, at_true_centre);
  ASSERT_TRUE(fit.valid);
  // Centred at the centroid the fixed-centre fit equals the free fit (same 1e-3 reason as above).
  EXPECT_EQ(fit.centre, glm::vec2(e.centre));
  EXPECT_NEAR(fit.a, e.a, 1e-3 * e.a);
  EXPECT_NEAR(fit.b, e.b, 1e-3 * e.b);
  EXPECT_LT(angle_difference(fit.angle, e.angle), 1e-3);

  // Off-centre (a joint at the rim side of a circle of radius 1): the moments about the joint
  // are stretched along the offset, so the fitted major axis points along it and the error grows.
  const TrueEllipse circle{{0.0, 0.0}, 0.0, 1.0, 1.0};
  EllipseFitOptions off_centre;
  off_centre.fixed_centre = glm::vec2(0.0f, 0.5f);
  const EllipseFit shifted = fit_polygon_ellipse(sample(circle, 256, 0.0), off_centre);
  ASSERT_TRUE(shifted.valid);
  EXPECT_EQ(shifted.centre, glm::vec2(0.0f, 0.5f));
  EXPECT_LT(angle_difference(shifted.angle, kPi / 2), 1e-4);  // symmetric about the y axis
  EXPECT_GT(shifted.a, shifted.b);
  EXPECT_GT(shifted.fit_error, 0.1f);
}

TEST(FitEllipse, FitErrorMeasuresTheShape) {
  // A square: the area-equal circle has radius 2/sqrt(π) for side 2, and the corners lie at
  // sqrt(2), so every vertex is off by sqrt(2π)/2 - 1 relative.
  const std::vector<glm::vec2> square{{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  const EllipseFit fit = fit_polygon_ellipse(square);
  ASSERT_TRUE(fit.valid);
  EXPECT_NEAR(fit.a, 2.0 / std::sqrt(kPi), 1e-6);  // isotropic moments: a circle
  EXPECT_NEAR(fit.b, 2.0 / std::sqrt(kPi), 1e-6);
  EXPECT_NEAR(fit.fit_error, std::sqrt(2.0 * kPi) / 2.0 - 1.0, 1e-6);
}

TEST(FitEllipse, RejectsPolygonsWithoutArea) {
  const std::vector<glm::vec2> collinear{{0, 0}, {1, 1}, {2, 2}, {3, 3}};
  EXPECT_FALSE(fit_polygon_ellipse(collinear).valid);
  const std::vector<glm::vec2> two{{0, 0}, {1, 0}};
  EXPECT_FALSE(fit_polygon_ellipse(two).valid);
}

}  // namespace
}  // namespace sweepd::deform
