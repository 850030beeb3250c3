// The feet of a model playing a clip, measured as a viewer would: where each sole is, when it
// is planted, and how far apart the footfalls are. Shared by the clip-unit and foot-planting
// tests; the definitions are the tests' own, independent of motion/foot_planting.h.
//
// Definitions (lengths scaled by the body: `size` is its height over 1.75 m, 1 for the male).
// A foot's height is its sole's: the lowest, in the posed frame, of the rest mesh's vertices
// skinned mostly to the rig map's foot joint or a joint below it (toes), each carried rigidly
// by that joint, minus the floor (the rest mesh's lowest vertex). A contact frame of a foot is
// a frame where it is planted: its height within 5 cm of its lowest over the clip, and its
// lowest vertex (that vertex, not the lowest one of other frames, which jumps between heel and
// toes as the foot rolls and can stand still under a foot that swings) moving under 0.25 m/s,
// measured over 0.05 s each side of the frame (a landing foot's marker noise jitters it by 2-3
// cm between 120 Hz frames), in three dimensions (a foot coming down to land is not planted
// yet). A footfall is a run of contact frames lasting at least 0.1 s, at the ankle's mean
// horizontal position over the run; footfalls closer than 10 cm to the previous one are the
// same placement (a standing foot's noise interrupting the run) and are merged into it. A
// stride is the horizontal distance between two successive footfalls of one foot.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "deform/model/forward_kinematics.h"
#include "deform/model/model.h"
#include "deform/rig/rig_map.h"
#include "motion/clip_poses.h"

namespace sweepd::test {

// Per foot (left, right), per frame.
struct FootTracks {
  std::vector<float> height[2];                   // the sole's, above the floor
  std::vector<glm::vec2> ankle[2];                // horizontal (x, z)
  std::vector<float> ankle_height[2];             // above the floor
  std::vector<glm::quat> foot_rotation[2];        // the foot joint's world rotation
  std::vector<std::vector<glm::vec3>> points[2];  // every sole vertex
  std::vector<std::size_t> lowest[2];             // the index of the lowest
  float floor = 0.0f;                             // the rest mesh's lowest y
  int frames() const { return static_cast<int>(height[0].size()); }
};

// `clip`'s feet turned about their ankles to `turned`'s world rotations, frame by frame: the sole
// points, heights and lowest points; the ankles stay (foot planting steadies a planted foot's
// rotation, motion/foot_planting.h, so the clip's own foot is compared turned alike).
inline FootTracks feet_turned_as(FootTracks clip, const FootTracks& turned) {
  for (int side = 0; side < 2; ++side)
    for (int f = 0; f < clip.frames(); ++f) {
      const glm::quat turn =
          turned.foot_rotation[side][f] * glm::inverse(clip.foot_rotation[side][f]);
      const glm::vec3 ankle(clip.ankle[side][f].x, clip.ankle_height[side][f] + clip.floor,
                            clip.ankle[side][f].y);
      float lowest = std::numeric_limits<float>::infinity();
      for (std::size_t k = 0; k < clip.points[side][f].size(); ++k) {
        glm::vec3& p = clip.points[side][f][k];
        p = ankle + turn * (p - ankle);
        if (p.y < lowest) lowest = p.y, clip.lowest[side][f] = k;
      }
      clip.height[side][f] = lowest - clip.floor;
      clip.foot_rotation[side][f] = turned.foot_rotation[side][f];
    }
  return clip;
}

class FeetOf {
 public:
  explicit FeetOf(const deform::Model& model)
      : model_(model), world_(model.skeleton.joints.size()) {
    const std::vector<glm::mat4> rest_inverse = deform::world_rest_inverse_matrices(model.skeleton);
    float top = -std::numeric_limits<float>::infinity();
    for (const glm::vec3& p : model.positions) {
      floor_ = std::min(floor_, p.y);
      top = std::max(top, p.y);
    }
    size_ = (top - floor_) / 1.75f;
    const deform::RigMap map = deform::detect_rig_map(model.skeleton);
    const deform::LegJoints* legs[2] = {&map.left_leg, &map.right_leg};
    for (int side = 0; side < 2; ++side) {
      ankle_[side] = legs[side]->foot;
      for (std::size_t v = 0; v < model.positions.size(); ++v) {
        const int joint = model.strongest_joint(v);
        for (int j = joint; j >= 0; j = model.skeleton.joints[j].parent)
          if (j == ankle_[side]) {
            sole_[side].push_back(
                {joint, rest_inverse[joint] * glm::vec4(model.positions[v], 1.0f)});
            break;
          }
      }
    }
  }
  std::size_t sole_vertices(int side) const { return sole_[side].size(); }
  // The body's height over 1.75 m: the definitions' lengths are scaled by it.
  float size() const { return size_; }

  // The feet over the clip sampled at `fps` from 0 to its end.
  FootTracks track(const motion::ClipPoses& clip, double fps) {
    FootTracks tracks;
    tracks.floor = floor_;
    for (int f = 0; f / fps <= clip.duration(); ++f) {
      const deform::Pose pose = clip.pose_at_time(f / fps);
      deform::forward_kinematics(model_.skeleton, pose, world_);
      std::vector<glm::quat> rotation(model_.skeleton.joints.size());
      for (int j = 0; j < model_.skeleton.size(); ++j) {
        const int parent = model_.skeleton.joints[j].parent;
        rotation[j] =
            parent < 0 ? pose.local_rotations[j] : rotation[parent] * pose.local_rotations[j];
      }
      for (int side = 0; side < 2; ++side) {
        float lowest = std::numeric_limits<float>::infinity();
        std::size_t lowest_index = 0;
        std::vector<glm::vec3>& points = tracks.points[side].emplace_back();
        for (const auto& [joint, local] : sole_[side]) {
          const glm::vec3 p = world_[joint] * local;
          if (p.y < lowest) {
            lowest = p.y;
            lowest_index = points.size();
          }
          points.push_back(p);
        }
        tracks.height[side].push_back(lowest - floor_);
        tracks.lowest[side].push_back(lowest_index);
        const glm::vec3 ankle(world_[ankle_[side]][3]);
        tracks.ankle[side].emplace_back(ankle.x, ankle.z);
        tracks.ankle_height[side].push_back(ankle.y - floor_);
        tracks.foot_rotation[side].push_back(rotation[ankle_[side]]);
      }
    }
    return tracks;
  }

 private:
  const deform::Model& model_;
  std::vector<glm::mat4> world_;
  float floor_ = std::numeric_limits<float>::infinity();
  float size_ = 1.0f;
  int ankle_[2];
  // (joint, rest position in the joint's rest frame): one matrix product per vertex and frame,
  // not two (the tracks of every frame of a clip are most of these tests' time).
  std::vector<std::pair<int, glm::vec4>> sole_[2];
};

struct Contacts {
  std::vector<int> frames;           // every contact frame
  std::vector<glm::vec2> footfalls;  // see the definitions above
};

inline Contacts contacts(const FootTracks& tracks, int side, double fps, float size = 1.0f) {
  const float kContactAboveLowest = 0.05f * size;  // m
  const float kContactSpeed = 0.25f * size;        // m/s
  constexpr double kSpeedWindow = 0.05;            // s, each side of the frame
  constexpr double kShortestFootfall = 0.1;        // s
  const float kSamePlacement = 0.1f * size;        // m
  const std::vector<float>& height = tracks.height[side];
  const float lowest = *std::min_element(height.begin(), height.end());
  const std::size_t reach = std::max<std::size_t>(1, std::lround(kSpeedWindow * fps));
  Contacts result;
  glm::vec2 sum(0.0f);
  int run = 0;
  for (std::size_t f = 0; f < height.size(); ++f) {
    const std::size_t a = f < reach ? 0 : f - reach, b = std::min(f + reach, height.size() - 1);
    const std::size_t point = tracks.lowest[side][f];
    const float speed =
        glm::distance(tracks.points[side][a][point], tracks.points[side][b][point]) *
        static_cast<float>(fps) / static_cast<float>(b - a);
    const bool contact = height[f] <= lowest + kContactAboveLowest && speed < kContactSpeed;
    if (contact) {
      result.frames.push_back(static_cast<int>(f));
      sum += tracks.ankle[side][f];
      ++run;
    }
    if (run > 0 && (!contact || f + 1 == height.size())) {
      const glm::vec2 at = sum / static_cast<float>(run);
      if (run >= kShortestFootfall * fps &&
          (result.footfalls.empty() ||
           glm::distance(result.footfalls.back(), at) >= kSamePlacement))
        result.footfalls.push_back(at);
      sum = glm::vec2(0.0f);
      run = 0;
    }
  }
  return result;
}

inline std::vector<float> strides(const Contacts& contacts) {
  std::vector<float> result;
  for (std::size_t i = 1; i < contacts.footfalls.size(); ++i)
    result.push_back(glm::distance(contacts.footfalls[i - 1], contacts.footfalls[i]));
  return result;
}

// Ankles and sole heights (the sole's lowest vertex may jump between two of equal height).
inline float foot_distance(const FootTracks& a, const FootTracks& b) {
  float worst = 0.0f;
  for (int side = 0; side < 2; ++side)
    for (std::size_t f = 0; f < a.ankle[side].size(); ++f)
      worst = std::max({worst, glm::distance(a.ankle[side][f], b.ankle[side][f]),
                        std::abs(a.height[side][f] - b.height[side][f])});
  return worst;
}

}  // namespace sweepd::test
