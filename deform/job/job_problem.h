// JobProblem: why a DeformJob cannot run (deform_job.h), and which of its inputs is at fault,
// so that a caller can answer each differently (the daemon maps them to its error codes).
//   kJointCount  the pose has a rotation count other than the skeleton's joint count
//   kPose        a rotation or the root translation is unusable (NaN, infinite, zero-length,
//                outside the job's rotation length tolerance), named by joint
//   kSelection   the method, features and options do not go together (features on LBS/DQS,
//                added volumes of the wrong size)
// A default JobProblem (kNone) means the job can run; it converts to false.
#pragma once

#include <string>

namespace sweepd::deform {

struct JobProblem {
  enum class Input { kNone, kJointCount, kPose, kSelection };
  Input input = Input::kNone;
  std::string message;

  explicit operator bool() const { return input != Input::kNone; }
};

}  // namespace sweepd::deform
