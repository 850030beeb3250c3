// Tests for the swept volume, its gradient and the volume correction step
// (deform/sweep/swept_volume.h).
#include "deform/sweep/swept_volume.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/quaternion.hpp>
#include <numbers>
#include <vector>

namespace sweepd::deform::swept_volume_test {
namespace {

constexpr double kPi = std::numbers::pi;

// Keys along the z axis at the given heights, plane normal +z, half-axes from the functions.
template <typename HalfAxisA, typename HalfAxisB>
std::vector<KeyEllipse> straight_keys(const std::vector<float>& heights, glm::quat orientation,
                                      HalfAxisA a, HalfAxisB b) {
  std::vector<KeyEllipse> keys;
  for (float z : heights) keys.push_back({glm::vec3(0.3f, -0.2f, z), orientation, a(z), b(z)});
  return keys;
}

// Keys on a circular arc of radius R in the xy plane over angle phi, normal = arc tangent.
std::vector<KeyEllipse> arc_keys(int count, double R, double phi, float a, float b) {
  std::vector<KeyEllipse> keys;
  for (int i = 0; i < count; ++i) {
    const double angle = phi * i / (count - 1);
    const glm::vec3 radial(std::cos(angle), std::sin(angle), 0.0);
    const glm::vec3 axial(0, 0, 1);
    const glm::vec3 tangent = glm::cross(axial, radial);  // = (-sin, cos, 0)
    const glm::quat q = glm::quat_cast(glm::mat3(axial, radial, tangent));
    keys.push_back({glm::vec3(R * glm::dvec3(radial)), q, a, b});
  }
  return keys;
}

TEST(SweepVolume, EllipticCylinder) {
  const float a = 0.3f, b = 0.2f;
  const std::vector<float> heights{0.0f, 0.4f, 0.5f, 1.3f, 2.0f};
  const Sweep sweep(straight_keys(
      heights, glm::quat(1, 0, 0, 0), [&](float) { return a; }, [&](float) { return b; }));
  const double expected = kPi * a * b * 2.0;
  // Polynomial integrand, exact quadrature: only float rounding of the inputs remains.
  EXPECT_NEAR(sweep_volume(sweep), expected, 1e-6 * expected);
}

TEST(SweepVolume, ObliqueCylinderCountsOnlyTheNormalComponent) {
  // Ellipse planes tilted by 25 degrees against the axis: volume = π a b <N, C(1) - C(0)>.
  const glm::quat tilt = glm::angleAxis(glm::radians(25.0f), glm::vec3(1, 0, 0));
  const std::vector<float> heights{0.0f, 0.7f, 1.1f, 2.0f};
  const Sweep sweep(straight_keys(
      heights, tilt, [](float) { return 0.4f; }, [](float) { return 0.25f; }));
  const double expected = kPi * 0.4f * 0.25f * 2.0 * std::cos(glm::radians(25.0));
  EXPECT_NEAR(sweep_volume(sweep), expected, 1e-6 * expected);  // polynomial integrand: exact
}

TEST(SweepVolume, EllipticConeFrustum) {
  // a and b vary linearly along the axis (a circular frustum is the case a == b). The
  // quadratic B-splines reproduce linear functions, so the closed form must match.
  const float h = 3.0f, a0 = 0.5f, a1 = 0.2f, b0 = 0.3f, b1 = 0.45f;
  auto a = [&](float z) { return a0 + (a1 - a0) * z / h; };
  auto b = [&](float z) { return b0 + (b1 - b0) * z / h; };
  const double da = a1 - a0, db = b1 - b0;
  const double expected = kPi * h * (a0 * b0 + (a0 * db + b0 * da) / 2.0 + da * db / 3.0);
  const double cone = kPi * h * (a0 * a0 + a0 * a1 + a1 * a1) / 3.0;
  // Two keys (linear a, b) and six uneven keys (quadratic B-splines) must agree.
  for (const auto& heights :
       {std::vector<float>{0.0f, 3.0f}, std::vector<float>{0.0f, 0.3f, 1.4f, 1.5f, 2.2f, 3.0f}}) {
    const Sweep sweep(straight_keys(heights, glm::quat(1, 0, 0, 0), a, b));
    EXPECT_NEAR(sweep_volume(sweep), expected, 1e-6 * expected) << heights.size() << " keys";
    const Sweep circular(straight_keys(heights, glm::quat(1, 0, 0, 0), a, a));
    EXPECT_NEAR(sweep_volume(circular), cone, 1e-6 * cone) << heights.size() << " keys";
  }
}

TEST(SweepVolume, BentTubeMatchesPappus) {
  // A tube of radius r around a quarter circle of radius R: volume π r² R φ (Pappus). C(t)
  // and Q(t) only approximate the arc, with errors of O(h^4) (not-a-knot spline) and O(h^6)
  // (nlerp angle error enters squared); 33 keys (h = φ/32) keep both below 1e-6 relative.
  const double R = 1.0, phi = kPi / 2.0;
  const float r = 0.1f;
  const Sweep sweep(arc_keys(33, R, phi, r, r));
  const double expected = kPi * double(r) * double(r) * R * phi;
  EXPECT_NEAR(sweep_volume(sweep), expected, 1e-6 * expected);
  // The centre curve stays on the arc (explains the above; same h^4 reason).
  for (float t = 0.0f; t <= 1.0f; t += 0.01f) EXPECT_NEAR(glm::length(sweep.centre(t)), R, 1e-6);
}

TEST(SweepVolume, BentTubeWithOffsetEllipsesMatchesPappusAtTheEllipseCentres) {
  // The same arc for C(t), with every ellipse moved in its plane by o along the radial axis
  // (R's second column): the tube's axis is the arc of radius R + o, so the volume is
  // π r² (R + o) φ. R' (o, 0) carries all of the difference (o' = 0); the error sources are
  // those of the test above, so the same 1e-6.
  const double R = 1.0, phi = kPi / 2.0;
  const float r = 0.1f;
  for (const float o : {0.3f, -0.3f}) {
    auto keys = arc_keys(33, R, phi, r, r);
    for (KeyEllipse& key : keys) key.offset = glm::vec2(0.0f, o);
    const Sweep sweep(keys);
    const double expected = kPi * double(r) * double(r) * (R + o) * phi;
    EXPECT_NEAR(sweep_volume(sweep), expected, 1e-6 * expected) << "offset " << o;
  }
}

TEST(SweepVolume, QuadratureMatchesAFineMidpointRuleOnATwistedSweep) {
  // Neighbouring keys 120 degrees apart make the rational part of the integrand (1/|Q(t)|^2)
  // vary strongly; the offset ellipses add R' (o, 0) to C'. Reference: 2×100000-point midpoint
  // rule on the same curves, whose own error (~h²/24 |f''|) is below 1e-9 relative here; 1e-8
  // leaves room for it.
  std::vector<KeyEllipse> keys{
      {{0, 0, 0}, glm::quat(1, 0, 0, 0), 0.3f, 0.2f, {0.05f, 0.0f}},
      {{0.2f, 0, 1},
       glm::angleAxis(glm::radians(120.0f), glm::normalize(glm::vec3(1, 1, 0))),
       0.5f,
       0.1f,
       {-0.1f, 0.08f}},
      {{0.5f, 0.3f, 1.5f},
       glm::angleAxis(glm::radians(240.0f), glm::vec3(0, 0, 1)),
       0.2f,
       0.3f,
       {0.0f, 0.12f}}};
  const Sweep sweep(keys);
  // Per key span: R' (o, 0) jumps at the keys (Q is piecewise linear), which a midpoint rule
  // across a key would only resolve to O(h).
  const int samples = 100000;  // per span
  const auto spans = sweep.parameters();
  double reference = 0.0;
  for (std::size_t i = 0; i + 1 < spans.size(); ++i) {
    const double h = (spans[i + 1] - spans[i]) / samples;
    for (int k = 0; k < samples; ++k) {
      const double t = spans[i] + (k + 0.5) * h;
      const glm::dvec3 normal = sweep.orientation_curve().rotation(t)[2];
      reference += sweep.a_function().value(t) * sweep.b_function().value(t) * kPi *
                   glm::dot(normal, sweep.ellipse_centre_derivative(t)) * h;
    }
  }
  EXPECT_NEAR(sweep_volume(sweep), reference, 1e-8 * std::abs(reference));
}

TEST(SweepVolume, SmoothOrientationQuadratureMatchesAFineMidpointRule) {
  // The C2 orientation curve (cumulative B-spline): N(t) holds sines and cosines of the basis
  // polynomials, so the Gauss rule is not exact. Five keys (one inner knot), neighbours up to
  // 150 degrees apart, offset ellipses. Reference: 2×10⁶-point midpoint rule over [0, 1] (the
  // integrand is C2 there), own error ~h²/24 |f''| below 1e-10 relative; 1e-9 is the stated
  // bound of the quadrature (swept_volume.h).
  std::vector<KeyEllipse> keys;
  for (int i = 0; i < 5; ++i) {
    const float s = float(i);
    keys.push_back({{0.1f * s * s, 0.05f * s, 0.4f * s},
                    glm::angleAxis(glm::radians(150.0f * s * (i % 2 ? 1.0f : 0.8f)),
                                   glm::normalize(glm::vec3(1, 0.3f * s, 0.2f))),
                    0.2f + 0.05f * s,
                    0.1f + 0.02f * float(i % 3),
                    {0.03f * s, -0.02f}});
  }
  const Sweep sweep(keys, SplineEnds::kNotAKnot, OrientationCurveKind::kSmooth);
  ASSERT_FALSE(sweep.orientation_curve().breakpoints().empty());
  const int samples = 2000000;
  const double h = 1.0 / samples;
  double reference = 0.0;
  for (int k = 0; k < samples; ++k) {
    const double t = (k + 0.5) * h;
    const glm::dvec3 normal = sweep.orientation_curve().rotation(t)[2];
    reference += sweep.a_function().value(t) * sweep.b_function().value(t) * kPi *
                 glm::dot(normal, sweep.ellipse_centre_derivative(t)) * h;
  }
  EXPECT_NEAR(sweep_volume(sweep), reference, 1e-9 * std::abs(reference));
  // A straight tube: the smooth and the linear curve give the same volume (equal keys).
  const std::vector<float> heights{0.0f, 0.4f, 0.5f, 1.3f, 2.0f};
  const auto tube = straight_keys(
      heights, glm::quat(1, 0, 0, 0), [](float z) { return 0.3f + 0.1f * z; },
      [](float) { return 0.2f; });
  EXPECT_NEAR(sweep_volume(Sweep(tube, SplineEnds::kNotAKnot, OrientationCurveKind::kSmooth)),
              sweep_volume(Sweep(tube)), 1e-12);
}

TEST(SweepVolume, GradientMatchesCentralDifferences) {
  // A bent tube with varying half-axes, its ellipses centred on the arc and then offset in
  // their planes. I is bilinear in (α, β) whatever the offsets, so a central difference in one
  // control is exact up to rounding; 1e-5 relative leaves room for that rounding only.
  for (const float offset : {0.0f, 0.15f}) {
    auto keys = arc_keys(6, 1.0, 2.0, 0.2f, 0.1f);
    for (std::size_t i = 0; i < keys.size(); ++i) {
      keys[i].a += 0.03f * static_cast<float>(i);
      keys[i].b += 0.02f * static_cast<float>(i % 3);
      keys[i].offset = offset * glm::vec2(std::cos(float(i)), std::sin(float(i)));
    }
    Sweep sweep(keys);
    const int n = sweep.key_count();
    std::vector<double> d_alpha(n), d_beta(n);
    const double volume = sweep_volume_gradient(sweep, d_alpha, d_beta);
    EXPECT_NEAR(volume, sweep_volume(sweep), 1e-12 * volume);
    const double eps = 1e-3;
    for (int i = 0; i < n; ++i) {
      for (auto [controls, analytic] :
           {std::pair{sweep.alpha(), d_alpha[i]}, std::pair{sweep.beta(), d_beta[i]}}) {
        const double saved = controls[i];
        controls[i] = saved + eps;
        const double plus = sweep_volume(sweep);
        controls[i] = saved - eps;
        const double minus = sweep_volume(sweep);
        controls[i] = saved;
        const double numeric = (plus - minus) / (2 * eps);
        EXPECT_NEAR(analytic, numeric, 1e-5 * std::abs(numeric))
            << "control " << i << ", offset " << offset;
        EXPECT_GT(std::abs(numeric), 0.0);
      }
    }
  }
}

TEST(SweepVolume, CorrectionStepsRestoreTheRestVolume) {
  // An "arm" straight along z with an elbow key in the middle; bending it at the elbow changes
  // the volume. The paper's steps on the elbow key, then on its neighbours, restore it.
  const std::vector<float> heights{0.0f, 0.5f, 1.0f, 1.5f, 2.0f};
  auto keys = straight_keys(
      heights, glm::quat(1, 0, 0, 0), [](float) { return 0.2f; }, [](float) { return 0.15f; });
  Sweep sweep(keys);
  const double rest_volume = sweep_volume(sweep);
  // Bend the lower half by 90 degrees about x at the elbow (key 2), elbow key at half angle.
  const glm::vec3 elbow = keys[2].centre;
  const glm::quat bend = glm::angleAxis(glm::radians(90.0f), glm::vec3(1, 0, 0));
  for (int i = 3; i < 5; ++i) {
    keys[i].centre = elbow + bend * (keys[i].centre - elbow);
    keys[i].orientation = bend;
  }
  keys[2].orientation = glm::angleAxis(glm::radians(45.0f), glm::vec3(1, 0, 0));
  sweep.set_key_frames(keys);
  const double bent_volume = sweep_volume(sweep);
  ASSERT_GT(std::abs(bent_volume - rest_volume), 1e-3 * rest_volume);  // the bend matters

  const int n = sweep.key_count();
  std::vector<double> d_alpha(n), d_beta(n);
  const std::vector<int> elbow_only{2}, elbow_and_neighbours{1, 2, 3};
  for (int step = 0; step < 3; ++step) {
    volume_correction_step(sweep, rest_volume, elbow_only, d_alpha, d_beta);
    for (int i : {0, 1, 3, 4}) {
      EXPECT_EQ(d_alpha[i], 0.0);  // restricted to the chosen controls
      EXPECT_EQ(d_beta[i], 0.0);
    }
    apply_half_axis_deltas(sweep, d_alpha, d_beta);
  }
  for (int step = 0; step < 2; ++step) {
    volume_correction_step(sweep, rest_volume, elbow_and_neighbours, d_alpha, d_beta);
    apply_half_axis_deltas(sweep, d_alpha, d_beta);
  }
  // Each step solves the linearisation of a bilinear function: the residual is second order in
  // the step, so five steps leave only rounding.
  EXPECT_NEAR(sweep_volume(sweep), rest_volume, 1e-9 * rest_volume);
  EXPECT_THROW(volume_correction_step(sweep, rest_volume, std::vector<int>{7}, d_alpha, d_beta),
               std::invalid_argument);
}

TEST(SweepVolume, ACorrectionStepOnOneHalfAxisHitsItsTargetAndLeavesTheOtherAlone) {
  const std::vector<float> heights{0.0f, 0.5f, 1.0f, 1.5f};
  auto keys = straight_keys(
      heights, glm::quat(1, 0, 0, 0), [](float) { return 0.2f; }, [](float) { return 0.15f; });
  Sweep sweep(keys);
  const double target = 1.1 * sweep_volume(sweep);
  const int n = sweep.key_count();
  std::vector<double> d_alpha(n), d_beta(n);
  const std::vector<int> key_one{1}, none{};
  volume_correction_step(sweep, target, key_one, none, d_alpha, d_beta);
  for (int i = 0; i < n; ++i) {
    EXPECT_EQ(d_beta[i], 0.0);  // β is frozen
    if (i != 1) {
      EXPECT_EQ(d_alpha[i], 0.0);
    }
  }
  EXPECT_GT(d_alpha[1], 0.0);
  apply_half_axis_deltas(sweep, d_alpha, d_beta);
  // I is linear in α for fixed β, so one step on α alone lands on the target (to rounding).
  EXPECT_NEAR(sweep_volume(sweep), target, 1e-9 * target);
  EXPECT_THROW(volume_correction_step(sweep, target, none, std::vector<int>{-1}, d_alpha, d_beta),
               std::invalid_argument);
}

}  // namespace
}  // namespace sweepd::deform::swept_volume_test
