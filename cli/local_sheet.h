// LocalSheet: a contact sheet (gpu/sheet/contact_sheet.h) drawn in sweepctl — cells on this
// thread's own EGL context, sweep+features' pairs from --collision's backend — of a PosedModel's
// frames (sweepctl sheet) or of poses from elsewhere (sweepctl check: its range of motion).
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "cli/local_collision.h"
#include "cli/posed_model.h"
#include "gpu/egl_context.h"
#include "gpu/sheet/contact_sheet.h"

namespace sweepd::cli {

class LocalSheet {
 public:
  // pose: the pose of a sheet frame; empty: posed.pose.
  LocalSheet(const PosedModel& posed, const sheet::SheetOptions& options,
             std::function<deform::Pose(int)> pose = {});

  sheet::ContactSheet& contact() { return contact_; }
  sheet::SheetPicture picture() { return sheet::draw_picture(contact_, context_.renderer()); }
  std::string collision_summary() const { return collision_ ? collision_->summary() : ""; }

 private:
  gpu::Context context_;
  gpu::PreviewRenderer renderer_;
  std::unique_ptr<LocalCollision> collision_;
  sheet::ContactSheet contact_;
};

}  // namespace sweepd::cli
