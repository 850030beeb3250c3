#include "deform/sweep.h"

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

Sweep::Sweep(std::span<const KeyEllipse> keys, SplineEnds ends) {
  if (keys.size() < 2)
    throw std::invalid_argument("sweep: need at least 2 key ellipses, got " +
                                std::to_string(keys.size()));
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const KeyEllipse& k = keys[i];
    if (!(k.a > 0.0f) || !(k.b > 0.0f) || !std::isfinite(k.a) || !std::isfinite(k.b))
      throw std::invalid_argument("sweep: key ellipse " + std::to_string(i) +
                                  " has a non-positive or non-finite half-axis");
    if (!std::isfinite(k.centre.x + k.centre.y + k.centre.z) ||
        !(glm::length(k.orientation) > 0.0f))
      throw std::invalid_argument("sweep: key ellipse " + std::to_string(i) +
                                  " has a non-finite centre or a zero orientation");
  }
  centres_.resize(keys.size());
  half_axes_.resize(keys.size());
  parameters_.resize(keys.size());
  for (std::size_t i = 0; i < keys.size(); ++i) centres_[i] = keys[i].centre;
  if (!chord_length_parameters(centres_, parameters_))
    throw std::invalid_argument("sweep: two consecutive key ellipses share a centre");
  centre_.set_parameters(parameters_, ends);
  orientation_.set_parameters(parameters_);
  a_.set_parameters(parameters_);
  b_.set_parameters(parameters_);
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
  for (std::size_t i = 0; i < keys.size(); ++i) half_axes_[i] = keys[i].a;
  a_.interpolate(half_axes_);
  for (std::size_t i = 0; i < keys.size(); ++i) half_axes_[i] = keys[i].b;
  b_.interpolate(half_axes_);
}

glm::vec3 Sweep::point(float theta, float t) const {
  const SweepFrame f = frame(t);
  return f.rotation * glm::vec3(f.a * std::cos(theta), f.b * std::sin(theta), 0.0f) + f.centre;
}

SweepFrame Sweep::frame(float t) const {
  return {glm::vec3(centre_.position(t)), glm::mat3(orientation_.rotation(t)),
          static_cast<float>(a_.value(t)), static_cast<float>(b_.value(t))};
}

void Sweep::frames(std::span<const float> t, std::span<SweepFrame> out) const {
  if (t.size() != out.size())
    throw std::invalid_argument("sweep: frames() got " + std::to_string(t.size()) +
                                " parameters but room for " + std::to_string(out.size()));
  for (std::size_t i = 0; i < t.size(); ++i) out[i] = frame(t[i]);
}

}  // namespace sweepd::deform
