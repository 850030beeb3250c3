// Tests for cutting a triangle mesh by a plane and keeping the link's loop
// (deform/binding/cross_section.h).
#include "deform/binding/cross_section.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "deform/binding/polygon_ellipse.h"
#include "tests/deform/tube_mesh.h"

namespace sweepd::deform {
namespace {

constexpr double kPi = std::numbers::pi;
using test_geometry::add_tube;
using test_geometry::Mesh;
using test_geometry::Tube;

constexpr int kSegments = 64;

// A circular tube of radius r along +y from the origin.
Tube tube_along_y(float r, float length, int rings) {
  return {.radius_1 = r, .radius_2 = r, .length = length, .segments = kSegments, .rings = rings};
}

// The loop of a cut through a tube is an inscribed polygon: its points lie between the
// chord distance r cos(π/segments) and r from the axis.
void expect_on_tube(const CrossSection& section, glm::vec3 axis_point, glm::vec3 axis,
                    float radius) {
  ASSERT_FALSE(section.points.empty());
  for (const glm::vec3& p : section.points) {
    const glm::vec3 d = p - axis_point;
    const float distance = glm::length(d - glm::dot(d, axis) * axis);
    EXPECT_GE(distance, radius * std::cos(kPi / kSegments) - 1e-5);  // float positions
    EXPECT_LE(distance, radius + 1e-5);
  }
}

TEST(CrossSection, CylinderCutGivesItsCircle) {
  Mesh mesh;
  const float r = 0.5f;
  add_tube(mesh, tube_along_y(r, 2.0f, 10));
  const PlaneFrame plane = make_plane_frame({0, 0.73f, 0}, {0, 1, 0});
  const CrossSection section = cross_section(mesh.positions, mesh.indices, plane, {0, 0.73f, 0});
  ASSERT_TRUE(section.found);
  EXPECT_TRUE(section.closed);
  EXPECT_TRUE(section.encloses_link_point);
  EXPECT_EQ(section.loop_count, 1);
  // Each quad between two rings contributes a vertical edge and a diagonal.
  EXPECT_EQ(section.points.size(), 2u * kSegments);
  EXPECT_EQ(section.points_2d.size(), section.points.size());
  expect_on_tube(section, {0, 0, 0}, {0, 1, 0}, r);
  for (const glm::vec3& p : section.points) EXPECT_NEAR(p.y, 0.73f, 1e-6f);  // in the plane

  const EllipseFit fit = fit_polygon_ellipse(section.points_2d);
  ASSERT_TRUE(fit.valid);
  // The loop is the inscribed 64-gon (diagonal points lie on its edges), whose area is
  // π r² sin(x)/x with x = 2π/64: the area-equal circle has radius r sqrt(sin(x)/x).
  const double x = 2.0 * kPi / kSegments;
  EXPECT_LT(glm::length(fit.centre), 1e-5f);  // plane origin is on the axis
  EXPECT_NEAR(fit.a, r * std::sqrt(std::sin(x) / x), 1e-5);
  EXPECT_NEAR(fit.b, r * std::sqrt(std::sin(x) / x), 1e-5);
}

TEST(CrossSection, PlaneThroughARingOfVerticesStillGivesOneClosedLoop) {
  Mesh mesh;
  const float r = 0.5f;
  add_tube(mesh, tube_along_y(r, 2.0f, 5));  // rings at y = 0, 0.5, 1, ...
  const PlaneFrame plane = make_plane_frame({0, 1.0f, 0}, {0, 1, 0});
  const CrossSection section = cross_section(mesh.positions, mesh.indices, plane, {0, 1.0f, 0});
  ASSERT_TRUE(section.found);
  EXPECT_TRUE(section.closed);
  EXPECT_EQ(section.loop_count, 1);
  // On-plane vertices count as positive: the loop passes exactly through the ring's vertices,
  // once each after dropping repeats.
  EXPECT_EQ(section.points.size(), static_cast<std::size_t>(kSegments));
  for (std::size_t i = 0; i < section.points.size(); ++i) {
    EXPECT_NEAR(glm::length(glm::vec2(section.points[i].x, section.points[i].z)), r, 1e-6f);
    EXPECT_NE(section.points[i], section.points[(i + 1) % section.points.size()]);
  }
}

// A "T": a tall torso tube along y and an arm tube along x at shoulder height. The plane
// x + y = 3.5 cuts the arm around x = 1.5 and, separately, the torso higher up.
struct TShape {
  Mesh mesh;
  PlaneFrame plane = make_plane_frame({1.5f, 2.0f, 0.0f}, glm::vec3(1, 1, 0));
  TShape() {
    Tube torso = tube_along_y(1.0f, 9.0f, 19);
    torso.base = {0, -3, 0};
    add_tube(mesh, torso);
    add_tube(mesh, {.base = {0.5f, 2, 0},
                    .axis = {1, 0, 0},
                    .radial = {0, 0, 1},
                    .radius_1 = 0.4f,
                    .radius_2 = 0.4f,
                    .length = 3.5f,
                    .segments = kSegments,
                    .rings = 15});
  }
};

TEST(CrossSection, TShapeKeepsTheLoopAroundTheLinkPoint) {
  const TShape t;
  const CrossSection arm = cross_section(t.mesh.positions, t.mesh.indices, t.plane, {1.5f, 2, 0});
  ASSERT_TRUE(arm.found);
  EXPECT_EQ(arm.loop_count, 2);
  EXPECT_TRUE(arm.closed);
  EXPECT_TRUE(arm.encloses_link_point);
  expect_on_tube(arm, {0, 2, 0}, {1, 0, 0}, 0.4f);

  // The same plane with a link point on the torso axis keeps the torso's loop.
  const CrossSection torso =
      cross_section(t.mesh.positions, t.mesh.indices, t.plane, {0.0f, 3.5f, 0});
  ASSERT_TRUE(torso.found);
  EXPECT_TRUE(torso.encloses_link_point);
  expect_on_tube(torso, {0, 0, 0}, {0, 1, 0}, 1.0f);
}

TEST(CrossSection, LinkPointOutsideEveryLoopTakesTheNearest) {
  const TShape t;
  // (2.5, 1, 0) is in the plane, ~0.85 from the arm loop and over 2 from the torso loop.
  const CrossSection near = cross_section(t.mesh.positions, t.mesh.indices, t.plane, {2.5f, 1, 0});
  ASSERT_TRUE(near.found);
  EXPECT_FALSE(near.encloses_link_point);
  expect_on_tube(near, {0, 2, 0}, {1, 0, 0}, 0.4f);
}

TEST(CrossSection, OpenMeshGivesAnOpenChain) {
  Mesh mesh;
  Tube slotted = tube_along_y(0.5f, 1.0f, 4);
  slotted.covered = 0.75;  // leaves a slot: an open mesh
  add_tube(mesh, slotted);
  const CrossSection section = cross_section(
      mesh.positions, mesh.indices, make_plane_frame({0, 0.4f, 0}, {0, 1, 0}), {0, 0.4f, 0});
  ASSERT_TRUE(section.found);
  EXPECT_FALSE(section.closed);
  EXPECT_EQ(section.loop_count, 1);
  EXPECT_EQ(section.points.size(), 2u * kSegments + 1);  // both boundary columns are crossed
}

TEST(CrossSection, MissingThePlaneFindsNothing) {
  Mesh mesh;
  add_tube(mesh, tube_along_y(0.5f, 1.0f, 3));
  const CrossSection section =
      cross_section(mesh.positions, mesh.indices, make_plane_frame({0, 5, 0}, {0, 1, 0}), {});
  EXPECT_FALSE(section.found);
  EXPECT_EQ(section.loop_count, 0);
  EXPECT_TRUE(section.points.empty());
}

TEST(CrossSection, RejectsBadIndices) {
  const std::vector<glm::vec3> positions{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const std::vector<std::uint32_t> out_of_range{0, 1, 3}, partial{0, 1};
  const PlaneFrame plane = make_plane_frame({0, 0.5f, 0}, {0, 1, 0});
  EXPECT_THROW(cross_section(positions, out_of_range, plane, {}), std::invalid_argument);
  EXPECT_THROW(cross_section(positions, partial, plane, {}), std::invalid_argument);
}

TEST(MakePlaneFrame, IsOrthonormalAndRightHanded) {
  for (glm::vec3 normal : {glm::vec3(0, 0, 2), glm::vec3(1, 0, 0), glm::vec3(1, 2, -3)}) {
    const PlaneFrame f = make_plane_frame({1, 2, 3}, normal);
    EXPECT_NEAR(glm::length(f.x_axis), 1.0f, 1e-6f);  // float normalisation
    EXPECT_NEAR(glm::length(f.y_axis), 1.0f, 1e-6f);
    EXPECT_NEAR(glm::dot(f.x_axis, f.normal), 0.0f, 1e-6f);
    EXPECT_LT(glm::length(glm::cross(f.x_axis, f.y_axis) - f.normal), 1e-6f);
    EXPECT_LT(glm::length(f.normal - glm::normalize(normal)), 1e-6f);
  }
}

}  // namespace
}  // namespace sweepd::deform
