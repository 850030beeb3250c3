#include "deform/sweep/sweep.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace sweepd::deform {
namespace {

void require_count(std::span<const KeyEllipse> keys, int expected) {
  if (static_cast<int>(keys.size()) != expected)
    throw std::invalid_argument("sweep: expected " + std::to_string(expected) +
                                " key ellipses, got " + std::to_string(keys.size()));
}

}  // namespace

Sweep::Sweep(std::span<const KeyEllipse> keys, SplineEnds ends, OrientationCurveKind orientation) {
  if (keys.size() < 2)
    throw std::invalid_argument("sweep: need at least 2 key ellipses, got " +
                                std::to_string(keys.size()));
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const KeyEllipse& k = keys[i];
    if (!(k.a > 0.0f) || !(k.b > 0.0f) || !std::isfinite(k.a) || !std::isfinite(k.b))
      throw std::invalid_argument("sweep: key ellipse " + std::to_string(i) +
                                  " has a non-positive or non-finite half-axis");
    if (!std::isfinite(k.centre.x + k.centre.y + k.centre.z + k.offset.x + k.offset.y) ||
        !(glm::length(k.orientation) > 0.0f))
      throw std::invalid_argument("sweep: key ellipse " + std::to_string(i) +
                                  " has a non-finite centre or offset, or a zero orientation");
  }
  centres_.resize(keys.size());
  key_values_.resize(keys.size());
  parameters_.resize(keys.size());
  for (std::size_t i = 0; i < keys.size(); ++i) centres_[i] = keys[i].centre;
  if (!chord_length_parameters(centres_, parameters_))
    throw std::invalid_argument("sweep: two consecutive key ellipses share a centre");
  centre_.set_parameters(parameters_, ends);
  orientation_.set_parameters(parameters_, orientation);
  a_.set_parameters(parameters_);
  b_.set_parameters(parameters_);
  offset_x_.set_parameters(parameters_);
  offset_y_.set_parameters(parameters_);
  set_key_frames(keys);
  set_key_half_axes(keys);
}

void Sweep::set_key_frames(std::span<const KeyEllipse> keys) {
  require_count(keys, key_count());
  for (std::size_t i = 0; i < keys.size(); ++i) {
    centres_[i] = keys[i].centre;
    orientation_.set_key(static_cast<int>(i), keys[i].orientation);
  }
  orientation_.finish_keys();
  centre_.interpolate(centres_);
}

void Sweep::set_key_half_axes(std::span<const KeyEllipse> keys) {
  require_count(keys, key_count());
  auto interpolate = [&](InterpolatingQuadraticSpline& function, auto value_of_key) {
    for (std::size_t i = 0; i < keys.size(); ++i) key_values_[i] = value_of_key(keys[i]);
    function.interpolate(key_values_);
  };
  interpolate(a_, [](const KeyEllipse& k) { return k.a; });
  interpolate(b_, [](const KeyEllipse& k) { return k.b; });
  interpolate(offset_x_, [](const KeyEllipse& k) { return k.offset.x; });
  interpolate(offset_y_, [](const KeyEllipse& k) { return k.offset.y; });
}

glm::vec2 Sweep::offset(float t) const {
  return {static_cast<float>(offset_x_.value(t)), static_cast<float>(offset_y_.value(t))};
}

glm::vec3 Sweep::ellipse_centre(float t) const {
  return centre(t) + rotation(t) * glm::vec3(offset(t), 0.0f);
}

glm::dvec3 Sweep::ellipse_centre_derivative(double t) const {
  // R v = Q v Q* / |Q|² for the unnormalised Q(t) (|Q| = 1 for the smooth curve), so
  // (R v)' = (Q' v Q* + Q v Q'*) / |Q|² - 2 <Q, Q'> / |Q|² R v.
  const glm::dquat q = orientation_.unnormalised(t), dq = orientation_.derivative(t);
  const glm::dquat o(0.0, offset_x_.value(t), offset_y_.value(t), 0.0);
  const glm::dquat d_o(0.0, offset_x_.derivative(t), offset_y_.derivative(t), 0.0);
  const double norm2 = glm::dot(q, q);
  const glm::dquat turned = q * o * glm::conjugate(q) / norm2;
  const glm::dquat turning = (dq * o * glm::conjugate(q) + q * o * glm::conjugate(dq)) / norm2 -
                             turned * (2.0 * glm::dot(q, dq) / norm2);
  const glm::dquat moving = q * d_o * glm::conjugate(q) / norm2;
  return centre_.derivative(t) + glm::dvec3(turning.x, turning.y, turning.z) +
         glm::dvec3(moving.x, moving.y, moving.z);
}

glm::vec3 Sweep::point(float theta, float t) const {
  const SweepFrame f = frame(t);
  return f.rotation * glm::vec3(f.a * std::cos(theta), f.b * std::sin(theta), 0.0f) + f.centre;
}

SweepFrame Sweep::frame(float t) const {
  const glm::mat3 rotation(orientation_.rotation(t));
  return {glm::vec3(centre_.position(t)) + rotation * glm::vec3(offset(t), 0.0f), rotation,
          static_cast<float>(a_.value(t)), static_cast<float>(b_.value(t))};
}

void Sweep::frames(std::span<const float> t, std::span<SweepFrame> out) const {
  if (t.size() != out.size())
    throw std::invalid_argument("sweep: frames() got " + std::to_string(t.size()) +
                                " parameters but room for " + std::to_string(out.size()));
  for (std::size_t i = 0; i < t.size(); ++i) out[i] = frame(t[i]);
}

}  // namespace sweepd::deform
