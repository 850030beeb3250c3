// ModelRuntime: everything a deformation needs of one bound model that never changes after
// binding, built once (when the model is loaded or bound) and shared read-only by every caller
// and thread — ozz-animation's runtime data. The per-frame scratch is DeformContext's
// (deform_context.h); a frame's inputs and outputs are DeformJob's (deform_job.h).
//
// Holds: the BoundModel (by reference: it must outlive the runtime), its key-ellipse edits
//   validated once (angle_driven_key_edits.h; the constructor throws std::invalid_argument
//   "key ellipse edits: <reason>" when they do not fit), the sweep poser's tables (rest sweeps,
//   sample-table layout, vertex kinds, welded-normals topology; sweep_poser_tables.h), I0 of
//   every sweep (rest_sweep_volumes), the collision regions and bone proxies (collision_model.h)
//   the J inverse world rest matrices and the skinning baselines' table (skinning_table.h). All of it is built eagerly in the constructor (on the
//   shared male about 100 ms, most of it the collision regions), so nothing is built lazily
//   and concurrent readers need no lock.
// serial(): unique per runtime in the process; what a DeformContext is keyed to.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <memory>
#include <span>
#include <vector>

#include "deform/baselines/skinning_table.h"
#include "deform/binding/bound_model.h"
#include "deform/edits/angle_driven_key_edits.h"
#include "deform/features/collision_model.h"
#include "deform/posing/sweep_poser_tables.h"

namespace sweepd::deform {

class ModelRuntime {
 public:
  explicit ModelRuntime(const BoundModel& bound, const CollisionRegionOptions& regions = {},
                        const BoneProxyOptions& proxies = {});
  ModelRuntime(const ModelRuntime&) = delete;  // contexts and posers refer into it
  ModelRuntime& operator=(const ModelRuntime&) = delete;

  const BoundModel& bound() const { return bound_; }
  const KeyEllipseEdits& edits() const { return edits_; }
  const std::shared_ptr<const SweepPoserTables>& poser_tables() const { return poser_tables_; }
  const WeldedNormals& welded_normals() const { return *poser_tables_->normals; }
  std::span<const double> rest_volumes() const { return rest_volumes_; }
  const CollisionModel& collision() const { return collision_; }
  std::span<const glm::mat4> world_rest_inverse() const { return world_rest_inverse_; }
  const SkinningTable& skinning_table() const { return skinning_table_; }
  std::uint64_t serial() const { return serial_; }

 private:
  const BoundModel& bound_;
  KeyEllipseEdits edits_;
  std::shared_ptr<const SweepPoserTables> poser_tables_;
  std::vector<double> rest_volumes_;
  CollisionModel collision_;
  std::vector<glm::mat4> world_rest_inverse_;
  SkinningTable skinning_table_;
  std::uint64_t serial_;
};

}  // namespace sweepd::deform
