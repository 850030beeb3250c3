// OrientationCurve: the orientation curve Q(t) of a sweep (paper §3.2) — piecewise-linear
// interpolation of unit quaternions q_i at parameters t_i,
//   Q(t) = ((t_{i+1} - t) q_i + (t - t_i) q_{i+1}) / (t_{i+1} - t_i),   t_i <= t <= t_{i+1},
// made sign-continuous (q_{i+1} is negated when <q_i, q_{i+1}> < 0, so each piece takes the
// short way) and normalised to give the rotation R(t).
// Inputs: n+1 parameters (set once), n+1 unit quaternions per frame (set_keys: no allocation).
// Outside [t_0, t_n] the end pieces are extended linearly.
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <span>
#include <vector>

namespace sweepd::deform {

class OrientationCurve {
 public:
  // params: n+1 strictly increasing values, n >= 1. Throws std::invalid_argument otherwise.
  void set_parameters(std::span<const double> params);
  // keys: exactly parameter_count() quaternions (normalised here). Throws on a size mismatch.
  void set_keys(std::span<const glm::quat> keys);
  // The same for quaternions that are not contiguous (e.g. inside KeyEllipse records): set each
  // with set_key, then call finish_keys once. i must be < parameter_count().
  void set_key(int i, const glm::quat& q) { keys_[i] = glm::normalize(glm::dquat(q)); }
  void finish_keys();  // applies the sign continuity to keys set by set_key

  glm::dquat unnormalised(double t) const;  // Q(t)
  glm::dquat derivative(double t) const;    // Q'(t), constant on each piece
  glm::dquat unit(double t) const;          // Q(t) / |Q(t)|
  glm::dmat3 rotation(double t) const;      // R(t)
  int parameter_count() const { return static_cast<int>(t_.size()); }
  // The key quaternions after the sign flips: <keys[i], keys[i+1]> >= 0.
  std::span<const glm::dquat> keys() const { return keys_; }

 private:
  int piece(double t) const;  // i with t_i <= t < t_{i+1}, clamped to the end pieces
  std::vector<double> t_;
  std::vector<glm::dquat> keys_;
};

}  // namespace sweepd::deform
