// One deformation of a pose with a method the comparing commands (sweepctl metrics, check and
// sheet, the daemon's ContactSheetRequest) took by name (deform/job/method_choice.h).
//   uses_collision    whether any of the methods folds and protrudes (and so needs a PairSource)
//   PairSource        where folding finds its intersecting pairs: sweepctl's --collision backend
//                     (cli/local_collision.h) or the daemon's (server CollisionPairFinder).
//                     begin() gives the DeformJob's pair finder (empty: the CPU reference);
//                     finish(report) takes the deformation's stage times.
//   deform_with       runs one deform::DeformJob of `pose` with the method into positions
//                     (vertex_count()), no normals (the sheet shades every method by its
//                     surface's: gpu/sheet/contact_sheet.h); folding's pairs from
//                     `pairs` (null: the CPU reference). Returns the context's SweepPoser
//                     posed to the pose: the deformation's own sweep state for sweep methods,
//                     the section planes for LBS/DQS. The context's world_pose() is the pose's.
#pragma once

#include <glm/glm.hpp>
#include <span>

#include "deform/job/deform_job.h"
#include "deform/job/method_choice.h"

namespace sweepd::sheet {

// Folding, protrusion and contact find their pairs in the PairSource.
bool uses_collision(std::span<const deform::MethodChoice> methods);

class PairSource {
 public:
  virtual const deform::DetectPairs& begin() = 0;
  virtual void finish(const deform::FeatureReport& report) = 0;

 protected:
  ~PairSource() = default;
};

const deform::SweepPoser& deform_with(const deform::MethodChoice& m,
                                      const deform::ModelRuntime& runtime,
                                      deform::DeformContext& context, PairSource* pairs,
                                      deform::Pose pose, std::span<glm::vec3> positions);

}  // namespace sweepd::sheet
