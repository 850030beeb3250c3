// KeyframeTrack: one animated property of one clip joint as keyframes (a glTF 2.0 animation
// channel with its sampler), and its sampling per the glTF 2.0 specification (section 3.11 and
// Appendix C). io/gltf/gltf_clip_load.h reads them; motion::Clip::local_pose_at_time samples them.
//
//   joint          index into Clip::joints
//   path           kTranslation (3 components: the joint's local translation, replacing its
//                  rest offset) or kRotation (4: a unit quaternion x, y, z, w in glTF order,
//                  replacing its rest rotation)
//   interpolation  kStep, kLinear (rotations: spherical, the spec's slerp) or kCubicSpline
//                  (Hermite, tangents scaled by the key interval)
//   times          K key times in seconds, strictly increasing
//   values         K × components floats; kCubicSpline: K × 3 × components (in-tangent, value,
//                  out-tangent of each key)
//
// sample_track(track, seconds, out): the track's value at `seconds` (out: components floats).
//   Before the first key: the first key's value; after the last: the last's. A time equal to a
//   key's up to float rounding (within 4 float epsilons relative, so frame times computed from
//   the key spacing land on keys) gives exactly that key's value. Between keys t_k and t_k+1,
//   with td = t_k+1 - t_k and s = (t - t_k) / td:
//     kStep         v_k
//     kLinear       (1 - s) v_k + s v_k+1; rotations slerp(v_k, v_k+1, s) on the shorter arc
//                   (plain lerp when the two are within 1e-6 rad)
//     kCubicSpline  (2s³ - 3s² + 1) v_k + td (s³ - 2s² + s) b_k + (-2s³ + 3s²) v_k+1
//                   + td (s³ - s²) a_k+1, with b_k the out-tangent of key k and a_k+1 the
//                   in-tangent of key k+1; rotations are then normalised.
//   Computed in double, written as float. Requires a track that passes track_problem().
// track_problem(track): "" when the track is well formed, else the reason in words (no keys,
//   times not increasing or not finite, a value count that does not match).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace sweepd::motion {

enum class TrackPath : std::uint8_t { kTranslation, kRotation };
enum class Interpolation : std::uint8_t { kStep, kLinear, kCubicSpline };

struct KeyframeTrack {
  int joint = 0;
  TrackPath path = TrackPath::kRotation;
  Interpolation interpolation = Interpolation::kLinear;
  std::vector<float> times;
  std::vector<float> values;

  int components() const { return path == TrackPath::kRotation ? 4 : 3; }
};

std::string track_problem(const KeyframeTrack& track);
void sample_track(const KeyframeTrack& track, double seconds, std::span<float> out);

}  // namespace sweepd::motion
