// Deformer: a pose in, a deformed mesh out — by control sweeps (the paper), or by the model's
// own skin weights with linear blend or dual-quaternion skinning (the baselines every quality
// and speed figure is compared against; clients may choose them too).
//
// deform: validates the pose once (normalize_and_validate: wrong joint count, NaN/Inf, zero
//   quaternions → std::invalid_argument naming the joint; non-unit quaternions normalised in
//   place), runs forward kinematics, then the method. positions/normals: vertex_count() each
//   (normals empty to skip). Nothing is allocated per frame; threads > 1 splits the vertices
//   with bit-identical results.
// The BoundModel must outlive the deformer.
#pragma once

#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "deform/bound_model.h"
#include "deform/pose.h"
#include "deform/sweep_poser.h"

namespace sweepd::deform {

enum class DeformMethod { kSweep, kLbs, kDqs };
const char* to_string(DeformMethod method);
std::optional<DeformMethod> parse_deform_method(std::string_view name);  // "sweep", "lbs", "dqs"

class Deformer {
 public:
  explicit Deformer(const BoundModel& bound);

  void deform(Pose& pose, DeformMethod method, std::span<glm::vec3> positions,
              std::span<glm::vec3> normals, int threads = 1);

  const BoundModel& bound() const { return bound_; }
  SweepPoser& sweep_poser() { return sweep_poser_; }
  // World joint matrices and skinning matrices of the last pose.
  std::span<const glm::mat4> world_pose() const { return world_pose_; }
  std::span<const glm::mat4> skinning() const { return skinning_; }

 private:
  const BoundModel& bound_;
  SweepPoser sweep_poser_;
  std::vector<glm::mat4> world_rest_inverse_, world_pose_, skinning_;
};

}  // namespace sweepd::deform
