// ContactSheetService: the answer to ContactSheetRequest (protocol 1.11) — `sweepctl sheet`'s
// grid (gpu/sheet/contact_sheet.h: a row per clip frame, a column per method, captioned with the
// worst edge stretch) of a held model and an uploaded clip, as one PNG for farm users who hold
// neither the model nor a GPU. The same code as the command, so the server's picture equals
// `sweepctl sheet`'s of the same model, clip and options pixel for pixel on the same renderer.
//
// read_contact_sheet_request(models, clips, request): the SheetWork, or the RequestError to
//   answer: UnknownModel, UnknownClip (upload it again), InvalidArgument naming the field — no
//   frames or more than ContactSheet::kMostRows, a frame past the clip's end, no methods, more
//   than kMostSheetColumns or an unknown one, a cell side outside 64..2048, a picture over
//   kMostSheetPixels, an unknown focus or one the model lacks, a heat scale that is not a
//   positive number, an angle out of range, a clip that cannot drive the model.
// render(work, pairs, picture): the deformations on the calling thread (folding's pairs from
//   `pairs`, the daemon's collision backend), each cell's render a job on the GPU thread (shared
//   with position maps and collision: a cell waits behind their jobs only), the picture
//   PNG-encoded into picture.png. Throws PositionMapUnavailable when renders are off or no EGL
//   context can be made (PositionMapService::worker), std::invalid_argument for a pose the clip
//   cannot give.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "gpu/sheet/contact_sheet.h"
#include "protocol/sweepd_generated.h"
#include "server/handlers/request_error.h"
#include "server/models/clip_store.h"
#include "server/models/model_lookup.h"
#include "server/services/position_map_service.h"

namespace sweepd::gpu {
class PreviewRenderer;
}  // namespace sweepd::gpu

namespace sweepd::server {

inline constexpr std::size_t kMostSheetColumns = 8;  // every method, and some twice
inline constexpr std::uint64_t kMostSheetPixels = 4096ull * 4096ull;  // 64 MiB of RGBA

struct SheetWork {
  ModelHandle model;
  std::shared_ptr<const motion::ClipPoses> clip;
  sheet::SheetOptions options;
  // The held model posed as the clip's frames (motion::sample_clip, as PoseFromClip plays them).
  sheet::SheetModel sheet_model() const;
};

std::variant<SheetWork, RequestError> read_contact_sheet_request(
    const ModelLookup& models, const ClipStore& clips,
    const protocol::ContactSheetRequest& request);

class ContactSheetService {
 public:
  // Renders on the position maps' GPU worker (off with them: --position-maps 0); `renders`
  // must outlive this service.
  explicit ContactSheetService(PositionMapService& renders);
  ~ContactSheetService();

  void render(const SheetWork& work, sheet::PairSource* pairs, sheet::SheetPicture& picture);

 private:
  PositionMapService& renders_;
  std::unique_ptr<gpu::PreviewRenderer> renderer_;  // touched only on the worker's thread
};

}  // namespace sweepd::server
