#include "cli/local_sheet.h"

#include <span>

namespace sweepd::cli {

LocalSheet::LocalSheet(const PosedModel& posed, const sheet::SheetOptions& options,
                       std::function<deform::Pose(int)> pose)
    : renderer_(context_),
      collision_(sheet::uses_collision(options.methods)
                     ? std::make_unique<LocalCollision>(posed.arguments().collision)
                     : nullptr),
      contact_({posed.bound(), posed.runtime(),
                pose ? std::move(pose)
                     : std::function<deform::Pose(int)>(
                           [&posed](int frame) { return posed.pose(frame); })},
               options, collision_.get(),
               [this](const gpu::PreviewMesh& mesh, const gpu::PreviewOptions& preview,
                      std::span<std::uint8_t> rgba) {
                 context_.make_current();  // a GPU collision backend may have made its own
                 renderer_.render(mesh, preview, rgba);
               }) {}

}  // namespace sweepd::cli
