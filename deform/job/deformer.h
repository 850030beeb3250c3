// Deformer: a pose in, a deformed mesh out — by control sweeps (the paper), or by the model's
// own skin weights with linear blend or dual-quaternion skinning (the baselines every quality
// and speed figure is compared against; clients may choose them too).
//
// deform: validates the pose once (normalize_and_validate: wrong joint count, NaN/Inf, zero
//   quaternions → std::invalid_argument naming the joint; non-unit quaternions normalised in
//   place), runs forward kinematics, then the method. positions/normals: vertex_count() each
//   (normals empty to skip). Nothing is allocated per frame; threads > 1 splits the vertices
//   with bit-identical results.
// DeformOptions (set_options) add to the sweep method: the key-ellipse edits (set_edits), the
//   muscle bulge, and volume preservation (paper §4.2–4.4). Preservation is opt-in per request
//   (preserve_volume); when on, it corrects the parts VolumePreservationOptions name (arms, legs
//   and torso by default), and with fold feedback (VolumePreservationOptions) it deforms up to
//   1 + fold_feedback_iterations times per frame. They do not change LBS or DQS.
// The BoundModel must outlive the deformer.
#pragma once

#include <optional>
#include <span>
#include <string_view>
#include <utility>
#include <vector>

#include "deform/binding/bound_model.h"
#include "deform/edits/angle_driven_key_edits.h"
#include "deform/features/muscle_bulge.h"
#include "deform/model/pose.h"
#include "deform/posing/sweep_poser.h"
#include "deform/volume/part_volume_regions.h"
#include "deform/volume/volume_preservation.h"

namespace sweepd::deform {

enum class DeformMethod { kSweep, kLbs, kDqs };
const char* to_string(DeformMethod method);
std::optional<DeformMethod> parse_deform_method(std::string_view name);  // "sweep", "lbs", "dqs"

struct DeformOptions {
  bool preserve_volume = false;  // §4.4, on the parts `volume` names
  bool muscle_bulge = false;     // §4.3
  bool edits = true;             // §4.2: apply the edits given to set_edits
  VolumePreservationOptions volume;
  MuscleBulgeOptions bulge;
  // I_C per sweep (bound().sweeps.size() values, or empty): volume added outside the sweep
  // integral (folding, protrusion), subtracted from each sweep's preserved target.
  std::vector<double> added_volume;
};

class Deformer {
 public:
  explicit Deformer(const BoundModel& bound);
  Deformer(const Deformer&) = delete;  // the poser's key adjuster points at this deformer
  Deformer& operator=(const Deformer&) = delete;

  void set_options(DeformOptions options) { options_ = std::move(options); }
  const DeformOptions& options() const { return options_; }
  // The edits start as the bound model's own (BoundModel::edits; the constructor validates them
  // and throws like set_edits); set_edits replaces them.
  // Validates (validate in angle_driven_key_edits.h) and keeps the edits; throws
  // std::invalid_argument with the reason when they do not fit the bound model.
  void set_edits(KeyEllipseEdits edits);
  const KeyEllipseEdits& edits() const { return edits_; }
  // What volume preservation did in the last sweep frame (when it was on).
  const VolumePreserver& volume_preserver() const { return volume_preserver_; }
  // Folding feedback of the last sweep frame: per sweep, the I_C it measured (m³), and the
  // number of extra deformations it took.
  std::span<const double> measured_fold_volume() const { return fold_volume_; }
  int fold_feedback_iterations() const { return fold_iterations_; }

  void deform(Pose& pose, DeformMethod method, std::span<glm::vec3> positions,
              std::span<glm::vec3> normals, int threads = 1);

  const BoundModel& bound() const { return bound_; }
  SweepPoser& sweep_poser() { return sweep_poser_; }
  // World joint matrices and skinning matrices of the last pose.
  std::span<const glm::mat4> world_pose() const { return world_pose_; }
  std::span<const glm::mat4> skinning() const { return skinning_; }

 private:
  void deform_preserving_volume(std::span<glm::vec3> positions, std::span<glm::vec3> normals,
                                int threads);

  const BoundModel& bound_;
  SweepPoser sweep_poser_;
  VolumePreserver volume_preserver_;
  DeformOptions options_;
  KeyEllipseEdits edits_;
  std::optional<PartVolumeRegions> regions_;  // built on the first folding feedback
  std::vector<double> rest_region_volume_, fold_volume_, added_volume_;
  int fold_iterations_ = 0;
  std::vector<glm::mat4> world_rest_inverse_, world_pose_, skinning_;
};

}  // namespace sweepd::deform
