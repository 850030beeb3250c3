// MethodChoice: the deformation methods that the comparing commands (sweepctl metrics and
// sheet, the daemon's ContactSheetRequest) take by name in their method lists, and one
// deformation of a pose with such a method.
//   methods_by_name   "sweep", "sweep+volume" (volume preservation), "sweep+features" (folding
//                     and protrusion), "sweep+contact" (those and whole-body contact), "lbs",
//                     "dqs"
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
#include <map>
#include <span>
#include <string>

#include "deform/job/deform_job.h"

namespace sweepd::sheet {

struct MethodChoice {
  std::string name;
  deform::DeformMethod method;
  bool preserve_volume;
  bool collision = false;  // folding and protrusion, their pairs from the PairSource
  bool contact = false;    // whole-body contact too (with collision), the same pairs
};

const std::map<std::string, MethodChoice>& methods_by_name();
bool uses_collision(std::span<const MethodChoice> methods);

class PairSource {
 public:
  virtual const deform::DetectPairs& begin() = 0;
  virtual void finish(const deform::FeatureReport& report) = 0;

 protected:
  ~PairSource() = default;
};

const deform::SweepPoser& deform_with(const MethodChoice& m, const deform::ModelRuntime& runtime,
                                      deform::DeformContext& context, PairSource* pairs,
                                      deform::Pose pose, std::span<glm::vec3> positions);

}  // namespace sweepd::sheet
