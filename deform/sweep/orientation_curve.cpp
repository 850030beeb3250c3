#include "deform/sweep/orientation_curve.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sweepd::deform {

void OrientationCurve::set_parameters(std::span<const double> params) {
  if (params.size() < 2)
    throw std::invalid_argument("quaternion curve: need at least 2 parameters");
  for (std::size_t i = 0; i + 1 < params.size(); ++i)
    if (!(params[i] < params[i + 1]))
      throw std::invalid_argument("quaternion curve: parameters must be strictly increasing");
  t_.assign(params.begin(), params.end());
  keys_.assign(params.size(), glm::dquat(1.0, 0.0, 0.0, 0.0));
}

void OrientationCurve::set_keys(std::span<const glm::quat> keys) {
  if (keys.size() != t_.size())
    throw std::invalid_argument("quaternion curve: expected " + std::to_string(t_.size()) +
                                " keys, got " + std::to_string(keys.size()));
  for (std::size_t i = 0; i < keys.size(); ++i) set_key(static_cast<int>(i), keys[i]);
  finish_keys();
}

void OrientationCurve::finish_keys() {
  for (std::size_t i = 1; i < keys_.size(); ++i)
    if (glm::dot(keys_[i - 1], keys_[i]) < 0.0) keys_[i] = -keys_[i];
}

int OrientationCurve::piece(double t) const {
  const auto it = std::upper_bound(t_.begin() + 1, t_.end() - 1, t);
  return static_cast<int>(it - t_.begin()) - 1;
}

glm::dquat OrientationCurve::unnormalised(double t) const {
  const int i = piece(t);
  const double s = (t - t_[i]) / (t_[i + 1] - t_[i]);
  return keys_[i] * (1.0 - s) + keys_[i + 1] * s;
}

glm::dquat OrientationCurve::derivative(double t) const {
  const int i = piece(t);
  return (keys_[i + 1] - keys_[i]) / (t_[i + 1] - t_[i]);
}

glm::dquat OrientationCurve::unit(double t) const { return glm::normalize(unnormalised(t)); }

glm::dmat3 OrientationCurve::rotation(double t) const { return glm::mat3_cast(unit(t)); }

}  // namespace sweepd::deform
