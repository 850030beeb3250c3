#include "server/handlers/upload_clip_handler.h"

#include <memory>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "server/handlers/work_size.h"
#include "server/log_event.h"
#include "server/replies/clip_info.h"

namespace sweepd::server {
namespace {

namespace pb = sweepd::protocol;

// On a worker: the clip read into the store, and the reply the I/O thread sends.
RequestSession::Reply add_clip(ConnectionEnvironment& environment,
                               std::shared_ptr<const ClipUpload> upload,
                               std::shared_ptr<const WorkReservation> reserved,
                               std::uint64_t request_id) {
  std::variant<ClipHandle, RequestError> outcome =
      environment.clips.add(*upload, environment.models);
  // (1.12) Played on the model the client names: what that leaves unmapped is said now, and
  // the player built for it serves the frames asked for next.
  std::vector<std::string> model_warnings;
  if (const ClipHandle* clip = std::get_if<ClipHandle>(&outcome); clip && upload->model_id)
    model_warnings = warnings_on_model(**clip, environment.models, *upload->model_id);
  reserved.reset();  // read: the held clip counts against --max-clip-bytes from here on
  return [outcome = std::move(outcome), model_warnings = std::move(model_warnings),
          request_id](RequestSession& session) {
    if (const RequestError* error = std::get_if<RequestError>(&outcome)) {
      log_event("clip_upload_failed",
                {{"connection", session.connection_id()}, {"reason", error->message}});
      session.send_error(*error, request_id);
      return;
    }
    const ClipHandle& clip = std::get<ClipHandle>(outcome);
    log_event("clip_uploaded", {{"connection", session.connection_id()},
                                {"clip", clip->id()},
                                {"name", clip->name()},
                                {"frames", clip->clip().frame_count},
                                {"model_warnings", model_warnings.size()}});
    flatbuffers::FlatBufferBuilder builder = session.take_builder();
    build_clip_info(builder, *clip, request_id, model_warnings);
    session.send(std::move(builder));
  };
}

}  // namespace

void handle_upload_clip(const pb::Message& message, RequestSession& session) {
  const std::uint64_t request_id = message.request_id();
  // The fields live in the reader's storage, reused by the next frame: copied for the worker.
  auto upload =
      std::make_shared<const ClipUpload>(ClipUpload::of_message(*message.body_as_UploadClip()));
  const std::uint64_t upload_bytes =
      upload->gltf.empty() ? upload->bvh.size() : upload->gltf.size();
  // The clip is decoded on a worker: its copy and its frames, reserved from the work budget.
  auto reserved = session.environment().work_budget.reserve(
      session.connection_id(), upload_bytes + clip_upload_work_bytes(upload_bytes));
  if (const WorkRefusal* refusal = std::get_if<WorkRefusal>(&reserved)) {
    session.send_error(
        work_refused("clip upload '" + upload->name + "'", *refusal, "upload a shorter clip"),
        request_id);
    return;
  }
  log_event("clip_upload_start", {{"connection", session.connection_id()},
                                  {"name", upload->name},
                                  {"format", upload->range_of_motion ? "range_of_motion"
                                             : upload->gltf.empty()  ? "bvh"
                                                                     : "gltf"},
                                  {"upload_bytes", upload_bytes}});
  session.run_in_order(
      RequestSession::Pool::kWorkers,
      [environment = &session.environment(), upload,
       reserved = std::get<std::shared_ptr<const WorkReservation>>(std::move(reserved)),
       request_id]() mutable {
        return add_clip(*environment, upload, std::move(reserved), request_id);
      });
}

}  // namespace sweepd::server
