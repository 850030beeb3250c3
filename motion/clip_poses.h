// ClipPoses: a clip (motion/clip.h) played on a model's skeleton — the deform::Pose of any frame
// or time. Two players implement it: motion::Retargeter (motion/retarget.h: a clip made for
// another skeleton, mapped by names and rig roles) and motion::OwnSkeletonClip
// (motion/own_skeleton_clip.h: a clip that animates the model's own joints, e.g. a glTF
// animation of the model's file). motion::sample_clip (motion/clip_sampling.h) takes either.
//
//   motion()         the clip played
//   frame_count()    its frames; duration() its seconds from frame 0 to its end
//   pose_at_frame    the model posed as frame `frame`; std::out_of_range outside
//                    [0, frame_count())
//   pose_at_time     the model posed at `seconds` after frame 0, clamped to [0, duration()]
//                    (Clip::local_pose_at_time); NaN is std::invalid_argument
//   warnings         what playing it on this model leaves undone, for a person (the
//                    Retargeter's: joints left unmapped on either side); none by default
// Sampling is const and thread-safe.
#pragma once

#include <string>
#include <vector>

#include "deform/model/pose.h"
#include "motion/clip.h"

namespace sweepd::motion {

class ClipPoses {
 public:
  virtual ~ClipPoses() = default;
  virtual const Clip& motion() const = 0;
  int frame_count() const { return motion().frame_count; }
  double duration() const { return motion().duration(); }
  virtual deform::Pose pose_at_frame(int frame) const = 0;
  virtual deform::Pose pose_at_time(double seconds) const = 0;
  virtual const std::vector<std::string>& warnings() const {
    static const std::vector<std::string> none;
    return none;
  }
};

}  // namespace sweepd::motion
