#include "server/services/contact_sheet_service.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "deform/job/method_choice.h"
#include "gpu/gpu_worker.h"
#include "gpu/preview_renderer.h"
#include "motion/clip_sampling.h"

namespace sweepd::server {
namespace {

// "a, b, c": the names an unknown one is refused with.
std::string comma_separated(const std::vector<std::string>& names) {
  std::string listed;
  for (const std::string& name : names) listed += (listed.empty() ? "" : ", ") + name;
  return listed;
}

RequestError invalid(const std::string& reason) {
  return RequestError{protocol::ErrorCode::InvalidArgument, "contact sheet: " + reason};
}

}  // namespace

std::variant<SheetWork, RequestError> read_contact_sheet_request(
    const ModelLookup& models, const ClipStore& clips,
    const protocol::ContactSheetRequest& request) {
  SheetWork work;
  work.model = models.find(request.model_id());
  if (!work.model)
    return RequestError{protocol::ErrorCode::UnknownModel,
                        "contact sheet: no model with id " + std::to_string(request.model_id()) +
                            " (" + held_models_clause(models) + ")"};
  const std::string clip_id = request.clip_id() ? request.clip_id()->str() : "";
  const ClipHandle clip = clips.find(clip_id);
  if (!clip)
    return RequestError{protocol::ErrorCode::UnknownClip,
                        "contact sheet: no clip with id '" + clip_id + "': upload it (UploadClip)"};
  try {
    work.clip = clip->player(work.model);
  } catch (const std::exception& error) {
    return invalid("clip '" + clip->name() + "' on model " + std::to_string(work.model->id) + ": " +
                   error.what());
  }
  sheet::SheetOptions& options = work.options;

  const std::size_t rows = request.frames() ? request.frames()->size() : 0;
  if (rows == 0 || rows > sheet::ContactSheet::kMostRows)
    return invalid(std::to_string(rows) + " frames: a sheet has 1 to " +
                   std::to_string(sheet::ContactSheet::kMostRows) + " rows");
  const int frame_count = work.clip->frame_count();
  for (const std::uint32_t frame : *request.frames()) {
    if (frame >= static_cast<std::uint32_t>(frame_count))
      return invalid("frame " + std::to_string(frame) + " is past the end of clip '" +
                     clip->name() + "' (" + std::to_string(frame_count) + " frames)");
    options.frames.push_back(static_cast<int>(frame));
  }

  const std::size_t columns = request.methods() ? request.methods()->size() : 0;
  if (columns == 0 || columns > kMostSheetColumns)
    return invalid(std::to_string(columns) + " methods: a sheet has 1 to " +
                   std::to_string(kMostSheetColumns) + " columns");
  for (const flatbuffers::String* name : *request.methods()) {
    try {
      options.methods.push_back(deform::parse_method_choice(name->str()));
    } catch (const std::invalid_argument& unknown) {
      return invalid(unknown.what());
    }
  }

  options.cell_width = request.cell_width();
  options.cell_height = request.cell_height();
  for (const int side : {options.cell_width, options.cell_height})
    if (side < sheet::ContactSheet::kSmallestCell || side > sheet::ContactSheet::kLargestCell)
      return invalid("a cell of " + std::to_string(options.cell_width) + " x " +
                     std::to_string(options.cell_height) + " pixels: each side must be " +
                     std::to_string(sheet::ContactSheet::kSmallestCell) + " to " +
                     std::to_string(sheet::ContactSheet::kLargestCell));
  const std::uint64_t pixels = options.pixel_count();
  if (pixels > kMostSheetPixels)
    return invalid(std::to_string(pixels) + " pixels (" + std::to_string(rows) + " rows x " +
                   std::to_string(columns) + " columns of cells): a sheet has at most " +
                   std::to_string(kMostSheetPixels));

  options.focus = request.focus() ? request.focus()->str() : "";
  if (!options.focus.empty()) {
    const auto& names = sheet::focus_names();
    if (std::find(names.begin(), names.end(), options.focus) == names.end())
      return invalid("unknown focus '" + options.focus + "' (focus: " + comma_separated(names) +
                     ")");
    try {
      sheet::focus_joint(work.model->bound.rig, options.focus);
    } catch (const std::invalid_argument& error) {
      return invalid(error.what());
    }
  }
  options.heat = request.heat();
  options.heat_full_scale = request.heat_full_scale();
  if (!std::isfinite(options.heat_full_scale) || options.heat_full_scale <= 0.0f)
    return invalid("heat_full_scale " + std::to_string(options.heat_full_scale) +
                   " must be a positive number (1 = 100 % stretch)");
  options.azimuth_degrees = request.azimuth_degrees();
  options.elevation_degrees = request.elevation_degrees();
  if (!(std::abs(options.azimuth_degrees) <= 360.0f))
    return invalid("azimuth " + std::to_string(options.azimuth_degrees) +
                   " degrees: it must be -360 to 360");
  if (!(std::abs(options.elevation_degrees) <= 80.0f))
    return invalid("elevation " + std::to_string(options.elevation_degrees) +
                   " degrees: it must be -80 to 80");
  return work;
}

sheet::SheetModel SheetWork::sheet_model() const {
  const motion::ClipPoses& played = *clip;
  return {model->bound, *model->runtime, [&played](int frame) {
            return motion::sample_clip(played, {.frame = static_cast<std::uint32_t>(frame)});
          }};
}

ContactSheetService::ContactSheetService(PositionMapService& renders) : renders_(renders) {}

ContactSheetService::~ContactSheetService() {
  // GL objects go with the context, on the worker's thread, before the worker ends.
  if (renderer_) renders_.worker().submit([this](gpu::Context&) { renderer_.reset(); }).get();
}

void ContactSheetService::render(const SheetWork& work, sheet::PairSource* pairs,
                                 sheet::SheetPicture& picture) {
  gpu::Worker& worker = renders_.worker();
  // renderer_ belongs to the worker's thread and context: made by the first job, used only
  // inside jobs. Each job's references outlive it: we wait for its result.
  const sheet::DrawCell draw = [this, &worker](const gpu::PreviewMesh& mesh,
                                               const gpu::PreviewOptions& options,
                                               std::span<std::uint8_t> rgba) {
    worker
        .submit([&](gpu::Context& context) {
          if (!renderer_) renderer_ = std::make_unique<gpu::PreviewRenderer>(context);
          renderer_->render(mesh, options, rgba);
        })
        .get();
  };
  sheet::ContactSheet contact(work.sheet_model(), work.options, pairs, draw);
  picture = sheet::draw_picture(contact, worker.renderer());
}

}  // namespace sweepd::server
