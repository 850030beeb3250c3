#include "motion/keyframe_track.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>

namespace sweepd::motion {
namespace {

// Floats per key: the value, or in-tangent, value and out-tangent.
std::size_t key_stride(const KeyframeTrack& track) {
  const std::size_t c = static_cast<std::size_t>(track.components());
  return track.interpolation == Interpolation::kCubicSpline ? 3 * c : c;
}

// The value of key k (past its in-tangent for a cubic spline).
const float* key_value(const KeyframeTrack& track, std::size_t k) {
  const std::size_t offset =
      track.interpolation == Interpolation::kCubicSpline ? track.components() : 0;
  return track.values.data() + k * key_stride(track) + offset;
}

bool same_time(double t, float key) {
  constexpr double kRounding = 4.0 * std::numeric_limits<float>::epsilon();
  return std::abs(t - key) <= kRounding * std::max(1.0, std::abs(double{key}));
}

void copy_key(const KeyframeTrack& track, std::size_t k, std::span<float> out) {
  const float* value = key_value(track, k);
  std::copy(value, value + track.components(), out.begin());
}

// The spec's slerp of unit quaternions a, b (4 doubles each) at s, on the shorter arc.
std::array<double, 4> slerp(const float* a, const float* b, double s) {
  double dot = 0.0;
  for (int i = 0; i < 4; ++i) dot += double{a[i]} * b[i];
  const double sign = dot < 0.0 ? -1.0 : 1.0;
  const double angle = std::acos(std::min(1.0, std::abs(dot)));
  double wa = 1.0 - s, wb = s;
  if (angle > 1e-6) {
    wa = std::sin(angle * (1.0 - s)) / std::sin(angle);
    wb = std::sin(angle * s) / std::sin(angle);
  }
  std::array<double, 4> result;
  for (int i = 0; i < 4; ++i) result[i] = wa * a[i] + sign * wb * b[i];
  return result;
}

}  // namespace

std::string track_problem(const KeyframeTrack& track) {
  if (track.times.empty()) return "no keyframes";
  for (std::size_t k = 0; k < track.times.size(); ++k) {
    if (!std::isfinite(track.times[k])) return "key time " + std::to_string(k) + " is not finite";
    if (k > 0 && !(track.times[k] > track.times[k - 1]))
      return "key times are not strictly increasing (key " + std::to_string(k) + " at " +
             std::to_string(track.times[k]) + " s after " + std::to_string(track.times[k - 1]) +
             " s)";
  }
  const std::size_t components = static_cast<std::size_t>(track.components());
  const std::size_t outputs = track.values.size() / components;
  const std::size_t expected = track.times.size() * (key_stride(track) / components);
  if (track.values.size() % components != 0 || outputs != expected)
    return std::to_string(outputs) + " outputs for " + std::to_string(track.times.size()) +
           " keys (expected " + std::to_string(expected) +
           (track.interpolation == Interpolation::kCubicSpline
                ? ": in-tangent, value and out-tangent per key)"
                : ")");
  for (float value : track.values)
    if (!std::isfinite(value)) return "an output value is not finite";
  return "";
}

void sample_track(const KeyframeTrack& track, double seconds, std::span<float> out) {
  const std::vector<float>& times = track.times;
  const std::size_t last = times.size() - 1;
  // k: the last key at or before `seconds` (0 before the first key).
  const std::size_t k = static_cast<std::size_t>(std::max<std::ptrdiff_t>(
      std::upper_bound(times.begin(), times.end(), seconds) - times.begin() - 1, 0));
  if (same_time(seconds, times[k]) || seconds <= times[0] || k == last)
    return copy_key(track, k, out);
  if (same_time(seconds, times[k + 1])) return copy_key(track, k + 1, out);
  if (track.interpolation == Interpolation::kStep) return copy_key(track, k, out);
  const double td = double{times[k + 1]} - times[k];
  const double s = (seconds - times[k]) / td;
  const int c = track.components();
  const float* v0 = key_value(track, k);
  const float* v1 = key_value(track, k + 1);
  std::array<double, 4> value{};
  if (track.interpolation == Interpolation::kLinear) {
    if (track.path == TrackPath::kRotation) {
      value = slerp(v0, v1, s);
    } else {
      for (int i = 0; i < c; ++i) value[i] = (1.0 - s) * v0[i] + s * v1[i];
    }
  } else {
    const float* out_tangent = v0 + c;  // b_k
    const float* in_tangent = v1 - c;   // a_k+1
    const double s2 = s * s, s3 = s2 * s;
    const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2,
                 h11 = s3 - s2;
    for (int i = 0; i < c; ++i)
      value[i] = h00 * v0[i] + td * h10 * out_tangent[i] + h01 * v1[i] + td * h11 * in_tangent[i];
    if (track.path == TrackPath::kRotation) {
      double length = 0.0;
      for (int i = 0; i < 4; ++i) length += value[i] * value[i];
      length = std::sqrt(length);
      if (length > 0.0)
        for (int i = 0; i < 4; ++i) value[i] /= length;
    }
  }
  for (int i = 0; i < c; ++i) out[i] = static_cast<float>(value[i]);
}

}  // namespace sweepd::motion
