// Tests for fitting key ellipses to mesh cross-sections (deform/binding/section_key_ellipse.h), and that a
// sweep through such keys recovers the mesh's volume.
#include "deform/binding/section_key_ellipse.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "deform/sweep/swept_volume.h"
#include "tests/deform/tube_mesh.h"

namespace sweepd::deform {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kSegments = 64;

// An elliptic tube along +y with half-axes 0.6 along x and 0.3 along z, y in [0, 2].
test_geometry::Mesh elliptic_tube() {
  test_geometry::Mesh mesh;
  test_geometry::add_tube(
      mesh,
      {.radius_1 = 0.6f, .radius_2 = 0.3f, .length = 2.0f, .segments = kSegments, .rings = 9});
  return mesh;
}

// The cut is the affine image of an inscribed regular 64-gon: its moment ellipse has the true
// axes scaled by sqrt(sin(x)/x), x = 2π/64 (area-equal scaling).
double polygon_scale() {
  const double x = 2.0 * kPi / kSegments;
  return std::sqrt(std::sin(x) / x);
}

TEST(FitKeyEllipse, RecoversTheTubeSection) {
  const auto mesh = elliptic_tube();
  const PlaneFrame plane = make_plane_frame({0, 0.77f, 0}, {0, 1, 0}, {0, 0, 1});
  const KeyEllipseFit fit = fit_key_ellipse(mesh.positions, mesh.indices, plane, {0, 0.77f, 0});
  ASSERT_TRUE(fit.valid);
  EXPECT_TRUE(fit.closed_loop);
  EXPECT_TRUE(fit.encloses_link_point);
  // Float mesh positions and float outputs: 1e-5 absolute at unit scale.
  EXPECT_LT(glm::length(fit.key.centre - glm::vec3(0, 0.77f, 0)), 1e-5f);
  EXPECT_NEAR(fit.key.a, 0.6 * polygon_scale(), 1e-5);
  EXPECT_NEAR(fit.key.b, 0.3 * polygon_scale(), 1e-5);
  const glm::mat3 r = glm::mat3_cast(fit.key.orientation);
  EXPECT_NEAR(std::abs(r[0].x), 1.0f, 1e-5f);                // major axis along x (either sign)
  EXPECT_NEAR(std::abs(r[1].z), 1.0f, 1e-5f);                // minor axis along z
  EXPECT_LT(glm::length(r[2] - glm::vec3(0, 1, 0)), 1e-5f);  // N is the plane normal
}

TEST(FitKeyEllipse, FixedCentreIsProjectedOntoThePlane) {
  const auto mesh = elliptic_tube();
  const PlaneFrame plane = make_plane_frame({0.2f, 0.5f, 0.1f}, {0, 1, 0});
  // A joint off the plane, on the axis: its projection (0, 0.5, 0) is the centroid.
  const KeyEllipseFit fit =
      fit_key_ellipse(mesh.positions, mesh.indices, plane, {0, 0.5f, 0}, glm::vec3(0, 0.9f, 0));
  ASSERT_TRUE(fit.valid);
  EXPECT_LT(glm::length(fit.key.centre - glm::vec3(0, 0.5f, 0)), 1e-6f);
  EXPECT_NEAR(fit.key.a, 0.6 * polygon_scale(), 1e-5);  // same moments as the free fit
  EXPECT_NEAR(fit.key.b, 0.3 * polygon_scale(), 1e-5);
}

TEST(FitKeyEllipse, PlaneMissingTheMeshIsInvalid) {
  const auto mesh = elliptic_tube();
  const KeyEllipseFit fit = fit_key_ellipse(mesh.positions, mesh.indices,
                                            make_plane_frame({0, 3, 0}, {0, 1, 0}), {0, 3, 0});
  EXPECT_FALSE(fit.valid);
}

TEST(FitKeyEllipse, SweepThroughFittedKeysHasTheTubeVolume) {
  // Keys fitted at uneven heights between y = 0.1 and 1.9 give an elliptic cylinder whose
  // volume is the polygonal tube's: (area of the cut) x 1.8.
  const auto mesh = elliptic_tube();
  std::vector<KeyEllipse> keys;
  for (float y : {0.1f, 0.45f, 0.5f, 1.2f, 1.9f}) {
    const PlaneFrame plane = make_plane_frame({0, y, 0}, {0, 1, 0}, {1, 0, 0});
    const KeyEllipseFit fit = fit_key_ellipse(mesh.positions, mesh.indices, plane, {0, y, 0});
    ASSERT_TRUE(fit.valid) << "y = " << y;
    // Same x_hint for every key: the major axes agree in sign (no half-turn twist).
    EXPECT_GT(glm::mat3_cast(fit.key.orientation)[0].x, 0.99f) << "y = " << y;
    keys.push_back(fit.key);
  }
  const Sweep sweep(keys);
  const double length = double(1.9f) - double(0.1f);
  const double expected = kPi * 0.6 * 0.3 * polygon_scale() * polygon_scale() * length;
  // Float fits (~1e-7 relative per key) and an exact quadrature for constant a, b.
  EXPECT_NEAR(sweep_volume(sweep), expected, 1e-5 * expected);
}

}  // namespace
}  // namespace sweepd::deform
